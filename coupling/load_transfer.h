// DEM -> FE, the step every scheme shares (docs/coupling.md, "The interface and its maps"): the
// bed's mean vertex loads of the last interval, taken on the DEM's process and sent to every
// process, and loads applied to the FE body with the check that the FE load resultant equals
// their sum (the load map conserves force).
#pragma once

#include <vector>

#include "coupling/interface_wall.h"
#include "dem/engine/simulation.h"
#include "dem/engine/types.h"
#include "fem/elastic_body.h"

namespace trackbed::coupling {

// Throws std::invalid_argument naming `scheme` unless sim.meshes()[mesh] is the deformable mesh
// built from wall.mesh() (its vertices in the same order).
void check_interface_mesh(const dem::Simulation& sim, int mesh, const InterfaceWall& wall,
                          const char* scheme);

// The mean vertex loads of mesh `mesh` over the interval since the last call (N), on every
// process of the wall's communicator; `sim` is null on the processes without the DEM, whose
// `loads` hold the count of wall vertices on entry. Collective.
void take_mean_loads(dem::Simulation* sim, int mesh, const InterfaceWall& wall,
                     std::vector<dem::Vec3>& loads);

// What the FE body was given.
struct AppliedLoad {
  dem::Vec3 sum;             // sum of the vertex loads applied, N
  dem::Vec3 fe_load;         // the FE load resultant, N
  double balance_error = 0;  // |fe_load - sum| / |sum| (|fe_load| in N for a zero sum)
};

// Replaces the body's interface load by `loads` (N, one per wall vertex, the same on every
// process). Collective. Throws std::runtime_error naming exchange `exchange` when the FE load
// resultant differs from their sum by more than 1e-10 of it.
AppliedLoad apply_loads(InterfaceWall& wall, fem::ElasticBody& body,
                        const std::vector<dem::Vec3>& loads, int exchange);

double rms(const std::vector<dem::Vec3>& v);
double dot(const std::vector<dem::Vec3>& a, const std::vector<dem::Vec3>& b);

}  // namespace trackbed::coupling
