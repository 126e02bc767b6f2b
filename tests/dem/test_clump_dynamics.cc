// Rigid-body dynamics of clumps: free rotation of an asymmetric body.
#include <gtest/gtest.h>

#include "dem/clump_template.h"
#include "sim_builder.h"

namespace trackbed::dem {
namespace {

TEST(ClumpDynamics, TorqueFreeRotationConservesEnergyAndMomentum) {
  // Three spheres in an L: three distinct principal moments. Spun about an axis off every
  // principal axis, it tumbles (Euler's equations); |L| and L itself must stay fixed in the
  // world and the energy constant. The splitting keeps |L| to round-off and the energy error
  // bounded by O(dt^2 w^2): with w dt = 2e-3 rad, 1e-5 relative is a safe bound.
  const ClumpTemplate t = make_clump_template(
      "L", {{Vec3(0, 0, 0), 0.02}, {Vec3(0.03, 0, 0), 0.015}, {Vec3(0, 0.025, 0.005), 0.012}});
  ASSERT_LT(t.principal_moments[0] * 1.05, t.principal_moments[1]);
  ASSERT_LT(t.principal_moments[1] * 1.05, t.principal_moments[2]);
  Material m = testing::test_material();
  MaterialTable table;
  table.add(m);
  Particles p;
  p.add_clump(t, Vec3::Zero(), Quat::Identity(), 0, m.density, 0);
  p.w[0] = Vec3(3.0, 20.0, 1.0);  // near the unstable middle axis: strong tumbling
  SimulationSettings s;
  s.time_step = 1e-4;
  s.gravity = Vec3::Zero();
  Simulation sim(std::move(table), std::move(p), s);
  sim.setup();
  const Vec3 L0 = sim.particles().L[0];
  const double E0 = sim.particles().kinetic_energy();
  Vec3 w_min = sim.particles().w[0], w_max = w_min;
  for (int i = 0; i < 20000; ++i) {
    sim.step();
    w_min = w_min.cwiseMin(sim.particles().w[0]);
    w_max = w_max.cwiseMax(sim.particles().w[0]);
  }
  EXPECT_LT((sim.particles().L[0] - L0).norm(), 1e-12 * L0.norm());
  EXPECT_NEAR(sim.particles().kinetic_energy(), E0, 1e-5 * E0);
  // The world angular velocity really changed (the body tumbled), so the test is not trivial.
  EXPECT_GT((w_max - w_min).norm(), 5.0);
  // L = I_world w holds at the end: angular velocity and momentum are consistent.
  const Vec3 Lw = sim.particles().world_inertia(0) * sim.particles().w[0];
  EXPECT_LT((Lw - L0).norm(), 1e-9 * L0.norm());
}

}  // namespace
}  // namespace trackbed::dem
