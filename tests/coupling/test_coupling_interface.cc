// The DEM wall of an FE boundary and the maps across it (coupling/interface_wall.h), on an
// elastic box with roller sides and a fixed base, its top the wall:
//  - the wall has one vertex per FE corner of the top (no seams) and faces out of the box;
//  - the load map and the motion map are transposes: sum_v F_v . u_v = f . U = 2 x strain energy;
//  - a layer of frictionless balls resting on the deformable wall: the FE load is their weight,
//    and the area-mean settlement of the top is F H / (M A) with M = E (1 - nu) / ((1 + nu)
//    (1 - 2 nu)), exact for any distribution of the loads by reciprocity (the uniform pressure
//    p gives the uniform settlement p H / M, and the work of one load system on the other's
//    displacements is the same either way).
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include "balls_on_box.h"
#include "common/input_error.h"
#include "coupling/interface_wall.h"
#include "coupling/quasi_static_scheme.h"
#include "dem/engine/mesh_body.h"
#include "dem/engine/simulation.h"
#include "elastic_box.h"
#include "fem/boundary_interface.h"
#include "fem/elastic_body.h"
#include "fem/material.h"

namespace trackbed::coupling {
namespace {

using dem::Vec3;

using testing::BallsOnBox;
using testing::box;
using testing::mean_top_settlement;

TEST(CouplingInterface, WallHasOneVertexPerCornerAndFacesOut) {
  auto body = box();
  fem::BoundaryInterface top(*body, "zmax");
  const InterfaceWall wall(top, "zmax", MPI_COMM_WORLD);
  EXPECT_EQ(wall.num_vertices(), 25u);  // 5 x 5 corners of the 4 x 4 faces, merged
  EXPECT_EQ(wall.mesh().triangles.size(), 32u);
  for (std::size_t t = 0; t < wall.mesh().triangles.size(); ++t)
    EXPECT_NEAR(wall.mesh().triangle_normal(static_cast<int>(t)).z(), 1.0, 1e-12);
}

TEST(CouplingInterface, LoadAndMotionMapsAreTransposes) {
  // Random vertex loads: their work on the vertex displacements equals f . U = u^T K u, twice
  // the strain energy, to the direct solver's rounding (1e-10 relative).
  auto body = box();
  fem::BoundaryInterface top(*body, "zmax");
  InterfaceWall wall(top, "zmax", MPI_COMM_WORLD);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> load(-10, 10);
  std::vector<Vec3> f(wall.num_vertices());
  Vec3 total = Vec3::Zero();
  for (Vec3& v : f) total += (v = Vec3(load(rng), load(rng), load(rng) - 20));
  wall.apply_vertex_loads(f);
  const fem::LoadResultant resultant = body->interface_load_resultant({{0, 0, 0}});
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(resultant.force[c], total[c], 1e-12 * total.norm());
  body->solve_static();
  std::vector<Vec3> u, v;
  wall.vertex_motion(u, v);
  double work = 0;
  for (std::size_t i = 0; i < f.size(); ++i) work += f[i].dot(u[i]);
  const double strain = body->energies().strain;
  EXPECT_GT(strain, 0);
  EXPECT_NEAR(work, 2 * strain, 1e-10 * work);
}

TEST(CouplingInterface, RestingBallsLoadTheBoxByTheirWeight) {
  BallsOnBox c;
  // Two exchanges by hand: settle, average the vertex loads over 0.01 s, solve, move the wall.
  double applied = 0;
  const std::vector<Vec3> reference = c.wall.mesh().vertices;
  for (int exchange = 0; exchange < 2; ++exchange) {
    for (int i = 0; i < 3000; ++i) c.sim->step();
    c.sim->meshes()[c.mesh].deformation.take_mean_load();
    for (int i = 0; i < 1000; ++i) c.sim->step();
    const std::vector<Vec3> mean = c.sim->meshes()[c.mesh].deformation.take_mean_load();
    c.wall.apply_vertex_loads(mean);
    c.body->solve_static();
    applied = -c.body->interface_load_resultant({{0, 0, 0}}).force[2];
    std::vector<Vec3> u, v, x(reference.size());
    c.wall.vertex_motion(u, v);
    for (std::size_t k = 0; k < x.size(); ++k) x[k] = reference[k] + u[k];
    c.sim->set_mesh_vertices(c.mesh, x, std::vector<Vec3>(x.size(), Vec3::Zero()));
  }
  // At rest (damping 0.9 of critical for 0.08 s, 290 periods) the wall carries the weight:
  // 1e-6 is far above the residual of the decayed bounce.
  EXPECT_NEAR(applied, c.weight, 1e-6 * c.weight);
  const double expected = BallsOnBox::settlement_of(applied);
  EXPECT_NEAR(mean_top_settlement(c.top), expected, 1e-6 * expected);
}

// The quasi-static scheme on the same bed: exchanges of 500 steps until the wall's displacement
// is the FE body's for the bed's load (RMS residual 1e-6 of it), the load ramped over three.
// Returns the exchanges it took.
int converge(BallsOnBox& c, bool aitken) {
  QuasiStaticParameters p;
  p.interval_steps = 500;
  p.ramp_exchanges = 3;
  p.aitken = aitken;
  p.tolerance = 1e-6;
  QuasiStaticScheme scheme(*c.sim, c.mesh, *c.body, c.wall, p);
  auto exchange = [&] {
    for (int i = 0; i < scheme.interval_steps(); ++i) c.sim->step();
    return scheme.exchange();
  };
  for (int k = 1; k <= 60; ++k) {
    const ExchangeReport r = exchange();
    EXPECT_LE(r.balance_error, 1e-10);  // (the scheme throws above it)
    if (r.converged) {
      // The mean load of an exchange includes the balls' change of momentum, 25 m dv / T, where
      // the wall's velocity changed at its start (1e-7 m/s at the last steps here: 2e-6 of the
      // weight). Two more exchanges: in the second the wall's velocity changes by under
      // 1e-10 m/s, 1e-9 of the weight. The bed's load is then its weight, and the wall sits
      // where the FE body puts it: the area-mean settlement of the top is F H / (M A).
      exchange();
      const ExchangeReport rest = exchange();
      EXPECT_TRUE(rest.converged);
      EXPECT_NEAR(rest.fe_load.z(), -c.weight, 1e-6 * c.weight);
      const double expected = BallsOnBox::settlement_of(-rest.fe_load.z());
      EXPECT_NEAR(mean_top_settlement(c.top), expected, 1e-6 * expected);
      return k;
    }
  }
  ADD_FAILURE() << "no convergence in 60 exchanges";
  return 0;
}

TEST(CouplingInterface, QuasiStaticSchemeConvergesAitkenFaster) {
  BallsOnBox fixed, dynamic;
  const int plain = converge(fixed, false), aitken = converge(dynamic, true);
  RecordProperty("exchanges_fixed_relaxation", plain);
  RecordProperty("exchanges_aitken", aitken);
  EXPECT_LT(aitken, plain);
}

TEST(CouplingInterface, QuasiStaticSchemeRefusesBadParameters) {
  QuasiStaticParameters p;
  p.relaxation = 1.5;
  EXPECT_THROW(p.validate(), InputError);
  p = QuasiStaticParameters();
  p.interval_steps = 0;
  EXPECT_THROW(p.validate(), InputError);
}

}  // namespace
}  // namespace trackbed::coupling
