#include "dem/engine/triangle_mesh.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <tuple>
#include <unordered_map>

#include "common/number_text.h"

namespace trackbed::dem {

namespace {

// ---- vertex merging -------------------------------------------------------------------------

struct CellKey {
  std::int64_t x, y, z;
  bool operator==(const CellKey& o) const { return x == o.x && y == o.y && z == o.z; }
};

struct CellKeyHash {
  std::size_t operator()(const CellKey& k) const {
    std::uint64_t h = static_cast<std::uint64_t>(k.x) * 0x9E3779B97F4A7C15ull;
    h ^= static_cast<std::uint64_t>(k.y) * 0xC2B2AE3D27D4EB4Full + (h << 6) + (h >> 2);
    h ^= static_cast<std::uint64_t>(k.z) * 0x165667B19E3779F9ull + (h << 6) + (h >> 2);
    return static_cast<std::size_t>(h);
  }
};

// Maps every vertex to the first earlier vertex within tol (a hash grid of cell tol, so only the
// 27 neighbouring cells are searched) and writes the distinct vertices to merged. A vertex is
// compared with representatives only, so the result does not depend on chains of near points.
void merge_close_vertices(const std::vector<Vec3>& vertices, double tol, std::vector<int>& new_id,
                          std::vector<Vec3>& merged) {
  const int n = static_cast<int>(vertices.size());
  new_id.assign(n, -1);
  merged.clear();
  if (!(tol > 0.0)) {  // a zero-size mesh: all its vertices are one point
    if (n > 0) merged.push_back(vertices[0]);
    new_id.assign(n, 0);
    return;
  }
  std::unordered_map<CellKey, std::vector<int>, CellKeyHash> cells;
  cells.reserve(vertices.size());
  const double tol2 = tol * tol;
  for (int i = 0; i < n; ++i) {
    const Vec3& v = vertices[i];
    const CellKey key{static_cast<std::int64_t>(std::floor(v.x() / tol)),
                      static_cast<std::int64_t>(std::floor(v.y() / tol)),
                      static_cast<std::int64_t>(std::floor(v.z() / tol))};
    int found = -1;
    for (int dx = -1; dx <= 1 && found < 0; ++dx) {
      for (int dy = -1; dy <= 1 && found < 0; ++dy) {
        for (int dz = -1; dz <= 1 && found < 0; ++dz) {
          const auto it = cells.find(CellKey{key.x + dx, key.y + dy, key.z + dz});
          if (it == cells.end()) continue;
          for (int rep : it->second) {
            if ((merged[rep] - v).squaredNorm() <= tol2) {
              found = rep;
              break;
            }
          }
        }
      }
    }
    if (found < 0) {
      found = static_cast<int>(merged.size());
      merged.push_back(v);
      cells[key].push_back(found);
    }
    new_id[i] = found;
  }
}

}  // namespace

// ---- TriangleMesh -----------------------------------------------------------------------------

void TriangleMesh::finalize() {
  const std::size_t nt = triangles.size();
  if (triangle_part.empty()) triangle_part.assign(nt, 0);
  if (part_names.empty()) part_names.push_back("mesh");
  if (triangle_part.size() != nt) {
    throw std::invalid_argument("TriangleMesh: triangle_part has " +
                                std::to_string(triangle_part.size()) + " entries for " +
                                std::to_string(nt) + " triangles");
  }
  for (int p : triangle_part) {
    if (p < 0 || p >= static_cast<int>(part_names.size())) {
      throw std::invalid_argument("TriangleMesh: part id " + std::to_string(p) +
                                  " out of range of part_names");
    }
  }
  for (const auto& tri : triangles) {
    for (int v : tri) {
      if (v < 0 || v >= static_cast<int>(vertices.size())) {
        throw std::invalid_argument("TriangleMesh: vertex id " + std::to_string(v) +
                                    " out of range");
      }
    }
  }
  Vec3 lower = Vec3::Constant(std::numeric_limits<double>::infinity());
  Vec3 upper = -lower;
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    if (!vertices[i].allFinite()) {
      throw InputError("mesh vertex " + std::to_string(i) +
                       " has a non-finite coordinate; coordinates must be finite numbers");
    }
    lower = lower.cwiseMin(vertices[i]);
    upper = upper.cwiseMax(vertices[i]);
  }
  const double tol = vertices.empty() ? 0.0 : kMergeTolerance * (upper - lower).norm();

  std::vector<int> new_id;
  std::vector<Vec3> merged;
  merge_close_vertices(vertices, tol, new_id, merged);
  vertices.swap(merged);
  for (auto& tri : triangles) {
    for (int& v : tri) v = new_id[v];
  }

  for (std::size_t t = 0; t < nt; ++t) {
    const Vec3& a = vertices[triangles[t][0]];
    const Vec3& b = vertices[triangles[t][1]];
    const Vec3& c = vertices[triangles[t][2]];
    const double twice_area = (b - a).cross(c - a).norm();
    const double longest =
        std::sqrt(std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()}));
    // The smallest height is twice the area over the longest edge; a triangle thinner than the
    // merging tolerance has a vertex that is, at that tolerance, on the line of the other two.
    if (!(twice_area > tol * longest)) {
      throw DegenerateTriangleError(
          static_cast<int>(t),
          "triangle " + std::to_string(t) + " (part '" + part_names[triangle_part[t]] +
              "') is degenerate: its smallest height " +
              number_text(longest > 0.0 ? twice_area / longest : 0.0) +
              " is not above the vertex-merging tolerance " + number_text(tol) +
              " (1e-6 of the mesh size); every triangle needs three distinct, non-collinear "
              "vertices");
    }
  }

  // Edges: sort the (lower, higher, triangle, slot) of every triangle side; equal keys are one
  // edge.
  std::vector<std::tuple<int, int, int, int>> sides;
  sides.reserve(3 * nt);
  for (std::size_t t = 0; t < nt; ++t) {
    for (int k = 0; k < 3; ++k) {
      const int a = triangles[t][k];
      const int b = triangles[t][(k + 1) % 3];
      sides.emplace_back(std::min(a, b), std::max(a, b), static_cast<int>(t), k);
    }
  }
  std::sort(sides.begin(), sides.end());
  triangle_edges.assign(nt, {-1, -1, -1});
  edge_vertices.clear();
  edge_triangle_offsets.assign(1, 0);
  edge_triangles.clear();
  edge_triangles.reserve(sides.size());
  for (std::size_t i = 0; i < sides.size(); ++i) {
    const auto [a, b, t, k] = sides[i];
    if (i == 0 || std::get<0>(sides[i - 1]) != a || std::get<1>(sides[i - 1]) != b) {
      edge_vertices.push_back({a, b});
      edge_triangle_offsets.push_back(edge_triangle_offsets.back());
    }
    triangle_edges[t][k] = static_cast<int>(edge_vertices.size()) - 1;
    edge_triangles.push_back(t);
    ++edge_triangle_offsets.back();
  }
  num_edges = static_cast<int>(edge_vertices.size());

  vertex_edge_offsets.assign(vertices.size() + 1, 0);
  for (const auto& ev : edge_vertices) {
    ++vertex_edge_offsets[ev[0] + 1];
    ++vertex_edge_offsets[ev[1] + 1];
  }
  for (std::size_t v = 0; v < vertices.size(); ++v) {
    vertex_edge_offsets[v + 1] += vertex_edge_offsets[v];
  }
  vertex_edges.assign(vertex_edge_offsets.back(), -1);
  std::vector<int> fill(vertex_edge_offsets.begin(), vertex_edge_offsets.end() - 1);
  for (int e = 0; e < num_edges; ++e) {
    vertex_edges[fill[edge_vertices[e][0]]++] = e;
    vertex_edges[fill[edge_vertices[e][1]]++] = e;
  }
}

bool TriangleMesh::is_closed() const {
  if (triangle_edges.size() != triangles.size()) {
    throw std::logic_error("TriangleMesh::is_closed: call finalize() first");
  }
  if (triangles.empty()) return false;
  for (int e = 0; e < num_edges; ++e) {
    if (edge_triangle_offsets[e + 1] - edge_triangle_offsets[e] != 2) return false;
    int forward = 0;
    for (int i = edge_triangle_offsets[e]; i < edge_triangle_offsets[e + 1]; ++i) {
      const int t = edge_triangles[i];
      if (triangles[t][local_edge(t, e)] == edge_vertices[e][0]) ++forward;
    }
    if (forward != 1) return false;
  }
  return true;
}

void TriangleMesh::translate(const Vec3& shift) {
  for (Vec3& v : vertices) v += shift;
}

void TriangleMesh::rotate(const Mat3& rotation, const Vec3& about) {
  for (Vec3& v : vertices) v = about + rotation * (v - about);
}

void TriangleMesh::scale(double factor, const Vec3& about) {
  if (!(factor > 0.0) || !std::isfinite(factor)) {
    throw std::invalid_argument("TriangleMesh::scale: factor must be finite and > 0, got " +
                                number_text(factor));
  }
  for (Vec3& v : vertices) v = about + factor * (v - about);
}

Vec3 TriangleMesh::triangle_normal(int triangle) const {
  const auto& tri = triangles[triangle];
  return (vertices[tri[1]] - vertices[tri[0]])
      .cross(vertices[tri[2]] - vertices[tri[0]])
      .normalized();
}

// ---- box ----------------------------------------------------------------------------------------

TriangleMesh make_box_mesh(const Vec3& lower, const Vec3& upper, bool with_part_names,
                           double bottom_width) {
  if (!(lower.array() < upper.array()).all()) {
    throw InputError("box mesh: the lower corner must be below the upper corner in x, y and z");
  }
  if (bottom_width < 0) throw InputError("box mesh: the bottom width must be >= 0");
  const double yc = 0.5 * (lower.y() + upper.y());
  const double hb = bottom_width > 0 ? 0.5 * bottom_width : 0.5 * (upper.y() - lower.y());
  TriangleMesh mesh;
  for (int i = 0; i < 8; ++i) {  // vertex i has x, y, z from bits 0, 1, 2 of i
    const double y = i & 4 ? (i & 2 ? upper.y() : lower.y()) : (i & 2 ? yc + hb : yc - hb);
    mesh.vertices.emplace_back(i & 1 ? upper.x() : lower.x(), y, i & 4 ? upper.z() : lower.z());
  }
  // Counter-clockwise seen from outside; parts: 0 base, 1 top, 2 sides, 3 ends.
  mesh.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                    {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  if (with_part_names) {
    mesh.part_names = {"base", "top", "sides", "ends"};
    mesh.triangle_part = {0, 0, 1, 1, 2, 2, 2, 2, 3, 3, 3, 3};
  } else {
    mesh.part_names = {"box"};
    mesh.triangle_part.assign(12, 0);
  }
  mesh.finalize();
  return mesh;
}

// ---- mass properties --------------------------------------------------------------------------

MeshMassProperties closed_mesh_mass_properties(const TriangleMesh& mesh) {
  if (!mesh.is_closed()) {
    throw InputError(
        "mass properties need a closed mesh: every edge shared by exactly two consistently "
        "oriented triangles");
  }
  // Integrate about the bounding-box centre: coordinates far from the origin would otherwise
  // cancel catastrophically in the second moments.
  Vec3 lower = mesh.vertices[0], upper = mesh.vertices[0];
  for (const Vec3& v : mesh.vertices) {
    lower = lower.cwiseMin(v);
    upper = upper.cwiseMax(v);
  }
  const Vec3 ref = 0.5 * (lower + upper);

  // Eberly (2002): integrals of 1, x, y, z, x^2, y^2, z^2, xy, yz, zx over the solid, each a sum
  // over triangles of the normal component times a cubic polynomial of the vertex coordinates.
  double intg[10] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0};
  struct Sub {
    double f1, f2, f3, g0, g1, g2;
  };
  const auto subexpressions = [](double w0, double w1, double w2) {
    Sub s;
    const double temp0 = w0 + w1;
    s.f1 = temp0 + w2;
    const double temp1 = w0 * w0;
    const double temp2 = temp1 + w1 * temp0;
    s.f2 = temp2 + w2 * s.f1;
    s.f3 = w0 * temp1 + w1 * temp2 + w2 * s.f2;
    s.g0 = s.f2 + w0 * (s.f1 + w0);
    s.g1 = s.f2 + w1 * (s.f1 + w1);
    s.g2 = s.f2 + w2 * (s.f1 + w2);
    return s;
  };
  for (const auto& tri : mesh.triangles) {
    const Vec3 p0 = mesh.vertices[tri[0]] - ref;
    const Vec3 p1 = mesh.vertices[tri[1]] - ref;
    const Vec3 p2 = mesh.vertices[tri[2]] - ref;
    const Vec3 d = (p1 - p0).cross(p2 - p0);
    const Sub x = subexpressions(p0.x(), p1.x(), p2.x());
    const Sub y = subexpressions(p0.y(), p1.y(), p2.y());
    const Sub z = subexpressions(p0.z(), p1.z(), p2.z());
    intg[0] += d.x() * x.f1;
    intg[1] += d.x() * x.f2;
    intg[2] += d.y() * y.f2;
    intg[3] += d.z() * z.f2;
    intg[4] += d.x() * x.f3;
    intg[5] += d.y() * y.f3;
    intg[6] += d.z() * z.f3;
    intg[7] += d.x() * (p0.y() * x.g0 + p1.y() * x.g1 + p2.y() * x.g2);
    intg[8] += d.y() * (p0.z() * y.g0 + p1.z() * y.g1 + p2.z() * y.g2);
    intg[9] += d.z() * (p0.x() * z.g0 + p1.x() * z.g1 + p2.x() * z.g2);
  }
  const double mult[10] = {1.0 / 6,  1.0 / 24, 1.0 / 24,  1.0 / 24,  1.0 / 60,
                           1.0 / 60, 1.0 / 60, 1.0 / 120, 1.0 / 120, 1.0 / 120};
  for (int i = 0; i < 10; ++i) intg[i] *= mult[i];

  const double volume = intg[0];
  if (!(volume > 0.0)) {
    throw InputError(
        "mass properties: the closed mesh encloses volume " + number_text(volume) +
        "; its triangles must be counter-clockwise seen from outside (outward normals)");
  }
  const Vec3 c(intg[1] / volume, intg[2] / volume, intg[3] / volume);
  Mat3 inertia;
  inertia(0, 0) = intg[5] + intg[6] - volume * (c.y() * c.y() + c.z() * c.z());
  inertia(1, 1) = intg[4] + intg[6] - volume * (c.z() * c.z() + c.x() * c.x());
  inertia(2, 2) = intg[4] + intg[5] - volume * (c.x() * c.x() + c.y() * c.y());
  inertia(0, 1) = inertia(1, 0) = -(intg[7] - volume * c.x() * c.y());
  inertia(1, 2) = inertia(2, 1) = -(intg[8] - volume * c.y() * c.z());
  inertia(0, 2) = inertia(2, 0) = -(intg[9] - volume * c.z() * c.x());
  return {volume, ref + c, inertia};
}

}  // namespace trackbed::dem
