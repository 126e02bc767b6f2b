#include "dem/samples/convex_hull.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

#include "common/input_error.h"

namespace trackbed::dem {
namespace {

// Points are rounded to integers in [0, 2^17] along every axis. Differences are then below 2^18,
// cross products below 2^37 and orientation determinants below 3 * 2^55, so every orientation
// test is exact in int64 and the incremental hull's topology is never decided by rounding.
constexpr int kGridBits = 17;

using IVec = std::array<std::int64_t, 3>;

IVec minus(const IVec& a, const IVec& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}

IVec cross(const IVec& a, const IVec& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

std::int64_t dot(const IVec& a, const IVec& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

double norm(const IVec& a) {
  return std::sqrt(static_cast<double>(a[0]) * a[0] + static_cast<double>(a[1]) * a[1] +
                   static_cast<double>(a[2]) * a[2]);
}

// Positive when d lies on the side of plane (a, b, c) that (b - a) x (c - a) points to.
std::int64_t orientation(const IVec& a, const IVec& b, const IVec& c, const IVec& d) {
  return dot(cross(minus(b, a), minus(c, a)), minus(d, a));
}

using Triangle = std::array<int, 3>;

InputError no_volume(std::size_t n_points, double tolerance) {
  std::ostringstream msg;
  msg << "convex hull: the " << n_points << " points span no volume (all within " << tolerance
      << " of one plane); a hull needs at least 4 points that are not in one plane";
  return InputError(msg.str());
}

// Incremental hull (beneath-beyond) of the points `ids` of `p`: triangles counter-clockwise seen
// from outside. A point is inserted only if it lies more than `tol` outside the current hull;
// the faces it replaces are those it sees strictly (exact test), so coplanar points cannot
// make the visible region anything but a disk bounded by one horizon cycle.
std::vector<Triangle> incremental_hull(const std::vector<IVec>& p, const std::vector<int>& ids,
                                       double tol, double tolerance_in_metres) {
  // Initial tetrahedron: the first point, the one farthest from it, the one farthest from
  // their line, the one farthest from their plane.
  const int i0 = ids[0];
  int i1 = -1, i2 = -1, i3 = -1;
  double best = 0.0;
  for (int i : ids) {
    const double d = norm(minus(p[i], p[i0]));
    if (d > best) best = d, i1 = i;
  }
  if (!(best > tol)) throw no_volume(ids.size(), tolerance_in_metres);
  const IVec axis = minus(p[i1], p[i0]);
  best = 0.0;
  for (int i : ids) {
    const double d = norm(cross(axis, minus(p[i], p[i0]))) / norm(axis);
    if (d > best) best = d, i2 = i;
  }
  if (!(best > tol)) throw no_volume(ids.size(), tolerance_in_metres);
  const IVec normal = cross(axis, minus(p[i2], p[i0]));
  best = 0.0;
  for (int i : ids) {
    const double d = std::abs(static_cast<double>(dot(normal, minus(p[i], p[i0])))) / norm(normal);
    if (d > best) best = d, i3 = i;
  }
  if (!(best > tol)) throw no_volume(ids.size(), tolerance_in_metres);
  if (orientation(p[i0], p[i1], p[i2], p[i3]) > 0) std::swap(i1, i2);  // i3 behind (i0, i1, i2)
  std::vector<Triangle> faces = {{i0, i1, i2}, {i0, i3, i1}, {i1, i3, i2}, {i2, i3, i0}};
  std::vector<bool> alive(faces.size(), true);

  for (int q : ids) {
    if (q == i0 || q == i1 || q == i2 || q == i3) continue;
    std::vector<int> visible;
    double farthest = 0.0;
    for (std::size_t f = 0; f < faces.size(); ++f) {
      if (!alive[f]) continue;
      const Triangle& t = faces[f];
      const std::int64_t o = orientation(p[t[0]], p[t[1]], p[t[2]], p[q]);
      if (o <= 0) continue;
      visible.push_back(static_cast<int>(f));
      const double n = norm(cross(minus(p[t[1]], p[t[0]]), minus(p[t[2]], p[t[0]])));
      farthest = std::max(farthest, static_cast<double>(o) / n);
    }
    if (!(farthest > tol)) continue;  // inside, or on the hull at the tolerance
    std::set<std::pair<int, int>> visible_edges;
    for (int f : visible) {
      for (int k = 0; k < 3; ++k) visible_edges.emplace(faces[f][k], faces[f][(k + 1) % 3]);
    }
    for (int f : visible) alive[f] = false;
    // Horizon: edges of the visible region whose other face is not visible; the new face keeps
    // the edge's direction, so it is oriented like its hidden neighbour.
    for (const auto& [a, b] : visible_edges) {
      if (visible_edges.count({b, a}) == 0) {
        faces.push_back({a, b, q});
        alive.push_back(true);
      }
    }
  }
  std::vector<Triangle> out;
  for (std::size_t f = 0; f < faces.size(); ++f) {
    if (alive[f]) out.push_back(faces[f]);
  }
  return out;
}

// A vertex of a triangle thinner than tol (its smallest height, twice the area over the longest
// edge), namely the one opposite the longest edge: it lies within tol of that edge, so dropping it
// moves the hull by less than tol. -1 if there is none.
int sliver_vertex(const std::vector<IVec>& p, const std::vector<Triangle>& triangles, double tol) {
  for (const Triangle& t : triangles) {
    double longest = 0.0;
    int opposite = -1;
    for (int k = 0; k < 3; ++k) {
      const double length = norm(minus(p[t[(k + 1) % 3]], p[t[k]]));
      if (length > longest) longest = length, opposite = t[(k + 2) % 3];
    }
    const double twice_area = norm(cross(minus(p[t[1]], p[t[0]]), minus(p[t[2]], p[t[0]])));
    if (!(twice_area > tol * longest)) return opposite;
  }
  return -1;
}

}  // namespace

TriangleMesh convex_hull(const std::vector<Vec3>& points) {
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!points[i].allFinite()) {
      throw InputError("convex hull: point " + std::to_string(i) +
                       " has a non-finite coordinate; coordinates must be finite numbers");
    }
  }
  if (points.size() < 4) throw no_volume(points.size(), 0.0);
  Vec3 lower = points[0], upper = points[0];
  for (const Vec3& v : points) {
    lower = lower.cwiseMin(v);
    upper = upper.cwiseMax(v);
  }
  const double extent = (upper - lower).maxCoeff();
  const double tolerance = kConvexHullTolerance * (upper - lower).norm();
  if (!(extent > 0.0)) throw no_volume(points.size(), tolerance);
  const double unit = extent / static_cast<double>(1 << kGridBits);
  const double tol = tolerance / unit;  // in grid units, 1.3 to 2.3 of them

  // Round to the grid and drop points within the tolerance of an earlier one.
  std::vector<IVec> grid;
  std::vector<int> ids;
  for (const Vec3& v : points) {
    const Vec3 g = ((v - lower) / unit).array().round();
    const IVec q = {static_cast<std::int64_t>(g.x()), static_cast<std::int64_t>(g.y()),
                    static_cast<std::int64_t>(g.z())};
    const bool repeated =
        std::any_of(ids.begin(), ids.end(), [&](int i) { return norm(minus(grid[i], q)) <= tol; });
    if (!repeated) ids.push_back(static_cast<int>(grid.size()));
    grid.push_back(q);
  }

  std::vector<Triangle> triangles;
  while (true) {
    triangles = incremental_hull(grid, ids, tol, tolerance);
    const int drop = sliver_vertex(grid, triangles, tol);
    if (drop < 0) break;
    ids.erase(std::find(ids.begin(), ids.end(), drop));
  }

  TriangleMesh mesh;
  std::vector<int> vertex_of(grid.size(), -1);
  for (Triangle& t : triangles) {
    for (int& v : t) {
      if (vertex_of[v] < 0) {
        vertex_of[v] = static_cast<int>(mesh.vertices.size());
        mesh.vertices.push_back(lower + unit * Vec3(static_cast<double>(grid[v][0]),
                                                    static_cast<double>(grid[v][1]),
                                                    static_cast<double>(grid[v][2])));
      }
      v = vertex_of[v];
    }
    mesh.triangles.push_back(t);
  }
  mesh.part_names = {"hull"};
  mesh.finalize();
  if (!mesh.is_closed()) throw std::logic_error("convex_hull: the hull is not a closed surface");
  return mesh;
}

}  // namespace trackbed::dem
