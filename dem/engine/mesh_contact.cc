#include "dem/engine/mesh_contact.h"

#include <algorithm>
#include <cmath>

namespace trackbed::dem {

namespace {

// ---- contact predicates ---------------------------------------------------------------------

// Regions are closed and widened by this much (a barycentric weight, or an edge parameter) so
// that rounding, about 1e-16 times (radius + edge) / height, never opens a gap between the
// region of a face and that of its edge or vertex: a point on a shared boundary then belongs to
// both features, and the duplicate is merged by position (kMergeRadius, kMergeEdge).
constexpr double kRegionSlack = 1e-12;
// Two contacts closer than kMergeRadius * radius + kMergeEdge * (longest edges of their
// triangles) are the same contact. This is 100 times the widening above and 1e7 times the
// rounding of closest points at coordinates of 100 radii, yet two genuine contacts are only this
// close when the centre lies within 1e-9 radii of a concave crease.
constexpr double kMergeRadius = 1e-9;
constexpr double kMergeEdge = 1e-10;

// Barycentric weight of the vertex opposite local edge k of triangle t at the projection of p
// onto the triangle's plane: positive on the triangle's side of the edge's line.
double opposite_weight(const TriangleMesh& mesh, int t, int k, const Vec3& p) {
  const auto& tri = mesh.triangles[t];
  const Vec3& v0 = mesh.vertices[tri[0]];
  const Vec3 n = (mesh.vertices[tri[1]] - v0).cross(mesh.vertices[tri[2]] - v0);
  const Vec3& a = mesh.vertices[tri[k]];
  const Vec3& b = mesh.vertices[tri[(k + 1) % 3]];
  return (p - a).dot(n.cross(b - a)) / n.squaredNorm();
}

// Parameter of the projection of p onto the line of edge e, 0 at its lower-id vertex, 1 at the
// other. Always computed from the edge alone, so every triangle and vertex sees the same value.
double edge_parameter(const TriangleMesh& mesh, int e, const Vec3& p) {
  const Vec3& lo = mesh.vertices[mesh.edge_vertices[e][0]];
  const Vec3 d = mesh.vertices[mesh.edge_vertices[e][1]] - lo;
  return (p - lo).dot(d) / d.squaredNorm();
}

bool edge_region_contains(const TriangleMesh& mesh, int e, double t, const Vec3& p) {
  if (t < -kRegionSlack || t > 1.0 + kRegionSlack) return false;
  for (int i = mesh.edge_triangle_offsets[e]; i < mesh.edge_triangle_offsets[e + 1]; ++i) {
    const int tri = mesh.edge_triangles[i];
    if (opposite_weight(mesh, tri, mesh.local_edge(tri, e), p) > kRegionSlack) {
      return false;
    }
  }
  return true;
}

bool vertex_region_contains(const TriangleMesh& mesh, int v, const Vec3& p) {
  for (int i = mesh.vertex_edge_offsets[v]; i < mesh.vertex_edge_offsets[v + 1]; ++i) {
    const int e = mesh.vertex_edges[i];
    const double t = edge_parameter(mesh, e, p);
    const bool behind = mesh.edge_vertices[e][0] == v ? t <= kRegionSlack : t >= 1.0 - kRegionSlack;
    if (!behind) return false;
  }
  return true;
}

bool has_feature(const std::vector<MeshContactPoint>& out, MeshFeature feature, int id) {
  for (const MeshContactPoint& c : out) {
    if (c.feature == feature && c.feature_id == id) return true;
  }
  return false;
}

double longest_edge(const TriangleMesh& mesh, int t) {
  const auto& tri = mesh.triangles[t];
  const Vec3& a = mesh.vertices[tri[0]];
  const Vec3& b = mesh.vertices[tri[1]];
  const Vec3& c = mesh.vertices[tri[2]];
  return std::sqrt(std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()}));
}

// Direction from point to centre; at zero distance (centre on the mesh) the outward normal of the
// triangle, the only direction left that is defined.
Vec3 contact_direction(const TriangleMesh& mesh, int t, const Vec3& from_point, double distance) {
  if (distance > 0.0) return from_point / distance;
  return mesh.triangle_normal(t);
}

}  // namespace

// ---- closest point ----------------------------------------------------------------------------

TriangleClosestPoint closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b,
                                               const Vec3& c) {
  const Vec3 ab = b - a;
  const Vec3 ac = c - a;
  const Vec3 ap = p - a;
  const double d1 = ab.dot(ap);
  const double d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return {a, MeshFeature::Vertex, 0, Vec3(1, 0, 0)};

  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp);
  const double d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return {b, MeshFeature::Vertex, 1, Vec3(0, 1, 0)};

  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
    const double v = d1 / (d1 - d3);
    return {a + v * ab, MeshFeature::Edge, 0, Vec3(1 - v, v, 0)};
  }

  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp);
  const double d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return {c, MeshFeature::Vertex, 2, Vec3(0, 0, 1)};

  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
    const double w = d2 / (d2 - d6);
    return {a + w * ac, MeshFeature::Edge, 2, Vec3(1 - w, 0, w)};
  }

  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return {b + w * (c - b), MeshFeature::Edge, 1, Vec3(0, 1 - w, w)};
  }

  const double denom = 1.0 / (va + vb + vc);
  const double v = vb * denom;
  const double w = vc * denom;
  return {a + ab * v + ac * w, MeshFeature::Face, 0, Vec3(1 - v - w, v, w)};
}

// ---- sphere-mesh contacts ---------------------------------------------------------------------

void sphere_mesh_contacts(const TriangleMesh& mesh, const Vec3& centre, double radius,
                          const int* candidate_triangles, int n_candidates,
                          std::vector<MeshContactPoint>& out) {
  out.clear();
  if (mesh.triangle_edges.size() != mesh.triangles.size()) {
    throw std::logic_error("sphere_mesh_contacts: call TriangleMesh::finalize() first");
  }
  const double r2 = radius * radius;
  for (int i = 0; i < n_candidates; ++i) {
    const int t = candidate_triangles[i];
    const auto& tri = mesh.triangles[t];
    const TriangleClosestPoint closest = closest_point_on_triangle(
        centre, mesh.vertices[tri[0]], mesh.vertices[tri[1]], mesh.vertices[tri[2]]);
    const Vec3 to_centre = centre - closest.point;
    const double d2 = to_centre.squaredNorm();
    // Every edge and vertex of the triangle is at least this far, so none of them touches either.
    if (d2 >= r2) continue;

    // Face: the centre projects into the triangle (all three opposite weights >= 0).
    if (!has_feature(out, MeshFeature::Face, t) &&
        opposite_weight(mesh, t, 0, centre) >= -kRegionSlack &&
        opposite_weight(mesh, t, 1, centre) >= -kRegionSlack &&
        opposite_weight(mesh, t, 2, centre) >= -kRegionSlack) {
      const Vec3 n = mesh.triangle_normal(t);
      const double distance = std::sqrt(d2);
      out.push_back({t, MeshFeature::Face, t, closest.point, to_centre.dot(n) < 0.0 ? -n : n,
                     radius - distance});
    }

    for (int k = 0; k < 3; ++k) {
      const int e = mesh.triangle_edges[t][k];
      if (has_feature(out, MeshFeature::Edge, e)) continue;
      const double s = edge_parameter(mesh, e, centre);
      const Vec3& lo = mesh.vertices[mesh.edge_vertices[e][0]];
      const Vec3& hi = mesh.vertices[mesh.edge_vertices[e][1]];
      const Vec3 point = lo + std::clamp(s, 0.0, 1.0) * (hi - lo);
      const Vec3 from = centre - point;
      const double de2 = from.squaredNorm();
      if (de2 >= r2 || !edge_region_contains(mesh, e, s, centre)) continue;
      const double distance = std::sqrt(de2);
      out.push_back({t, MeshFeature::Edge, e, point, contact_direction(mesh, t, from, distance),
                     radius - distance});
    }

    for (int k = 0; k < 3; ++k) {
      const int v = tri[k];
      if (has_feature(out, MeshFeature::Vertex, v)) continue;
      const Vec3 from = centre - mesh.vertices[v];
      const double dv2 = from.squaredNorm();
      if (dv2 >= r2 || !vertex_region_contains(mesh, v, centre)) continue;
      const double distance = std::sqrt(dv2);
      out.push_back({t, MeshFeature::Vertex, v, mesh.vertices[v],
                     contact_direction(mesh, t, from, distance), radius - distance});
    }
  }

  // Contacts at one position are one contact (a centre on a shared boundary lies in the widened
  // regions of several features); keep the face, whose normal is exact, before an edge or vertex.
  std::size_t kept = 0;
  for (std::size_t j = 0; j < out.size(); ++j) {
    const double edge_j = longest_edge(mesh, out[j].triangle);
    bool merged = false;
    for (std::size_t i = 0; i < kept && !merged; ++i) {
      const double tol =
          kMergeRadius * radius + kMergeEdge * (edge_j + longest_edge(mesh, out[i].triangle));
      if ((out[i].point - out[j].point).squaredNorm() <= tol * tol) {
        if (out[j].feature < out[i].feature) out[i] = out[j];
        merged = true;
      }
    }
    if (!merged) out[kept++] = out[j];
  }
  out.resize(kept);
}

}  // namespace trackbed::dem
