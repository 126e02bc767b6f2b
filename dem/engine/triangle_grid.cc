#include "dem/engine/triangle_grid.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "common/number_text.h"

namespace trackbed::dem {

// ---- TriangleGrid -----------------------------------------------------------------------------

void TriangleGrid::build(const TriangleMesh& mesh, double cell) {
  if (!(cell > 0.0) || !std::isfinite(cell)) {
    throw std::invalid_argument("TriangleGrid::build: cell must be finite and > 0, got " +
                                number_text(cell));
  }
  const std::size_t nt = mesh.triangles.size();
  box_lower_.resize(nt);
  box_upper_.resize(nt);
  Vec3 lower = Vec3::Constant(std::numeric_limits<double>::infinity());
  Vec3 upper = -lower;
  for (std::size_t t = 0; t < nt; ++t) {
    const auto& tri = mesh.triangles[t];
    const Vec3& a = mesh.vertices[tri[0]];
    box_lower_[t] = a.cwiseMin(mesh.vertices[tri[1]]).cwiseMin(mesh.vertices[tri[2]]);
    box_upper_[t] = a.cwiseMax(mesh.vertices[tri[1]]).cwiseMax(mesh.vertices[tri[2]]);
    lower = lower.cwiseMin(box_lower_[t]);
    upper = upper.cwiseMax(box_upper_[t]);
  }
  cell_offsets_.assign(1, 0);
  items_.clear();
  dims_ = {0, 0, 0};
  cell_ = cell;
  if (nt == 0) return;
  origin_ = lower;
  const Vec3 extent = upper - lower;
  while (true) {
    long cells = 1;
    for (int k = 0; k < 3; ++k) {
      dims_[k] = static_cast<int>(std::min(std::floor(extent[k] / cell_) + 1.0, 1e9));
      cells *= dims_[k];
      cells = std::min(cells, kMaxCells + 1);
    }
    if (cells <= kMaxCells) break;
    cell_ *= 1.25;  // coarsen until the grid fits; a few steps at most
  }
  const auto cell_range = [&](std::size_t t, std::array<int, 3>& from, std::array<int, 3>& to) {
    for (int k = 0; k < 3; ++k) {
      from[k] =
          std::clamp(static_cast<int>((box_lower_[t][k] - origin_[k]) / cell_), 0, dims_[k] - 1);
      to[k] =
          std::clamp(static_cast<int>((box_upper_[t][k] - origin_[k]) / cell_), 0, dims_[k] - 1);
    }
  };
  const long n_cells = static_cast<long>(dims_[0]) * dims_[1] * dims_[2];
  std::vector<long> counts(n_cells + 1, 0);
  std::array<int, 3> from, to;
  for (std::size_t t = 0; t < nt; ++t) {
    cell_range(t, from, to);
    for (int z = from[2]; z <= to[2]; ++z)
      for (int y = from[1]; y <= to[1]; ++y)
        for (int x = from[0]; x <= to[0]; ++x)
          ++counts[(static_cast<long>(z) * dims_[1] + y) * dims_[0] + x + 1];
  }
  for (long c = 0; c < n_cells; ++c) counts[c + 1] += counts[c];
  if (counts[n_cells] > std::numeric_limits<int>::max()) {
    throw std::invalid_argument("TriangleGrid::build: cell " + number_text(cell_) +
                                " is too small for triangles this large (over 2^31 entries)");
  }
  cell_offsets_.assign(counts.begin(), counts.end());
  items_.assign(counts[n_cells], -1);
  std::vector<int> fill(cell_offsets_.begin(), cell_offsets_.end() - 1);
  for (std::size_t t = 0; t < nt; ++t) {
    cell_range(t, from, to);
    for (int z = from[2]; z <= to[2]; ++z)
      for (int y = from[1]; y <= to[1]; ++y)
        for (int x = from[0]; x <= to[0]; ++x)
          items_[fill[(static_cast<long>(z) * dims_[1] + y) * dims_[0] + x]++] =
              static_cast<int>(t);
  }
}

void TriangleGrid::query(const Vec3& centre, double radius, std::vector<int>& out) const {
  out.clear();
  if (dims_[0] == 0) return;
  std::array<int, 3> from, to;
  for (int k = 0; k < 3; ++k) {
    const double lo = (centre[k] - radius - origin_[k]) / cell_;
    const double hi = (centre[k] + radius - origin_[k]) / cell_;
    if (!(hi >= 0.0 && lo < dims_[k])) return;  // the sphere's box misses the grid
    from[k] = static_cast<int>(std::max(0.0, std::floor(lo)));
    to[k] = static_cast<int>(std::min(dims_[k] - 1.0, std::floor(hi)));
  }
  const double r2 = radius * radius;
  for (int z = from[2]; z <= to[2]; ++z) {
    for (int y = from[1]; y <= to[1]; ++y) {
      for (int x = from[0]; x <= to[0]; ++x) {
        const long c = (static_cast<long>(z) * dims_[1] + y) * dims_[0] + x;
        for (int i = cell_offsets_[c]; i < cell_offsets_[c + 1]; ++i) {
          const int t = items_[i];
          // Distance from the centre to the triangle's bounding box.
          const Vec3 gap = (box_lower_[t] - centre).cwiseMax(centre - box_upper_[t]).cwiseMax(0.0);
          if (gap.squaredNorm() <= r2) out.push_back(t);
        }
      }
    }
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
}

}  // namespace trackbed::dem
