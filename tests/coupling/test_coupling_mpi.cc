// The interface wall on two MPI processes (run with mpirun -np 2): the FE box split between
// them, each owning part of the wall's vertices. Given the same vertex loads, the vertex
// displacements equal those of the same box solved whole on one process (MPI_COMM_SELF), to
// 1e-8 of their size (both solved by CG to 1e-12), and the wall is the same on every process.
#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "coupling/interface_wall.h"
#include "elastic_box.h"
#include "fem/boundary_interface.h"
#include "fem/elastic_body.h"

namespace trackbed::coupling {
namespace {

using dem::Vec3;

// One layer of 4 x 4 coarse cells refined twice: p4est hands each process whole coarse cells in
// order, so the top, the wall, is split between the two processes. CG to 1e-12.
std::unique_ptr<fem::ElasticBody> box(MPI_Comm communicator) {
  fem::SolverParameters solver;
  solver.relative_tolerance = 1e-12;
  return testing::elastic_box(communicator, {{4, 4, 1}}, 2, solver);
}

// Loads that differ from vertex to vertex and in every component, the same on every process.
std::vector<Vec3> loads(std::size_t n) {
  std::vector<Vec3> f(n);
  for (std::size_t v = 0; v < n; ++v)
    f[v] = Vec3(std::sin(1.3 * v), std::cos(0.7 * v), -2.0 - std::sin(0.3 * v * v));
  return f;
}

// The wall's vertex displacements under loads(); `mesh` gets the wall, `local_triangles` the
// number of interface triangles this process holds.
std::vector<Vec3> displacements(MPI_Comm communicator, dem::TriangleMesh& mesh,
                                std::size_t& local_triangles) {
  auto body = box(communicator);
  fem::BoundaryInterface top(*body, "zmax");
  local_triangles = top.triangles().size();
  InterfaceWall wall(top, "zmax", communicator);
  mesh = wall.mesh();
  wall.apply_vertex_loads(loads(wall.num_vertices()));
  body->solve_static();
  std::vector<Vec3> u, v;
  wall.vertex_motion(u, v);
  return u;
}

TEST(CouplingMpi, TwoProcessesGiveTheOneProcessDisplacements) {
  int size = 0;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  ASSERT_EQ(size, 2) << "run with mpirun -np 2";
  dem::TriangleMesh split_mesh, whole_mesh;
  std::size_t split_triangles = 0, whole_triangles = 0;
  const std::vector<Vec3> split = displacements(MPI_COMM_WORLD, split_mesh, split_triangles);
  const std::vector<Vec3> whole = displacements(MPI_COMM_SELF, whole_mesh, whole_triangles);
  // Each process holds a part of the wall, not all of it.
  EXPECT_GT(split_triangles, 0u);
  EXPECT_LT(split_triangles, whole_triangles);
  ASSERT_EQ(split_mesh.vertices, whole_mesh.vertices);  // the same wall, vertex for vertex
  ASSERT_EQ(split_mesh.triangles, whole_mesh.triangles);
  ASSERT_EQ(split_mesh.vertices.size(), 17u * 17u);
  double largest = 0;
  for (const Vec3& u : whole) largest = std::max(largest, u.norm());
  ASSERT_GT(largest, 0);
  for (std::size_t v = 0; v < whole.size(); ++v)
    EXPECT_NEAR((split[v] - whole[v]).norm(), 0, 1e-8 * largest) << "vertex " << v;
}

}  // namespace
}  // namespace trackbed::coupling
