#include "coupling/quasi_static_scheme.h"

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

namespace {

// The smallest Aitken factor, as a fraction of the first: the secant reads the scatter of a bed's
// load from one interval to the next as a change of the fixed point and can drive the factor to
// nothing, freezing the wall while the load still changes.
constexpr double kSmallestRelaxationFraction = 0.1;
// Exchanges in a row whose residual exceeds the displacement before the run stops as diverged.
constexpr int kDivergingExchanges = 10;

}  // namespace

void QuasiStaticParameters::validate() const {
  if (interval_steps < 1)
    throw InputError("coupling: interval = " + std::to_string(interval_steps) +
                     " DEM steps; valid: an integer >= 1");
  if (!(relaxation > 0 && relaxation <= 1))
    throw InputError("coupling: relaxation = " + number_text(relaxation) + "; valid: (0, 1]");
  if (!(tolerance > 0 && std::isfinite(tolerance)))
    throw InputError("coupling: tolerance = " + number_text(tolerance) + "; valid: > 0");
  if (ramp_exchanges < 1)
    throw InputError("coupling: ramp = " + std::to_string(ramp_exchanges) +
                     " exchanges; valid: an integer >= 1");
}

QuasiStaticScheme::QuasiStaticScheme(dem::Simulation& sim, int mesh, fem::ElasticBody& body,
                                     InterfaceWall& wall, const QuasiStaticParameters& parameters)
    : sim_(&sim), mesh_(mesh), body_(body), wall_(wall), parameters_(parameters) {
  check_interface_mesh(sim, mesh, wall, "QuasiStaticScheme");
  start(sim.time_step());
}

QuasiStaticScheme::QuasiStaticScheme(fem::ElasticBody& body, InterfaceWall& wall,
                                     const QuasiStaticParameters& parameters)
    : sim_(nullptr), mesh_(-1), body_(body), wall_(wall), parameters_(parameters) {
  start(0);
}

void QuasiStaticScheme::start(double time_step) {
  parameters_.validate();
  MPI_Bcast(&time_step, 1, MPI_DOUBLE, 0, wall_.communicator());
  interval_seconds_ = parameters_.interval_steps * time_step;
  reference_ = wall_.mesh().vertices;
  u_.assign(reference_.size(), dem::Vec3::Zero());
  loads_.assign(reference_.size(), dem::Vec3::Zero());
}

QuasiStaticState QuasiStaticScheme::state() const {
  return {exchanges_, last_relaxation_, u_, last_residual_, converged_, diverging_};
}

void QuasiStaticScheme::restore(QuasiStaticState state) {
  if (state.displacement.size() != u_.size() ||
      (!state.last_residual.empty() && state.last_residual.size() != u_.size()) ||
      state.exchanges < 0)
    throw InputError("coupling state: " + std::to_string(state.displacement.size()) +
                     " interface vertices where the interface has " + std::to_string(u_.size()) +
                     "; valid: a checkpoint of the same case");
  exchanges_ = state.exchanges;
  last_relaxation_ = state.last_relaxation;
  u_ = std::move(state.displacement);
  last_residual_ = std::move(state.last_residual);
  converged_ = state.converged;
  diverging_ = state.diverging;
}

double QuasiStaticScheme::next_relaxation(const std::vector<dem::Vec3>& r) {
  // Aitken: w_k = -w_k-1 r_k-1 . (r_k - r_k-1) / |r_k - r_k-1|^2, the secant estimate of the
  // factor that would have cancelled the residual along its last change. Not while the load
  // ramps: the fixed point itself moves then, and the secant would measure the ramp.
  if (!parameters_.aitken || exchanges_ <= parameters_.ramp_exchanges)
    return parameters_.relaxation;
  std::vector<dem::Vec3> change(r.size());
  for (std::size_t i = 0; i < r.size(); ++i) change[i] = r[i] - last_residual_[i];
  const double squared = dot(change, change);
  if (!(squared > 0)) return last_relaxation_;
  const double w = -last_relaxation_ * dot(last_residual_, change) / squared;
  return std::clamp(w, kSmallestRelaxationFraction * parameters_.relaxation, 1.0);
}

ExchangeReport QuasiStaticScheme::exchange() {
  ExchangeReport report;
  report.exchange = ++exchanges_;
  const auto start = std::chrono::steady_clock::now();

  // DEM -> FE: the mean vertex loads (from the DEM's process to all), ramped.
  take_mean_loads(sim_, mesh_, wall_, loads_);
  report.ramp = std::min(1.0, static_cast<double>(exchanges_) / parameters_.ramp_exchanges);
  report.dem_load = dem::Vec3::Zero();
  std::vector<dem::Vec3> loads = loads_;
  for (dem::Vec3& f : loads) {
    report.dem_load += f;
    f *= report.ramp;
  }
  const AppliedLoad applied = apply_loads(wall_, body_, loads, report.exchange);
  report.fe_load = applied.fe_load;
  report.balance_error = applied.balance_error;
  report.fe_iterations = body_.solve_static().iterations;

  // FE -> DEM: the relaxed interface displacement, reached over the next interval.
  std::vector<dem::Vec3> fe_u, fe_v, r(u_.size());
  wall_.vertex_motion(fe_u, fe_v);
  for (std::size_t i = 0; i < u_.size(); ++i) r[i] = fe_u[i] - u_[i];
  const double work = dot(loads_, fe_u);  // F . u~: the unramped load's work
  report.load_work = report.ramp * work;
  report.relaxation = next_relaxation(r);
  report.residual = rms(r);
  report.work_residual = work != 0 ? std::abs(dot(loads_, r) / work) : 0.0;
  std::vector<dem::Vec3> at(u_.size()), velocity(u_.size());
  for (std::size_t i = 0; i < u_.size(); ++i) {
    at[i] = reference_[i] + u_[i];  // where the last interval's motion was to end
    const dem::Vec3 step = report.relaxation * r[i];
    velocity[i] = step / interval_seconds_;
    u_[i] += step;
  }
  if (sim_) sim_->set_mesh_vertices(mesh_, at, velocity);
  last_residual_ = std::move(r);
  last_relaxation_ = report.relaxation;
  report.displacement = rms(u_);
  if (!std::isfinite(report.displacement))
    throw std::runtime_error("coupling: exchange " + std::to_string(report.exchange) +
                             ": the interface displacement is not finite (the coupling diverged)");
  report.converged = report.ramp == 1.0 && report.work_residual <= parameters_.tolerance;
  converged_ = report.converged;
  // A residual above the displacement itself, exchange after exchange once the load is complete,
  // is an oscillation growing between the bed and the subgrade, not scatter.
  diverging_ = report.ramp == 1.0 && report.work_residual > 1 ? diverging_ + 1 : 0;
  if (diverging_ >= kDivergingExchanges)
    throw std::runtime_error(
        "coupling: exchange " + std::to_string(report.exchange) +
        ": the interface residual has exceeded the displacement for " +
        std::to_string(kDivergingExchanges) +
        " exchanges (the staggered scheme diverges); valid: a lower coupling/relaxation, "
        "coupling/aitken = true, or a longer coupling/interval");
  report.fe_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return report;
}

}  // namespace trackbed::coupling
