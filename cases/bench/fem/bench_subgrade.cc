// Benchmark of the quasi-static FE subgrade (not a test): a layered block of about N dofs under
// gravity and a sleeper-footprint load, fixed base and roller sides. It reports the setup
// (dofs, sparsity, stiffness assembly), the AMG setup, the first solve, and re-solves with the
// preconditioner reused after load changes, as a coupled run does at every exchange.
//
//   mpirun -np P trackbed_fem_bench DOFS DEGREE RESOLVES [TOLERANCE]
#include <deal.II/base/mpi.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>

#include "fem/elastic_body.h"

using namespace trackbed::fem;

int run(int argc, char** argv) {
  const double target_dofs = argc > 1 ? std::atof(argv[1]) : 1e6;
  const unsigned int degree = argc > 2 ? std::atoi(argv[2]) : 1;
  const int resolves = argc > 3 ? std::atoi(argv[3]) : 5;
  SolverParameters solver;
  solver.relative_tolerance = argc > 4 ? std::atof(argv[4]) : 1e-8;
  int rank = 0, n_ranks = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &n_ranks);

  // An 8 m (across) x 4 m (along) x 4 m (deep) block: 0.3 m sub-ballast, 1.7 m fill, 2 m ground,
  // with (2n p + 1)(n p + 1)^2 nodes of 3 dofs.
  const unsigned int n =
      std::max(1u, static_cast<unsigned int>(std::round(std::cbrt(target_dofs / 6.0) / degree)));
  BoxGeometry box{{{-4, 0, -4}}, {{4, 4, 0}}, {{2 * n, n, n}}, {}};
  box.layers = {{-4, -2, 4}, {-2, -0.3, 3}, {-0.3, 0.1, 2}};
  auto clock = std::chrono::steady_clock::now();
  auto lap = [&] {
    MPI_Barrier(MPI_COMM_WORLD);
    const auto now = std::chrono::steady_clock::now();
    const double seconds = std::chrono::duration<double>(now - clock).count();
    clock = now;
    return seconds;
  };
  ElasticBody body(degree, MPI_COMM_WORLD);
  body.make_box(box);
  body.set_material(2, sub_ballast());
  body.set_material(3, subgrade_fill());
  body.set_material(4, natural_ground());
  // The footprint of a sleeper's ballast pressure: 2.6 m x 0.3 m at the centre of the top.
  body.mark_boundary("footprint", 6, [](const Vector3& c) {
    return c[2] > -1e-9 && std::abs(c[0]) < 1.3 && std::abs(c[1] - 2.0) < 0.15 + 1e-9;
  });
  body.fix(body.boundary_id("zmin"));
  for (const char* side : {"xmin", "xmax"})
    body.fix(body.boundary_id(side), {{true, false, false}});
  for (const char* side : {"ymin", "ymax"})
    body.fix(body.boundary_id(side), {{false, true, false}});
  body.set_boundary_force(body.boundary_id("footprint"), {{0, 0, -1e5}});
  body.set_solver(solver);
  const double mesh_seconds = lap();
  body.setup();
  const double setup_seconds = lap();
  const SolveReport first = body.solve_static();
  const double first_seconds = lap();

  double resolve_seconds = 0.0, resolve_load_seconds = 0.0, resolve_solve_seconds = 0.0;
  unsigned int resolve_iterations = 0;
  for (int k = 1; k <= resolves; ++k) {
    // A load change as between two coupling exchanges: 2 % more, slightly lateral.
    body.set_boundary_force(body.boundary_id("footprint"), {{2e3 * k, 0, -1e5 * (1 + 0.02 * k)}});
    lap();
    const SolveReport report = body.solve_static();
    resolve_seconds += lap();
    resolve_iterations += report.iterations;
    resolve_load_seconds += report.assembly_seconds;
    resolve_solve_seconds += report.solve_seconds;
  }
  const double settlement = -body.probe({{{0, 2, 0}}})[0].displacement[2];
  if (rank == 0)
    std::printf(
        "processes=%d degree=%u tolerance=%g dofs=%llu cells=%llu mesh_s=%.2f setup_s=%.2f "
        "amg_s=%.2f "
        "first_solve_s=%.2f first_iterations=%u resolve_s=%.3f resolve_load_s=%.3f "
        "resolve_solve_s=%.3f resolve_iterations=%.1f settlement_mm=%.4f\n",
        n_ranks, degree, solver.relative_tolerance, static_cast<unsigned long long>(body.n_dofs()),
        static_cast<unsigned long long>(body.n_cells()), mesh_seconds, setup_seconds,
        first.preconditioner_seconds, first_seconds - first.preconditioner_seconds,
        first.iterations, resolve_seconds / resolves, resolve_load_seconds / resolves,
        resolve_solve_seconds / resolves, static_cast<double>(resolve_iterations) / resolves,
        settlement * 1e3);
  return 0;
}

int main(int argc, char** argv) {
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  try {
    return run(argc, argv);
  } catch (const std::exception& error) {
    std::fprintf(stderr, "trackbed_fem_bench: %s\n", error.what());
    return 1;
  }
}
