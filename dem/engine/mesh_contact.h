// Sphere-mesh contact detection with face, edge and vertex contacts, each feature reported once
// (docs/meshes.md). Pure geometry: no contact history, no forces.
#pragma once

#include <vector>

#include "dem/engine/triangle_mesh.h"
#include "dem/engine/types.h"

namespace trackbed::dem {

// The closest features of a triangle: its interior, edge k from vertex k to vertex (k + 1) % 3,
// or vertex k.
enum class MeshFeature { Face, Edge, Vertex };

struct TriangleClosestPoint {
  Vec3 point;
  MeshFeature feature;
  int local_id;      // edge k or vertex k (0, 1, 2); 0 for Face
  Vec3 barycentric;  // weights of (a, b, c) of point
};

// Closest point of triangle (a, b, c) to p by Voronoi regions (Ericson, Real-Time Collision
// Detection, 2005, section 5.1.5): the feature is the region p lies in, boundaries going to the
// lower-dimensional feature. The triangle must not be degenerate.
TriangleClosestPoint closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b,
                                               const Vec3& c);

// One contact of a sphere with a mesh.
struct MeshContactPoint {
  using Feature = MeshFeature;
  int triangle;     // the triangle it was found on (for an edge or vertex: a triangle holding it)
  Feature feature;  // Face, Edge or Vertex
  int feature_id;   // triangle id, edge id or vertex id
  Vec3 point;       // closest point on the mesh
  Vec3 normal;      // unit, from the mesh toward the sphere centre
  double overlap;   // radius - distance, > 0
};

// All contacts of the sphere (centre, radius) with the mesh, into out (cleared first; no heap
// allocation once out has grown to the largest contact count). candidate_triangles must include
// every triangle closer than radius to the centre (more is fine, duplicates too): TriangleGrid
// gives such a list. The mesh must be finalized. Rules (docs/meshes.md):
//  - a face contact exists where the centre projects into the triangle;
//  - an edge contact exists where the centre projects onto the edge segment and, for every
//    triangle of the edge, not into that triangle's interior;
//  - a vertex contact exists where the centre projects behind the vertex along every edge of it;
// so every feature is reported once, a face contact excludes the contacts of its edges and
// vertices, an edge contact those of its two vertices, and on a flat mesh there is one contact
// equal to the plane contact wherever the sphere is. A convex edge gives one contact, a concave
// corner one per face. Contacts are two-sided: a centre behind a face (inside a closed mesh)
// gets a normal from the closest point toward the centre, i.e. against the face's outward normal.
// A face contact's normal is the face normal (sign toward the centre); edge and vertex contacts
// use the direction from the closest point to the centre.
void sphere_mesh_contacts(const TriangleMesh& mesh, const Vec3& centre, double radius,
                          const int* candidate_triangles, int n_candidates,
                          std::vector<MeshContactPoint>& out);

}  // namespace trackbed::dem
