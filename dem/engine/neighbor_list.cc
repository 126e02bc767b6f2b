#include "dem/engine/neighbor_list.h"

#include <omp.h>

#include <algorithm>
#include <cmath>

#include "dem/engine/work_split.h"

namespace trackbed::dem {

void CellGrid::build(const std::vector<Vec3>& points, double min_cell) {
  const int n = static_cast<int>(points.size());
  Vec3 lo = Vec3::Constant(0), hi = Vec3::Constant(0);
  if (n > 0) {
    lo = hi = points[0];
    for (const auto& x : points) {
      lo = lo.cwiseMin(x);
      hi = hi.cwiseMax(x);
    }
  }
  // A sparse cloud spread over a large box must not allocate a huge empty grid: grow the cells
  // until there are at most ~2 cells per point.
  double cell = min_cell;
  const Vec3 extent = (hi - lo).cwiseMax(min_cell);
  auto count = [&](double h) {
    return std::ceil(extent.x() / h) * std::ceil(extent.y() / h) * std::ceil(extent.z() / h);
  };
  while (count(cell) > 2.0 * std::max(n, 64)) cell *= 1.26;
  lower_ = lo;
  inv_cell_ = 1.0 / cell;
  nx_ = static_cast<int>(std::ceil(extent.x() / cell)) + 1;
  ny_ = static_cast<int>(std::ceil(extent.y() / cell)) + 1;
  nz_ = static_cast<int>(std::ceil(extent.z() / cell)) + 1;

  const int ncell = nx_ * ny_ * nz_;
  std::vector<int> cell_of_point(n);
  start_.assign(ncell + 1, 0);
  for (int i = 0; i < n; ++i) {
    int ix, iy, iz;
    cell_of(points[i], ix, iy, iz);
    cell_of_point[i] = index(ix, iy, iz);
    ++start_[cell_of_point[i] + 1];
  }
  for (int c = 0; c < ncell; ++c) start_[c + 1] += start_[c];
  sorted_.resize(n);
  std::vector<int> fill(start_.begin(), start_.end() - 1);
  for (int i = 0; i < n; ++i) sorted_[fill[cell_of_point[i]]++] = i;
}

void CellGrid::cell_of(const Vec3& x, int& ix, int& iy, int& iz) const {
  auto clampi = [](double v, int n) { return std::min(std::max(static_cast<int>(v), 0), n - 1); };
  ix = clampi((x.x() - lower_.x()) * inv_cell_, nx_);
  iy = clampi((x.y() - lower_.y()) * inv_cell_, ny_);
  iz = clampi((x.z() - lower_.z()) * inv_cell_, nz_);
}

void NeighborList::build(const Particles& p, double skin, bool parallel) {
  const int n = p.num_elements();
  CellGrid grid;
  grid.build(p.pos, 2 * p.max_element_radius() + skin);

  offsets.assign(n + 1, 0);
  const int nthreads = parallel ? omp_get_max_threads() : 1;
  std::vector<std::vector<int>> chunk(nthreads);

#pragma omp parallel if (parallel)
  {
    // Static contiguous chunks of i: concatenating the chunks in thread order gives CSR by i.
    std::vector<int>& mine = chunk[omp_get_thread_num()];
    mine.clear();
#pragma omp for schedule(static)
    for (int i = 0; i < n; ++i) {
      const Vec3 xi = p.pos[i];
      const double ri = p.radius[i];
      const int bi = p.body[i];
      int cx, cy, cz;
      grid.cell_of(xi, cx, cy, cz);
      const std::size_t first = mine.size();
      for (int iz = std::max(cz - 1, 0); iz <= std::min(cz + 1, grid.nz() - 1); ++iz)
        for (int iy = std::max(cy - 1, 0); iy <= std::min(cy + 1, grid.ny() - 1); ++iy)
          for (int ix = std::max(cx - 1, 0); ix <= std::min(cx + 1, grid.nx() - 1); ++ix) {
            const int c = grid.index(ix, iy, iz);
            for (const int* it = grid.begin(c); it != grid.end(c); ++it) {
              const int j = *it;
              if (j <= i || p.body[j] == bi) continue;
              const double cut = ri + p.radius[j] + skin;
              if ((p.pos[j] - xi).squaredNorm() < cut * cut) mine.push_back(j);
            }
          }
      std::sort(mine.begin() + first, mine.end());
      offsets[i + 1] = static_cast<int>(mine.size() - first);
    }
  }
  for (int i = 0; i < n; ++i) offsets[i + 1] += offsets[i];
  partners.resize(offsets[n]);
  std::size_t at = 0;
  for (const auto& c : chunk) {
    std::copy(c.begin(), c.end(), partners.begin() + at);
    at += c.size();
  }
}

int NeighborList::find(int i, int j) const {
  const auto b = partners.begin() + offsets[i], e = partners.begin() + offsets[i + 1];
  const auto it = std::lower_bound(b, e, j);
  return (it != e && *it == j) ? static_cast<int>(it - partners.begin()) : -1;
}

std::vector<int> NeighborList::balanced_ranges(const std::vector<Vec3>& pos,
                                               const std::vector<double>& radius, int parts) const {
  const int n = static_cast<int>(offsets.size()) - 1;
  if (parts == 1) return {0, n};
  std::vector<long long> work(n + 1, 0);  // work[i + 1]: row i's, summed below to a prefix
#pragma omp parallel for schedule(static)
  for (int i = 0; i < n; ++i) {
    long long w = 1;  // the row's own cost, for a row without pairs
    for (int k = offsets[i]; k < offsets[i + 1]; ++k) {
      const int j = partners[k];
      const double rsum = radius[i] + radius[j];
      w += (pos[j] - pos[i]).squaredNorm() < rsum * rsum ? kTouchingPairWork : 1;
    }
    work[i + 1] = w;
  }
  for (int i = 0; i < n; ++i) work[i + 1] += work[i];
  return split_by_work(work, parts);
}

}  // namespace trackbed::dem
