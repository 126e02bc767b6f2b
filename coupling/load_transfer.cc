#include "coupling/load_transfer.h"

#include <mpi.h>

#include <cmath>
#include <stdexcept>
#include <string>

#include "common/number_text.h"

namespace trackbed::coupling {

void check_interface_mesh(const dem::Simulation& sim, int mesh, const InterfaceWall& wall,
                          const char* scheme) {
  if (mesh < 0 || mesh >= static_cast<int>(sim.meshes().size()) || !sim.meshes()[mesh].deformable ||
      sim.meshes()[mesh].world.vertices.size() != wall.num_vertices())
    throw std::invalid_argument(
        std::string(scheme) + ": mesh " + std::to_string(mesh) +
        " is not the deformable mesh of the interface wall (same vertices, same order)");
}

void take_mean_loads(dem::Simulation* sim, int mesh, const InterfaceWall& wall,
                     std::vector<dem::Vec3>& loads) {
  if (sim) loads = sim->meshes()[mesh].deformation.take_mean_load();
  static_assert(sizeof(dem::Vec3) == 3 * sizeof(double), "Vec3 is three packed doubles");
  MPI_Bcast(loads.data(), static_cast<int>(3 * loads.size()), MPI_DOUBLE, 0, wall.communicator());
}

AppliedLoad apply_loads(InterfaceWall& wall, fem::ElasticBody& body,
                        const std::vector<dem::Vec3>& loads, int exchange) {
  AppliedLoad applied;
  applied.sum = dem::Vec3::Zero();
  for (const dem::Vec3& f : loads) applied.sum += f;
  wall.apply_vertex_loads(loads);
  const fem::LoadResultant resultant = body.interface_load_resultant({{0, 0, 0}});
  applied.fe_load = dem::Vec3(resultant.force[0], resultant.force[1], resultant.force[2]);
  const double scale = applied.sum.norm();
  applied.balance_error =
      scale > 0 ? (applied.fe_load - applied.sum).norm() / scale : applied.fe_load.norm();
  if (!(applied.balance_error <= 1e-10))
    throw std::runtime_error("coupling: exchange " + std::to_string(exchange) +
                             ": the FE load differs from the DEM's by " +
                             number_text(applied.balance_error) + " of it (limit 1e-10)");
  return applied;
}

double rms(const std::vector<dem::Vec3>& v) {
  double sum = 0;
  for (const dem::Vec3& x : v) sum += x.squaredNorm();
  return v.empty() ? 0.0 : std::sqrt(sum / v.size());
}

double dot(const std::vector<dem::Vec3>& a, const std::vector<dem::Vec3>& b) {
  double sum = 0;
  for (std::size_t i = 0; i < a.size(); ++i) sum += a[i].dot(b[i]);
  return sum;
}

}  // namespace trackbed::coupling
