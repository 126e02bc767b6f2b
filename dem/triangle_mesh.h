// Triangle-mesh walls: the mesh and its topology, STL input, mass properties of closed meshes,
// sphere-mesh contact detection with face, edge and vertex contacts, and a uniform grid that
// finds the triangles near a sphere. Pure geometry: no contact history, no forces (docs/meshes.md).
#pragma once

#include <array>
#include <string>
#include <vector>

#include "dem/input_error.h"
#include "dem/types.h"

namespace trackbed::dem {

// A triangle mesh. Triangles list vertex ids counter-clockwise seen from outside, so the normal
// (v1 - v0) x (v2 - v0) points outward. The topology members are built by finalize() and depend
// only on the vertex ids, never on coordinates: moving the vertices (a moving wall, or an FE
// boundary that deforms) needs no call to keep them valid.
struct TriangleMesh {
  std::vector<Vec3> vertices;
  std::vector<std::array<int, 3>> triangles;
  std::vector<int> triangle_part;       // index into part_names, one per triangle
  std::vector<std::string> part_names;  // e.g. "base", "sides", "ends" of a sleeper

  // Topology, built by finalize().
  std::vector<std::array<int, 3>> triangle_edges;  // edge ids of (v0v1, v1v2, v2v0)
  int num_edges = 0;
  std::vector<std::array<int, 2>> edge_vertices;  // the two vertex ids, lower id first
  // Triangles of edge e: edge_triangles[edge_triangle_offsets[e] .. edge_triangle_offsets[e+1]).
  // One entry on an open boundary, two on a manifold edge, more on a non-manifold one.
  std::vector<int> edge_triangle_offsets;
  std::vector<int> edge_triangles;
  // Edges of vertex v: vertex_edges[vertex_edge_offsets[v] .. vertex_edge_offsets[v+1]).
  std::vector<int> vertex_edge_offsets;
  std::vector<int> vertex_edges;

  // Merges vertices closer than kMergeTolerance times the bounding-box diagonal (STL repeats every
  // vertex once per triangle), renumbers the triangles, and builds the topology. Vertex ids are
  // kept in order of first occurrence, so a mesh without such duplicates keeps its numbering.
  // An empty triangle_part means one part; an empty part_names gets the name "mesh".
  // Throws DegenerateTriangleError for a triangle whose smallest height is below the merging
  // tolerance (collinear or repeated vertices), InputError for non-finite coordinates, and
  // std::invalid_argument for inconsistent sizes or vertex ids out of range.
  void finalize();

  // Every edge shared by exactly two triangles that traverse it in opposite directions (a
  // consistently oriented, watertight 2-manifold). Needs finalize().
  bool is_closed() const;

  // Rigid and similarity transforms; they move vertices only, so the topology stays valid.
  void translate(const Vec3& shift);
  void rotate(const Mat3& rotation, const Vec3& about);  // rotation must be orthonormal, det +1
  void scale(double factor, const Vec3& about);          // factor > 0 keeps the orientation

  // Unit outward normal of a triangle (from its vertex order).
  Vec3 triangle_normal(int triangle) const;

  // Relative to the bounding-box diagonal: far below any physical feature of a wall or sleeper
  // (1 um on a 1 m mesh), far above the rounding of coordinates stored as float in binary STL
  // (6e-8 relative), so vertices an exporter repeated always merge.
  static constexpr double kMergeTolerance = 1e-6;
};

// The InputError of a degenerate triangle, carrying its index so that read_stl can say on which
// line of the file the triangle is.
class DegenerateTriangleError : public InputError {
 public:
  DegenerateTriangleError(int triangle, const std::string& message)
      : InputError(message), triangle_(triangle) {}
  int triangle() const { return triangle_; }

 private:
  int triangle_;
};

// Reads an ASCII or binary STL file and returns the finalized mesh. Binary is recognised by its
// size, 84 + 50 n bytes for the n triangles its header declares (binary headers may begin with
// "solid" too); otherwise a text file beginning with "solid" is ASCII. Every ASCII
// `solid NAME ... endsolid` block becomes a part named NAME (blocks with the same name share a
// part; a nameless block is named after the file stem); a binary file is one part named after the
// file stem. Facet normals in the file are ignored: the vertex order defines the orientation.
// Throws InputError ("FILE:LINE: message" for ASCII) for a missing file, a truncated binary file,
// malformed ASCII, non-finite coordinates, no triangles, or a degenerate triangle.
TriangleMesh read_stl(const std::string& path);

// An axis-aligned box, 8 vertices and 12 triangles with outward normals. With part names the parts
// are "base" (z = lower.z), "top" (z = upper.z), "sides" (the two y faces) and "ends" (the two x
// faces), which fits a sleeper lying along x; otherwise one part "box". Finalized.
// bottom_width > 0 narrows (or widens) the base face to that extent in y about the box's centre
// line, a trapezoidal prism: the wedge-shaped sleeper section of the ballast box test.
TriangleMesh make_box_mesh(const Vec3& lower, const Vec3& upper, bool with_part_names,
                           double bottom_width = 0);

// Volume, centroid and inertia tensor about the centroid per unit density of the solid a closed
// mesh bounds (Eberly, "Polyhedral Mass Properties (Revisited)", 2002: divergence theorem on each
// triangle). Throws InputError for an open mesh or one oriented inward (negative volume).
struct MeshMassProperties {
  double volume;
  Vec3 centroid;
  Mat3 inertia;  // multiply by the density; products of inertia carry the minus sign
};
MeshMassProperties closed_mesh_mass_properties(const TriangleMesh& mesh);

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

// A uniform grid over a mesh's bounding box; each triangle is registered in every cell its
// bounding box overlaps. A query visits only the cells the sphere's bounding box overlaps and
// returns, sorted and without repeats, the triangles whose bounding box comes within radius of
// the centre: a superset of the triangles closer than radius. The grid holds the vertex
// positions at build time: rebuild when the mesh moves, or query with the radius enlarged by the
// largest vertex displacement since the build.
class TriangleGrid {
 public:
  // cell > 0; a cell about the size of the triangles or of the particles is a good choice. The
  // cell is enlarged if the grid would need more than kMaxCells cells.
  void build(const TriangleMesh& mesh, double cell);
  void query(const Vec3& centre, double radius, std::vector<int>& out) const;

  double cell_size() const { return cell_; }

  static constexpr long kMaxCells = 1L << 26;  // 64 Mi cells, 256 MiB of offsets

 private:
  Vec3 origin_ = Vec3::Zero();
  double cell_ = 0.0;
  std::array<int, 3> dims_{{0, 0, 0}};
  std::vector<int> cell_offsets_;  // CSR: triangles of cell c in items_[offsets[c], offsets[c+1])
  std::vector<int> items_;
  std::vector<Vec3> box_lower_;  // triangle bounding boxes at build time
  std::vector<Vec3> box_upper_;
};

}  // namespace trackbed::dem
