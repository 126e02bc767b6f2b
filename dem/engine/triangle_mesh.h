// Triangle-mesh walls: the mesh and its topology, its transforms, a box mesh, and the mass
// properties of closed meshes. Pure geometry: no contact history, no forces (docs/meshes.md).
// Contact detection against a mesh is in mesh_contact.h, the search grid in triangle_grid.h, STL
// input in dem/io/stl_file.h.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "common/input_error.h"
#include "dem/engine/types.h"

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

  // Which of triangle t's edges (0, 1, 2: v0v1, v1v2, v2v0) is edge e; e must be one of them.
  int local_edge(int t, int e) const {
    const auto& te = triangle_edges[t];
    return te[0] == e ? 0 : (te[1] == e ? 1 : 2);
  }

  // Relative to the bounding-box diagonal: far below any physical feature of a wall or sleeper
  // (1 um on a 1 m mesh), far above the rounding of coordinates stored as float in binary STL
  // (6e-8 relative), so vertices an exporter repeated always merge.
  static constexpr double kMergeTolerance = 1e-6;
};

// The InputError of a degenerate triangle, carrying its index so that read_stl (dem/io/stl_file.h)
// can say on which line of the file the triangle is.
class DegenerateTriangleError : public InputError {
 public:
  DegenerateTriangleError(int triangle, const std::string& message)
      : InputError(message), triangle_(triangle) {}
  int triangle() const { return triangle_; }

 private:
  int triangle_;
};

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

}  // namespace trackbed::dem
