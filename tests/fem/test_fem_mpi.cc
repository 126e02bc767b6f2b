// Run with mpirun -np 2: the distributed solution must equal the serial one (each process also
// solves the whole problem alone on MPI_COMM_SELF) to solver tolerance.
#include <gtest/gtest.h>
#include <mpi.h>

#include <cmath>
#include <fstream>

#include "fem/boundary_interface.h"
#include "fem/elastic_body.h"

namespace trackbed::fem {
namespace {

// Two layers under gravity and a footing load, fixed base and roller sides: Q2 on 6 x 4 x 6 cells.
void build(ElasticBody& body) {
  body.make_box({{{0, 0, -3}}, {{3, 2, 0}}, {{6, 4, 6}}, {{{-3, -1, 3}, {-1, 0.1, 2}}}});
  body.set_material(2, sub_ballast());
  body.set_material(3, subgrade_fill());
  body.mark_boundary("footing", 6,
                     [](const Vector3& c) { return c[2] > -1e-9 && c[0] < 1.0 && c[1] < 1.0; });
  body.fix(body.boundary_id("zmin"));
  for (const char* side : {"xmin", "xmax"})
    body.fix(body.boundary_id(side), {{true, false, false}});
  for (const char* side : {"ymin", "ymax"})
    body.fix(body.boundary_id(side), {{false, true, false}});
  body.set_traction(body.boundary_id("footing"), {{0, 0, -5e4}});
  SolverParameters solver;
  solver.relative_tolerance = 1e-12;
  body.set_solver(solver);
  body.setup();
}

const std::vector<Vector3> points{{{0.1, 0.1, -0.01}}, {{0.9, 0.5, -0.5}}, {{2.9, 1.9, -2.9}},
                                  {{1.5, 1.0, -1.5}},  {{0.5, 1.7, -2.2}}, {{2.2, 0.3, -0.7}}};

// Solver tolerance 1e-12 relative; the two solutions differ by at most cond(K) times that, and
// 1e-8 of the largest value bounds it with margin.
void expect_equal(const std::vector<PointValues>& a, const std::vector<PointValues>& b) {
  double u_scale = 0.0, s_scale = 0.0, v_scale = 0.0;
  for (const auto& v : b)
    for (int i = 0; i < 3; ++i) {
      u_scale = std::max(u_scale, std::abs(v.displacement[i]));
      v_scale = std::max(v_scale, std::abs(v.velocity[i]));
      for (int j = 0; j < 3; ++j) s_scale = std::max(s_scale, std::abs(v.stress[i][j]));
    }
  for (std::size_t k = 0; k < a.size(); ++k)
    for (int i = 0; i < 3; ++i) {
      EXPECT_NEAR(a[k].displacement[i], b[k].displacement[i], 1e-8 * u_scale);
      EXPECT_NEAR(a[k].velocity[i], b[k].velocity[i], 1e-8 * v_scale);
      for (int j = 0; j < 3; ++j) EXPECT_NEAR(a[k].stress[i][j], b[k].stress[i][j], 1e-8 * s_scale);
    }
}

TEST(FemMpi, TwoProcessesEqualOne) {
  int n_processes = 0;
  MPI_Comm_size(MPI_COMM_WORLD, &n_processes);
  EXPECT_EQ(n_processes, 2) << "run with mpirun -np 2";
  ElasticBody distributed(2, MPI_COMM_WORLD), serial(2, MPI_COMM_SELF);
  build(distributed);
  build(serial);
  EXPECT_EQ(distributed.n_dofs(), serial.n_dofs());
  const SolveReport parallel_report = distributed.solve_static();
  serial.solve_static();
  EXPECT_GT(parallel_report.iterations, 0u);
  expect_equal(distributed.probe(points), serial.probe(points));
  EXPECT_NEAR(distributed.energies().strain, serial.energies().strain,
              1e-9 * serial.energies().strain);

  // A few Newmark steps after removing the footing load.
  NewmarkParameters newmark;
  newmark.time_step = 2e-3;
  newmark.rayleigh_mass = 1.0;
  newmark.rayleigh_stiffness = 1e-4;
  for (ElasticBody* body : {&distributed, &serial}) {
    body->set_absorbing(body->boundary_id("zmin"));
    body->start_dynamics(newmark);
    body->set_traction(body->boundary_id("footing"), {{0, 0, 0}});
    for (int step = 0; step < 5; ++step) body->advance();
  }
  expect_equal(distributed.probe(points), serial.probe(points));
}

// Each process holds the triangles of its own cells: together they are the serial set, and the
// nodal loads of forces added on every process sum to all the forces.
TEST(FemMpi, InterfaceIsPartitioned) {
  ElasticBody distributed(1, MPI_COMM_WORLD), serial(1, MPI_COMM_SELF);
  build(distributed);
  build(serial);
  BoundaryInterface parallel_top(distributed, "zmax"), serial_top(serial, "zmax");
  unsigned long local = parallel_top.triangles().size(), total = 0;
  MPI_Allreduce(&local, &total, 1, MPI_UNSIGNED_LONG, MPI_SUM, MPI_COMM_WORLD);
  EXPECT_EQ(total, serial_top.triangles().size());
  double area = 0.0;
  for (const auto& t : parallel_top.triangles()) area += t.area;
  MPI_Allreduce(MPI_IN_PLACE, &area, 1, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
  EXPECT_NEAR(area, 5.0, 1e-12);  // the 3 m x 2 m top less the 1 m x 1 m footing

  std::vector<PointForce> forces;
  for (std::size_t t = 0; t < parallel_top.triangles().size(); t += 3)
    forces.push_back({{t, {{0.2, 0.3, 0.5}}}, {{1.0, -2.0, -10.0}}});
  parallel_top.add_forces(forces);
  double fz = -10.0 * forces.size();
  MPI_Allreduce(MPI_IN_PLACE, &fz, 1, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
  const LoadResultant resultant = distributed.interface_load_resultant({{0, 0, 0}});
  EXPECT_NEAR(resultant.force[2], fz, 1e-10 * std::abs(fz));
  EXPECT_NEAR(resultant.force[0], -0.1 * fz, 1e-10 * std::abs(fz));
}

// Both processes write their piece of the PVTU record and their part of the HDF5 file.
TEST(FemMpi, ParallelOutput) {
  ElasticBody body(1, MPI_COMM_WORLD);
  build(body);
  body.solve_static();
  const std::string directory = ::testing::TempDir();
  const std::string record = body.write_vtu(directory, "fem_mpi", 0);
  body.write_hdf5(directory + "/fem_mpi.h5", 0.0);
  for (const std::string& file :
       {record, directory + "/fem_mpi_00000.0000.vtu", directory + "/fem_mpi_00000.0001.vtu",
        directory + "/fem_mpi.h5", directory + "/fem_mpi.xdmf"})
    EXPECT_TRUE(std::ifstream(file).good()) << file;
}

}  // namespace
}  // namespace trackbed::fem
