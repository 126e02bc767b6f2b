// The dynamic staggered scheme of a DEM bed on an elastic FE body (docs/coupling.md, "Dynamic
// staggered scheme"): for loads that change fast against the FE body's periods (cyclic loading,
// impacts), where its inertia matters.
//
// The FE body steps with Newmark's average-acceleration rule, H = T dt per step (T =
// interval_steps DEM steps of dt), on a grid half a DEM step behind the DEM's: the loads of the
// force passes n = s, ..., s + T - 1 are, by the DEM's leapfrog, the impulses over
// [t_s - dt/2, t_s+T - dt/2], so the FE body steps over that interval with their mean F^ as its
// mean load. Each exchange, after the caller's T DEM steps:
//   1. F^ (times the ramp factor min(1, k / ramp_exchanges) at exchange k) becomes the FE body's
//      mean load over its step: Newmark's rule sees a step's loads only through
//      (f_n + f_n+1) / 2, so the end load f_n+1 = 2 F^ - f_n gives it exactly, and the body's
//      energy changes by F^ . (u_n+1 - u_n) less its damping: the work the bed did;
//   2. the FE body advances one step to u_n+1, v_n+1 at the wall's vertices;
//   3. the wall's vertices, where they are, get the velocity that takes them over the next T DEM
//      steps to the FE displacement predicted for the end of them, u_n+1 + v_n+1 (T + 1/2) dt.
// The prediction makes the scheme explicit in the bed's contacts: it is stable for
// H <= Omega*(zeta) sqrt(M_v / k_v), with M_v a wall vertex's FE mass, k_v the stiffness of the
// contacts on it and zeta their damping ratio (docs/coupling.md derives the bound). Every
// exchange checks that the FE load resultant equals the applied vertex loads (relative 1e-10).
#pragma once

#include <vector>

#include "coupling/interface_wall.h"
#include "coupling/parameters.h"
#include "dem/engine/simulation.h"
#include "fem/elastic_body.h"

namespace trackbed::coupling {

// What one exchange did.
struct DynamicExchangeReport {
  int exchange = 0;           // 1, 2, ...
  double fe_time = 0;         // s since the scheme started, the FE body's (half a DEM step behind)
  double ramp = 0;            // load factor applied
  dem::Vec3 dem_load;         // sum of the mean vertex loads F^, N
  dem::Vec3 fe_load;          // the FE body's mean load resultant over its step, N (ramp dem_load)
  double balance_error = 0;   // of the FE load resultant against the applied loads
  double displacement = 0;    // RMS |u_n+1| over the wall's vertices, m
  double kinetic = 0;         // FE kinetic energy v^T M v / 2, J
  double strain = 0;          // FE strain energy u^T K u / 2, J
  double interface_work = 0;  // work of the mean loads on the FE body since the start, J
  unsigned int fe_iterations = 0;
  double fe_seconds = 0;  // the FE step and the maps
};

class DynamicScheme {
 public:
  // On the process with the DEM (rank 0 of the wall's communicator). `mesh`: the index in
  // sim.meshes() of the deformable mesh built from wall.mesh() (its vertices in the same order,
  // at the reference positions). The FE body must be set up, unloaded and at zero displacement
  // (displacements are measured from the geostatic state, its own gravity off); the scheme starts
  // its Newmark stepping at rest. Collective over the wall's communicator, with the constructor
  // below on the other processes.
  DynamicScheme(dem::Simulation& sim, int mesh, fem::ElasticBody& body, InterfaceWall& wall,
                const DynamicParameters& parameters);
  // On a process that has FE cells but no DEM: it takes part in every exchange.
  DynamicScheme(fem::ElasticBody& body, InterfaceWall& wall, const DynamicParameters& parameters);

  // The exchange after the caller's interval_steps DEM steps (steps 1 to 3 above); collective.
  // Throws std::runtime_error when the load balance check fails or the interface displacement is
  // not finite (an interval above the stability bound).
  DynamicExchangeReport exchange();
  int interval_steps() const { return parameters_.interval_steps; }
  int exchanges() const { return exchanges_; }
  // The last exchange's mean vertex loads (N, before the ramp).
  const std::vector<dem::Vec3>& vertex_loads() const { return mean_; }

 private:
  void start(double time_step);

  dem::Simulation* sim_;  // null on the processes without the DEM
  int mesh_;
  fem::ElasticBody& body_;
  InterfaceWall& wall_;
  DynamicParameters parameters_;
  double time_step_ = 0;              // the DEM's, s
  std::vector<dem::Vec3> reference_;  // the wall's vertices at zero displacement
  std::vector<dem::Vec3> mean_;       // F^ of the last interval
  std::vector<dem::Vec3> end_load_;   // f_n, the FE body's load at the end of its last step
  std::vector<dem::Vec3> u_;          // FE displacement at the wall's vertices, u_n
  double interface_work_ = 0;
  int exchanges_ = 0;
};

}  // namespace trackbed::coupling
