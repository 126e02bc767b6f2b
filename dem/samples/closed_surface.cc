#include "dem/samples/closed_surface.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <sstream>
#include <stdexcept>

#include <Eigen/Eigenvalues>

#include "common/input_error.h"
#include "dem/engine/mesh_contact.h"
#include "dem/io/stl_file.h"

namespace trackbed::dem {
namespace {

using Corners = std::array<Vec3, 3>;

Corners corners(const TriangleMesh& mesh, int t) {
  const auto& tri = mesh.triangles[t];
  return {mesh.vertices[tri[0]], mesh.vertices[tri[1]], mesh.vertices[tri[2]]};
}

std::string point_text(const Vec3& p) {
  std::ostringstream s;
  s.precision(6);
  s << "(" << p.x() << ", " << p.y() << ", " << p.z() << ")";
  return s.str();
}

// ---- closedness ---------------------------------------------------------------------------------

void check_closed(const TriangleMesh& mesh, const std::string& what) {
  if (mesh.is_closed()) return;
  int open = 0, non_manifold = 0, misoriented = 0, first = -1;
  for (int e = 0; e < mesh.num_edges; ++e) {
    const int n = mesh.edge_triangle_offsets[e + 1] - mesh.edge_triangle_offsets[e];
    bool bad = true;
    if (n == 1) {
      ++open;
    } else if (n > 2) {
      ++non_manifold;
    } else {
      // Two triangles: they must traverse the edge in opposite directions.
      int forward = 0;
      for (int i = mesh.edge_triangle_offsets[e]; i < mesh.edge_triangle_offsets[e + 1]; ++i) {
        const auto& tri = mesh.triangles[mesh.edge_triangles[i]];
        for (int k = 0; k < 3; ++k) {
          if (tri[k] == mesh.edge_vertices[e][0] && tri[(k + 1) % 3] == mesh.edge_vertices[e][1])
            ++forward;
        }
      }
      bad = forward != 1;
      if (bad) ++misoriented;
    }
    if (bad && first < 0) first = e;
  }
  std::ostringstream msg;
  msg << what << ": the surface is not closed: " << open << " edges with one triangle (holes), "
      << non_manifold << " with more than two, " << misoriented
      << " between triangles of opposite orientation";
  if (first >= 0) {
    const Vec3 mid = 0.5 * (mesh.vertices[mesh.edge_vertices[first][0]] +
                            mesh.vertices[mesh.edge_vertices[first][1]]);
    msg << ", the first at " << point_text(mid);
  }
  msg << "; a stone surface must be watertight, every edge shared by exactly two triangles that "
         "traverse it in opposite directions";
  throw InputError(msg.str());
}

// ---- self-intersection (Moeller 1997) -----------------------------------------------------------

// Signed distances of `a` from the plane through `origin` with unit normal `n`, those within eps
// set to zero; true if all three are strictly on one side (the plane separates the triangles).
bool plane_separates(const Corners& a, const Vec3& n, const Vec3& origin, double eps,
                     std::array<double, 3>& d) {
  for (int k = 0; k < 3; ++k) {
    d[k] = n.dot(a[k] - origin);
    if (std::abs(d[k]) <= eps) d[k] = 0.0;
  }
  return (d[0] > 0 && d[1] > 0 && d[2] > 0) || (d[0] < 0 && d[1] < 0 && d[2] < 0);
}

// The interval, along `direction`, of the segment where triangle `a` meets the other plane (its
// vertices on the plane and its edges that cross it).
void crossing_interval(const Corners& a, const std::array<double, 3>& d, const Vec3& direction,
                       double& lo, double& hi) {
  lo = std::numeric_limits<double>::infinity();
  hi = -lo;
  for (int k = 0; k < 3; ++k) {
    const int j = (k + 1) % 3;
    if (d[k] == 0.0) {
      lo = std::min(lo, direction.dot(a[k]));
      hi = std::max(hi, direction.dot(a[k]));
    }
    if (d[k] * d[j] < 0.0) {
      const double t = direction.dot(a[k] + (a[j] - a[k]) * (d[k] / (d[k] - d[j])));
      lo = std::min(lo, t);
      hi = std::max(hi, t);
    }
  }
}

using Vec2 = Eigen::Vector2d;

double orient2(const Vec2& p, const Vec2& q, const Vec2& r) {
  const Vec2 u = q - p, v = r - p;
  return u.x() * v.y() - u.y() * v.x();
}

bool segments_meet(const Vec2& p1, const Vec2& p2, const Vec2& q1, const Vec2& q2, double eps) {
  const auto snap = [eps](double x) { return std::abs(x) <= eps ? 0.0 : x; };
  const double d1 = snap(orient2(q1, q2, p1)), d2 = snap(orient2(q1, q2, p2));
  const double d3 = snap(orient2(p1, p2, q1)), d4 = snap(orient2(p1, p2, q2));
  if (d1 * d2 > 0.0 || d3 * d4 > 0.0) return false;
  if (d1 == 0.0 && d2 == 0.0) {  // collinear: do the projections on the line overlap?
    const Vec2 dir = p2 - p1;
    const double a = 0.0, b = dir.squaredNorm();
    const double c = dir.dot(q1 - p1), e = dir.dot(q2 - p1);
    return std::max(a, std::min(c, e)) <= std::min(b, std::max(c, e));
  }
  return true;
}

bool inside_triangle(const Vec2& p, const std::array<Vec2, 3>& t, double eps) {
  const double a = orient2(t[0], t[1], p), b = orient2(t[1], t[2], p), c = orient2(t[2], t[0], p);
  return (a >= -eps && b >= -eps && c >= -eps) || (a <= eps && b <= eps && c <= eps);
}

bool coplanar_triangles_meet(const Corners& a, const Corners& b, const Vec3& n, double eps_area) {
  Eigen::Index drop = 0;
  n.cwiseAbs().maxCoeff(&drop);
  const int u = (drop + 1) % 3, v = (drop + 2) % 3;
  std::array<Vec2, 3> pa, pb;
  for (int k = 0; k < 3; ++k) {
    pa[k] = Vec2(a[k][u], a[k][v]);
    pb[k] = Vec2(b[k][u], b[k][v]);
  }
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      if (segments_meet(pa[i], pa[(i + 1) % 3], pb[j], pb[(j + 1) % 3], eps_area)) return true;
    }
  }
  return inside_triangle(pa[0], pb, eps_area) || inside_triangle(pb[0], pa, eps_area);
}

// Whether two non-degenerate triangles touch or cross, distances below eps counting as zero:
// each must meet the other's plane, and the two segments where they meet the line common to
// both planes must overlap (Moeller 1997); coplanar triangles are tested in their plane.
bool triangles_meet(const Corners& a, const Corners& b, double eps) {
  const Vec3 nb = (b[1] - b[0]).cross(b[2] - b[0]).normalized();
  std::array<double, 3> da, db;
  if (plane_separates(a, nb, b[0], eps, da)) return false;
  const Vec3 na = (a[1] - a[0]).cross(a[2] - a[0]).normalized();
  if (plane_separates(b, na, a[0], eps, db)) return false;
  if (da[0] == 0.0 && da[1] == 0.0 && da[2] == 0.0) {
    const double size = std::max((a[1] - a[0]).norm(), (b[1] - b[0]).norm());
    return coplanar_triangles_meet(a, b, nb, eps * size);
  }
  const Vec3 line = na.cross(nb).normalized();  // lengths along it compare with eps
  double lo_a, hi_a, lo_b, hi_b;
  crossing_interval(a, da, line, lo_a, hi_a);
  crossing_interval(b, db, line, lo_b, hi_b);
  return std::max(lo_a, lo_b) <= std::min(hi_a, hi_b) + eps;
}

bool share_vertex(const std::array<int, 3>& s, const std::array<int, 3>& t) {
  for (int a : s) {
    for (int b : t) {
      if (a == b) return true;
    }
  }
  return false;
}

void check_no_self_intersection(const TriangleMesh& mesh, const std::string& what) {
  const int nt = static_cast<int>(mesh.triangles.size());
  Vec3 lower = mesh.vertices[0], upper = mesh.vertices[0];
  for (const Vec3& v : mesh.vertices) {
    lower = lower.cwiseMin(v);
    upper = upper.cwiseMax(v);
  }
  // Far below the merging tolerance (1e-6 of the size) that separates distinct vertices, far
  // above rounding: two triangles closer than this touch.
  const double eps = 1e-9 * (upper - lower).norm();
  std::vector<Vec3> box_lower(nt), box_upper(nt);
  double mean_size = 0.0;
  for (int t = 0; t < nt; ++t) {
    const Corners c = corners(mesh, t);
    box_lower[t] = c[0].cwiseMin(c[1]).cwiseMin(c[2]);
    box_upper[t] = c[0].cwiseMax(c[1]).cwiseMax(c[2]);
    mean_size += (box_upper[t] - box_lower[t]).maxCoeff() / nt;
  }
  // A cell of twice the typical triangle holds a few triangles: the pairs tested are then the
  // near ones only, O(n) of them.
  TriangleGrid grid;
  grid.build(mesh, 2.0 * mean_size);
  std::vector<int> near;
  for (int t = 0; t < nt; ++t) {
    const Vec3 centre = 0.5 * (box_lower[t] + box_upper[t]);
    grid.query(centre, 0.5 * (box_upper[t] - box_lower[t]).norm() + eps, near);
    const Corners a = corners(mesh, t);
    for (int u : near) {
      if (u <= t || share_vertex(mesh.triangles[t], mesh.triangles[u])) continue;
      const bool boxes_overlap = (box_lower[u].array() <= box_upper[t].array() + eps).all() &&
                                 (box_lower[t].array() <= box_upper[u].array() + eps).all();
      if (!boxes_overlap || !triangles_meet(a, corners(mesh, u), eps)) continue;
      throw InputError(what + ": the surface intersects itself: triangles " + std::to_string(t) +
                       " and " + std::to_string(u) + " (near " +
                       point_text((a[0] + a[1] + a[2]) / 3.0) +
                       ") touch or cross; a stone surface must bound one solid without touching "
                       "itself");
    }
  }
}

}  // namespace

void check_closed_surface(const TriangleMesh& mesh, const std::string& what) {
  if (mesh.triangle_edges.size() != mesh.triangles.size()) {
    throw std::logic_error("check_closed_surface: call TriangleMesh::finalize() first");
  }
  check_closed(mesh, what);
  try {
    closed_mesh_mass_properties(mesh);  // refuses a negative (inward) volume
  } catch (const InputError& e) {
    throw InputError(what + ": " + e.what());
  }
  check_no_self_intersection(mesh, what);
}

TriangleMesh read_closed_surface(const std::string& stl_path) {
  TriangleMesh mesh = read_stl(stl_path);
  check_closed_surface(mesh, stl_path);
  return mesh;
}

MassProperties surface_mass_properties(const TriangleMesh& closed_surface) {
  const MeshMassProperties m = closed_mesh_mass_properties(closed_surface);
  MassProperties mp;
  mp.volume = m.volume;
  mp.centroid = m.centroid;
  mp.inertia = 0.5 * (m.inertia + m.inertia.transpose());
  // The convention of sphere_union_mass_properties (docs/clumps.md, "Principal frame"), so that
  // both mass sources give the same frame for the same shape.
  set_principal_frame(mp);
  return mp;
}

// ---- SignedDistance -----------------------------------------------------------------------------

SignedDistance::SignedDistance(const TriangleMesh& surface) : mesh_(surface) {
  if (mesh_.triangle_edges.size() != mesh_.triangles.size() || !mesh_.is_closed()) {
    throw std::invalid_argument("SignedDistance: the surface must be finalized and closed");
  }
  const int nt = static_cast<int>(mesh_.triangles.size());
  face_normals_.resize(nt);
  edge_normals_.assign(mesh_.num_edges, Vec3::Zero());
  vertex_normals_.assign(mesh_.vertices.size(), Vec3::Zero());
  for (int t = 0; t < nt; ++t) {
    const Vec3 n = mesh_.triangle_normal(t);
    face_normals_[t] = n;
    const Corners c = corners(mesh_, t);
    for (int k = 0; k < 3; ++k) {
      edge_normals_[mesh_.triangle_edges[t][k]] += n;
      const Vec3 u = c[(k + 1) % 3] - c[k], v = c[(k + 2) % 3] - c[k];
      const double angle = std::atan2(u.cross(v).norm(), u.dot(v));
      vertex_normals_[mesh_.triangles[t][k]] += angle * n;
    }
  }
  order_.resize(nt);
  std::iota(order_.begin(), order_.end(), 0);
  nodes_.reserve(2 * nt);
  build(0, nt);
}

int SignedDistance::build(int first, int count) {
  const int id = static_cast<int>(nodes_.size());
  nodes_.push_back({Vec3::Zero(), Vec3::Zero(), 0, 0, -1, -1});  // filled in below
  Vec3 lower = Vec3::Constant(std::numeric_limits<double>::infinity()), upper = -lower;
  Vec3 c_lower = lower, c_upper = upper;  // bounds of the triangle centroids
  for (int i = first; i < first + count; ++i) {
    const Corners c = corners(mesh_, order_[i]);
    for (const Vec3& v : c) {
      lower = lower.cwiseMin(v);
      upper = upper.cwiseMax(v);
    }
    const Vec3 centroid = (c[0] + c[1] + c[2]) / 3.0;
    c_lower = c_lower.cwiseMin(centroid);
    c_upper = c_upper.cwiseMax(centroid);
  }
  constexpr int kLeafSize = 4;
  if (count <= kLeafSize) {
    nodes_[id] = {lower, upper, first, count, -1, -1};
    return id;
  }
  Eigen::Index axis = 0;
  (c_upper - c_lower).maxCoeff(&axis);
  const int half = count / 2;
  const auto centroid_coordinate = [&](int t) {
    const auto& tri = mesh_.triangles[t];
    return mesh_.vertices[tri[0]][axis] + mesh_.vertices[tri[1]][axis] +
           mesh_.vertices[tri[2]][axis];
  };
  std::nth_element(order_.begin() + first, order_.begin() + first + half,
                   order_.begin() + first + count,
                   [&](int a, int b) { return centroid_coordinate(a) < centroid_coordinate(b); });
  const int left = build(first, half);
  const int right = build(first + half, count - half);
  nodes_[id] = {lower, upper, first, 0, left, right};
  return id;
}

double SignedDistance::operator()(const Vec3& p) const {
  const auto box_distance2 = [&p](const Node& n) {
    return (n.lower - p).cwiseMax(p - n.upper).cwiseMax(0.0).squaredNorm();
  };
  double best = std::numeric_limits<double>::infinity();
  int best_triangle = -1;
  TriangleClosestPoint closest{Vec3::Zero(), MeshFeature::Face, 0, Vec3::Zero()};
  // A balanced tree over at most 2^31 triangles is under 32 levels deep; each level leaves at
  // most one node on the stack.
  std::array<int, 64> stack;
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = nodes_[stack[--top]];
    if (box_distance2(node) >= best) continue;
    if (node.count > 0) {
      for (int i = node.first; i < node.first + node.count; ++i) {
        const Corners c = corners(mesh_, order_[i]);
        const TriangleClosestPoint q = closest_point_on_triangle(p, c[0], c[1], c[2]);
        const double d2 = (p - q.point).squaredNorm();
        if (d2 < best) best = d2, best_triangle = order_[i], closest = q;
      }
      continue;
    }
    const bool left_first = box_distance2(nodes_[node.left]) <= box_distance2(nodes_[node.right]);
    stack[top++] = left_first ? node.right : node.left;  // the nearer child is visited first
    stack[top++] = left_first ? node.left : node.right;
  }
  const int t = best_triangle;
  const Vec3& normal = closest.feature == MeshFeature::Face
                           ? face_normals_[t]
                           : (closest.feature == MeshFeature::Edge
                                  ? edge_normals_[mesh_.triangle_edges[t][closest.local_id]]
                                  : vertex_normals_[mesh_.triangles[t][closest.local_id]]);
  const double distance = std::sqrt(best);
  return (p - closest.point).dot(normal) < 0.0 ? -distance : distance;
}

}  // namespace trackbed::dem
