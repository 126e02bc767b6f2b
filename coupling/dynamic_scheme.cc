#include "coupling/dynamic_scheme.h"

#include <mpi.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>

#include "common/input_error.h"
#include "common/number_text.h"
#include "coupling/load_transfer.h"

namespace trackbed::coupling {

void DynamicParameters::validate() const {
  if (interval_steps < 1)
    throw InputError("coupling: interval = " + std::to_string(interval_steps) +
                     " DEM steps; valid: an integer >= 1");
  if (ramp_exchanges < 1)
    throw InputError("coupling: ramp = " + std::to_string(ramp_exchanges) +
                     " exchanges; valid: an integer >= 1");
  if (!(rayleigh_mass >= 0 && std::isfinite(rayleigh_mass)))
    throw InputError("fem: Rayleigh mass damping = " + number_text(rayleigh_mass) +
                     " 1/s; valid: >= 0");
  if (!(rayleigh_stiffness >= 0 && std::isfinite(rayleigh_stiffness)))
    throw InputError("fem: Rayleigh stiffness damping = " + number_text(rayleigh_stiffness) +
                     " s; valid: >= 0");
}

DynamicScheme::DynamicScheme(dem::Simulation& sim, int mesh, fem::ElasticBody& body,
                             InterfaceWall& wall, const DynamicParameters& parameters)
    : sim_(&sim), mesh_(mesh), body_(body), wall_(wall), parameters_(parameters) {
  check_interface_mesh(sim, mesh, wall, "DynamicScheme");
  start(sim.time_step());
}

DynamicScheme::DynamicScheme(fem::ElasticBody& body, InterfaceWall& wall,
                             const DynamicParameters& parameters)
    : sim_(nullptr), mesh_(-1), body_(body), wall_(wall), parameters_(parameters) {
  start(0);
}

void DynamicScheme::start(double time_step) {
  parameters_.validate();
  MPI_Bcast(&time_step, 1, MPI_DOUBLE, 0, wall_.communicator());
  time_step_ = time_step;
  reference_ = wall_.mesh().vertices;
  const std::size_t n = reference_.size();
  mean_.assign(n, dem::Vec3::Zero());
  end_load_.assign(n, dem::Vec3::Zero());
  u_.assign(n, dem::Vec3::Zero());
  // At rest and unloaded: Newmark's start then has a_0 = M^-1 (f_0 - K u_0) = 0.
  wall_.apply_vertex_loads(end_load_);
  body_.start_dynamics({parameters_.interval_steps * time_step, parameters_.rayleigh_mass,
                        parameters_.rayleigh_stiffness});
}

DynamicExchangeReport DynamicScheme::exchange() {
  DynamicExchangeReport report;
  report.exchange = ++exchanges_;
  const auto start = std::chrono::steady_clock::now();
  const int T = parameters_.interval_steps;

  // DEM -> FE: the interval's mean loads F^ as the FE step's mean load, through its end load.
  take_mean_loads(sim_, mesh_, wall_, mean_);
  report.ramp = std::min(1.0, static_cast<double>(exchanges_) / parameters_.ramp_exchanges);
  report.dem_load = dem::Vec3::Zero();
  std::vector<dem::Vec3> ramped(mean_.size());
  dem::Vec3 last_end_sum = dem::Vec3::Zero();
  for (std::size_t v = 0; v < mean_.size(); ++v) {
    report.dem_load += mean_[v];
    ramped[v] = report.ramp * mean_[v];
    last_end_sum += end_load_[v];
    end_load_[v] = 2.0 * ramped[v] - end_load_[v];
  }
  const AppliedLoad applied = apply_loads(wall_, body_, end_load_, report.exchange);
  report.fe_load = 0.5 * (last_end_sum + applied.fe_load);
  report.balance_error = applied.balance_error;
  report.fe_iterations = body_.advance().iterations;
  report.fe_time = body_.time();

  // FE -> DEM: the wall heads for the displacement predicted at the end of the next interval.
  std::vector<dem::Vec3> u, v;
  wall_.vertex_motion(u, v);
  for (std::size_t i = 0; i < u.size(); ++i) interface_work_ += ramped[i].dot(u[i] - u_[i]);
  u_ = std::move(u);
  report.interface_work = interface_work_;
  report.displacement = rms(u_);
  if (!std::isfinite(report.displacement))
    throw std::runtime_error(
        "coupling: exchange " + std::to_string(report.exchange) +
        ": the interface displacement is not finite (the dynamic scheme is unstable at this "
        "interval); valid: a shorter coupling/interval (docs/coupling.md, the stability bound)");
  if (sim_) {
    const double interval = T * time_step_, ahead = (T + 0.5) * time_step_;
    const std::vector<dem::Vec3>& at = sim_->meshes()[mesh_].world.vertices;
    std::vector<dem::Vec3> velocity(at.size());
    for (std::size_t i = 0; i < at.size(); ++i)
      velocity[i] = (reference_[i] + u_[i] + ahead * v[i] - at[i]) / interval;
    sim_->set_mesh_vertices(mesh_, std::vector<dem::Vec3>(at), velocity);
  }
  const fem::Energies energies = body_.energies();
  report.kinetic = energies.kinetic;
  report.strain = energies.strain;
  report.fe_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return report;
}

}  // namespace trackbed::coupling
