// The DEM wall of an FE boundary, and the two maps across it (docs/coupling.md).
//
// The faces of the named FE boundary (fem::BoundaryInterface, each process its own) are gathered
// from every process into one triangle mesh with coincident corners merged, so the wall has no
// seams, and oriented with its normals out of the FE body, into the ballast. Each wall vertex is
// a corner of FE interface triangles; one process owns it (the lowest rank that holds such a
// triangle) and evaluates the FE field there. The maps:
//   DEM -> FE  a vertex load F_v becomes the point force F_v at that corner, i.e. the consistent
//              nodal loads F_v,c phi_i(x_v) on every dof i of component c;
//   FE -> DEM  a vertex displacement is u(x_v) = sum_i U_i phi_i(x_v).
// They are exact transposes: sum_v F_v . u(x_v) = f . U, so the interface work is the same on
// both sides. With the DEM's barycentric split of contact forces to vertices (the transpose of
// its interpolation of vertex velocities), a contact force's work is the same in DEM and FE.
#pragma once

#include <mpi.h>

#include <string>
#include <vector>

#include "dem/engine/triangle_mesh.h"
#include "dem/engine/types.h"
#include "fem/boundary_interface.h"

namespace trackbed::coupling {

class InterfaceWall {
 public:
  // Collective over the body's communicator. Throws InputError naming the boundary when it has
  // no face, or a gathered triangle whose corner order cannot match the FE outward normal.
  InterfaceWall(fem::BoundaryInterface& interface, const std::string& boundary_name,
                MPI_Comm communicator);

  // The wall in reference (undeformed) position, finalized; one part named after the boundary.
  const dem::TriangleMesh& mesh() const { return mesh_; }
  std::size_t num_vertices() const { return mesh_.vertices.size(); }
  MPI_Comm communicator() const { return communicator_; }

  // DEM -> FE: replaces the body's interface load by the vertex loads (N, one per wall vertex,
  // the same on every process). Collective.
  void apply_vertex_loads(const std::vector<dem::Vec3>& loads);
  // FE -> DEM: the displacement (m) and velocity (m/s) of every wall vertex from the body's
  // current solution, the same on every process. Collective.
  void vertex_motion(std::vector<dem::Vec3>& displacement, std::vector<dem::Vec3>& velocity) const;

 private:
  fem::BoundaryInterface& interface_;
  MPI_Comm communicator_;
  dem::TriangleMesh mesh_;
  // The vertices this process owns and where they lie on its FE triangles.
  std::vector<int> owned_;
  std::vector<fem::TrianglePoint> owned_points_;
};

}  // namespace trackbed::coupling
