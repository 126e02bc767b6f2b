// Closed triangle surfaces that bound a solid (a stone to be packed with pebbles): the checks
// that a surface really bounds one, its mass properties with a principal frame, and the signed
// distance to it (docs/templates.md).
#pragma once

#include <string>
#include <vector>

#include "dem/engine/mass_properties.h"
#include "dem/engine/triangle_grid.h"
#include "dem/engine/triangle_mesh.h"
#include "dem/engine/types.h"

namespace trackbed::dem {

// Throws InputError, one line starting with `what` (e.g. the file), unless the finalized `mesh`
// is a closed, consistently and outward oriented surface that does not intersect itself:
//  - every edge shared by exactly two triangles traversing it in opposite directions
//    (TriangleMesh::is_closed), else the counts of open, non-manifold and misoriented edges;
//  - positive enclosed volume (closed_mesh_mass_properties), else it is oriented inward;
//  - no two triangles without a common vertex touch or cross (Moeller 1997 interval test on the
//    pairs a TriangleGrid finds, so a 100k-triangle scan takes well under a second).
// Degenerate triangles never get here: TriangleMesh::finalize() refuses them.
void check_closed_surface(const TriangleMesh& mesh, const std::string& what);

// read_stl and check_closed_surface: the surface of a stone given as STL. Errors name the file
// (and for a degenerate triangle the line of its facet).
TriangleMesh read_closed_surface(const std::string& stl_path);

// Volume, centroid, inertia and principal frame of the solid a closed surface bounds
// (closed_mesh_mass_properties), with principal axes chosen as sphere_union_mass_properties
// chooses them (ascending moments, each axis's largest component positive, right-handed).
MassProperties surface_mass_properties(const TriangleMesh& closed_surface);

// Signed distance to a closed surface, negative inside, by a bounding-volume hierarchy over the
// triangles (nearest triangle in O(log n)). The sign is that of (p - closest point) . n, n the
// angle-weighted pseudo-normal of the closest feature (face, edge or vertex), which is exact for
// closed, consistently oriented manifolds (Baerentzen and Aanaes 2005): no rays, no parity.
class SignedDistance {
 public:
  // `surface` must be closed (check_closed_surface); it is copied.
  explicit SignedDistance(const TriangleMesh& surface);
  double operator()(const Vec3& p) const;

 private:
  struct Node {
    Vec3 lower, upper;
    int first, count;  // leaf: triangles order_[first, first + count); inner: count = 0
    int left, right;
  };
  int build(int first, int count);

  TriangleMesh mesh_;
  std::vector<Vec3> face_normals_, edge_normals_, vertex_normals_;
  std::vector<int> order_;
  std::vector<Node> nodes_;
};

}  // namespace trackbed::dem
