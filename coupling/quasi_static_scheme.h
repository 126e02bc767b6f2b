// The quasi-static staggered scheme of a DEM bed on an elastic FE body (docs/coupling.md,
// "Quasi-static staggered scheme"): for the push tests, where the bed moves slowly and the FE
// body's inertia does not matter.
//
// Each exchange, of T = interval_steps DEM steps:
//   1. the DEM runs T steps (the caller steps it, with its outputs, between exchanges), the
//      interface wall moving at the velocities set at the last exchange;
//   2. the wall's vertex loads averaged over those steps (impulses over T) are applied to the FE
//      body, times the ramp factor min(1, k / ramp_exchanges) at exchange k = 1, 2, ..., so a bed
//      is not dropped onto a foundation that jumps at the start;
//   3. the FE body is solved: the vertex displacements u~ it gives for those loads;
//   4. the interface displacement is relaxed, u_k+1 = u_k + w_k (u~ - u_k), with w_k fixed, or
//      Aitken's dynamic factor (Kuettler and Wall 2008) from the last two residuals
//      r = u~ - u_k once the ramp is complete;
//   5. the wall's vertices get velocities (u_k+1 - u_k) / T, so they reach u_k+1 at the end of
//      the next exchange's DEM steps.
// The scheme has converged when |r| <= tolerance |u_k+1| (root mean square over the vertices)
// with the ramp complete. The mean load of an exchange includes the bed's change of momentum
// over it, sum m dv / T, where the wall's velocity changed at its start: quasi-static means T
// long against that. Every exchange also checks that the FE load resultant equals the sum of
// the DEM's mean vertex loads (the load map conserves force; relative 1e-10).
#pragma once

#include <vector>

#include "coupling/interface_wall.h"
#include "dem/engine/simulation.h"
#include "fem/elastic_body.h"

namespace trackbed::coupling {

struct QuasiStaticParameters {
  int interval_steps = 100;  // DEM steps per exchange, >= 1
  double relaxation = 0.5;   // the first (or, without Aitken, every) relaxation factor, (0, 1]
  bool aitken = true;        // Aitken's dynamic relaxation after the first exchange
  double tolerance = 1e-3;   // converged at |r| <= tolerance |u| (RMS over the vertices)
  int ramp_exchanges = 5;    // the load reaches its full value at this exchange, >= 1
  // Throws InputError naming the parameter for a value outside its range.
  void validate() const;
};

// What one exchange did.
struct ExchangeReport {
  int exchange = 0;          // 1, 2, ...
  double ramp = 0;           // load factor applied
  dem::Vec3 dem_load;        // sum of the mean vertex loads, N (what the bed put on the wall)
  dem::Vec3 fe_load;         // FE load resultant, N (ramp times dem_load)
  double balance_error = 0;  // |fe_load - ramp dem_load| / |ramp dem_load|
  double residual = 0;       // RMS |u~ - u_k|, m
  double displacement = 0;   // RMS |u_k+1|, m
  double relaxation = 0;     // w_k used
  bool converged = false;
  unsigned int fe_iterations = 0;
  double fe_seconds = 0;  // the FE solve and the maps
};

class QuasiStaticScheme {
 public:
  // `mesh`: the index in sim.meshes() of the deformable mesh built from wall.mesh() (its
  // vertices in the same order, at the reference positions). The FE body must be set up and
  // loaded only through the interface (its own gravity off: displacements are measured from the
  // geostatic state).
  QuasiStaticScheme(dem::Simulation& sim, int mesh, fem::ElasticBody& body, InterfaceWall& wall,
                    const QuasiStaticParameters& parameters);

  // The exchange after the caller's interval_steps DEM steps (steps 2 to 5 above). Throws
  // std::runtime_error when the load balance check fails or the interface displacement is not
  // finite (a diverging coupling).
  ExchangeReport exchange();
  int interval_steps() const { return parameters_.interval_steps; }

  const std::vector<dem::Vec3>& interface_displacement() const { return u_; }

 private:
  double next_relaxation(const std::vector<dem::Vec3>& r);

  dem::Simulation& sim_;
  int mesh_;
  fem::ElasticBody& body_;
  InterfaceWall& wall_;
  QuasiStaticParameters parameters_;
  std::vector<dem::Vec3> reference_;  // the wall's vertices at zero displacement
  std::vector<dem::Vec3> u_;          // interface displacement the wall moves to
  std::vector<dem::Vec3> last_residual_;
  double last_relaxation_ = 0;
  int exchanges_ = 0;
};

}  // namespace trackbed::coupling
