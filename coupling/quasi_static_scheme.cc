#include "coupling/quasi_static_scheme.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>

#include "common/input_error.h"
#include "common/number_text.h"

namespace trackbed::coupling {

namespace {

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

// The smallest relaxation Aitken's factor may take: below it the interface would hardly move.
constexpr double kSmallestRelaxation = 1e-3;

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
    : sim_(sim), mesh_(mesh), body_(body), wall_(wall), parameters_(parameters) {
  parameters_.validate();
  if (mesh < 0 || mesh >= static_cast<int>(sim.meshes().size()) || !sim.meshes()[mesh].deformable ||
      sim.meshes()[mesh].world.vertices.size() != wall.num_vertices())
    throw std::invalid_argument(
        "QuasiStaticScheme: mesh " + std::to_string(mesh) +
        " is not the deformable mesh of the interface wall (same vertices, same order)");
  reference_ = wall.mesh().vertices;
  u_.assign(reference_.size(), dem::Vec3::Zero());
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
  return std::clamp(w, kSmallestRelaxation, 1.0);
}

ExchangeReport QuasiStaticScheme::exchange() {
  ExchangeReport report;
  report.exchange = ++exchanges_;
  const auto start = std::chrono::steady_clock::now();

  // DEM -> FE: the mean vertex loads, ramped.
  std::vector<dem::Vec3> loads = sim_.meshes()[mesh_].deformation.take_mean_load();
  report.ramp = std::min(1.0, static_cast<double>(exchanges_) / parameters_.ramp_exchanges);
  report.dem_load = dem::Vec3::Zero();
  for (dem::Vec3& f : loads) {
    report.dem_load += f;
    f *= report.ramp;
  }
  wall_.apply_vertex_loads(loads);
  const fem::LoadResultant resultant = body_.interface_load_resultant({{0, 0, 0}});
  report.fe_load = dem::Vec3(resultant.force[0], resultant.force[1], resultant.force[2]);
  const dem::Vec3 expected = report.ramp * report.dem_load;
  report.balance_error = expected.norm() > 0 ? (report.fe_load - expected).norm() / expected.norm()
                                             : report.fe_load.norm();
  if (!(report.balance_error <= 1e-10))
    throw std::runtime_error("coupling: exchange " + std::to_string(report.exchange) +
                             ": the FE load differs from the DEM's by " +
                             number_text(report.balance_error) + " of it (limit 1e-10)");
  report.fe_iterations = body_.solve_static().iterations;

  // FE -> DEM: the relaxed interface displacement, reached over the next interval.
  std::vector<dem::Vec3> fe_u, fe_v, r(u_.size());
  wall_.vertex_motion(fe_u, fe_v);
  for (std::size_t i = 0; i < u_.size(); ++i) r[i] = fe_u[i] - u_[i];
  report.relaxation = next_relaxation(r);
  report.residual = rms(r);
  std::vector<dem::Vec3> at(u_.size()), velocity(u_.size());
  const double interval = parameters_.interval_steps * sim_.time_step();
  for (std::size_t i = 0; i < u_.size(); ++i) {
    at[i] = reference_[i] + u_[i];  // where the last interval's motion was to end
    const dem::Vec3 step = report.relaxation * r[i];
    velocity[i] = step / interval;
    u_[i] += step;
  }
  sim_.set_mesh_vertices(mesh_, at, velocity);
  last_residual_ = std::move(r);
  last_relaxation_ = report.relaxation;
  report.displacement = rms(u_);
  if (!std::isfinite(report.displacement))
    throw std::runtime_error("coupling: exchange " + std::to_string(report.exchange) +
                             ": the interface displacement is not finite (the coupling diverged)");
  report.converged =
      report.ramp == 1.0 && report.residual <= parameters_.tolerance * report.displacement;
  report.fe_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return report;
}

}  // namespace trackbed::coupling
