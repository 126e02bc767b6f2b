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
#include "coupling/parameters.h"
#include "dem/engine/simulation.h"
#include "fem/elastic_body.h"

namespace trackbed::coupling {

// What one exchange did.
struct ExchangeReport {
  int exchange = 0;          // 1, 2, ...
  double ramp = 0;           // load factor applied
  dem::Vec3 dem_load;        // sum of the mean vertex loads, N (what the bed put on the wall)
  dem::Vec3 fe_load;         // FE load resultant, N (ramp times dem_load)
  double balance_error = 0;  // |fe_load - ramp dem_load| / |ramp dem_load|
  double residual = 0;       // RMS |u~ - u_k|, m
  double work_residual = 0;  // |F . (u~ - u_k)| / |F . u~|, F the mean vertex loads
  double displacement = 0;   // RMS |u_k+1|, m
  double relaxation = 0;     // w_k used
  double load_work = 0;      // f . U = sum_v (ramp F_v) . u~_v, J: twice the FE strain energy
  bool converged = false;
  unsigned int fe_iterations = 0;
  double fe_seconds = 0;  // the FE solve and the maps
};

// The relaxation's memory, all a checkpoint needs of the scheme (with the FE displacement).
struct QuasiStaticState {
  int exchanges = 0;
  double last_relaxation = 0;
  std::vector<dem::Vec3> displacement;   // u_k, the interface displacement the wall moves to
  std::vector<dem::Vec3> last_residual;  // r_k-1 (Aitken)
  bool converged = false;                // the last exchange's verdict
  int diverging = 0;                     // exchanges in a row with a residual above u
};

class QuasiStaticScheme {
 public:
  // On the process with the DEM (rank 0 of the wall's communicator). `mesh`: the index in
  // sim.meshes() of the deformable mesh built from wall.mesh() (its vertices in the same order,
  // at the reference positions). The FE body must be set up and loaded only through the
  // interface (its own gravity off: displacements are measured from the geostatic state).
  // Collective over the wall's communicator, with the constructor below on the other processes.
  QuasiStaticScheme(dem::Simulation& sim, int mesh, fem::ElasticBody& body, InterfaceWall& wall,
                    const QuasiStaticParameters& parameters);
  // On a process that has FE cells but no DEM: it takes part in every exchange.
  QuasiStaticScheme(fem::ElasticBody& body, InterfaceWall& wall,
                    const QuasiStaticParameters& parameters);

  // The exchange after the caller's interval_steps DEM steps (steps 2 to 5 above); collective,
  // the DEM's loads sent to every process. Throws std::runtime_error when the load balance check
  // fails or the interface displacement is not finite (a diverging coupling).
  ExchangeReport exchange();
  // The last exchange's mean vertex loads (N, before the ramp).
  const std::vector<dem::Vec3>& vertex_loads() const { return loads_; }
  int interval_steps() const { return parameters_.interval_steps; }

  const std::vector<dem::Vec3>& interface_displacement() const { return u_; }
  // The last exchange converged (false before the first).
  bool converged() const { return converged_; }
  int exchanges() const { return exchanges_; }
  QuasiStaticState state() const;
  // Continues from state() of the same scheme (the DEM's wall vertices come with its own state).
  // Throws InputError for a state of another interface.
  void restore(QuasiStaticState state);

 private:
  void start(double time_step);
  double next_relaxation(const std::vector<dem::Vec3>& r);

  dem::Simulation* sim_;  // null on the processes without the DEM
  int mesh_;
  fem::ElasticBody& body_;
  InterfaceWall& wall_;
  QuasiStaticParameters parameters_;
  double interval_seconds_ = 0;       // T times the DEM step
  std::vector<dem::Vec3> reference_;  // the wall's vertices at zero displacement
  std::vector<dem::Vec3> loads_;
  std::vector<dem::Vec3> u_;  // interface displacement the wall moves to
  std::vector<dem::Vec3> last_residual_;
  double last_relaxation_ = 0;
  int exchanges_ = 0;
  bool converged_ = false;
  int diverging_ = 0;
};

}  // namespace trackbed::coupling
