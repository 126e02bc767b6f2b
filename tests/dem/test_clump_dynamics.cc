// Rigid-body dynamics of clumps: free rotation of an asymmetric body, and the rotation about a
// principal axis the free rotation is composed of.
#include <gtest/gtest.h>

#include <random>

#include "dem/engine/clump_template.h"
#include "dem/engine/rigid_rotation.h"
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

TEST(ClumpDynamics, SinCosSeriesAgreesWithLibm) {
  // The Taylor polynomials below |x| = 0.03 and libm above: both to a few units of the last place.
  for (double x = -0.05; x <= 0.05; x += 1.37e-4)
    for (const double y : {x, x * 1e-3, x * 1e-6}) {
      double s, c;
      sin_cos(y, s, c);
      EXPECT_NEAR(s, std::sin(y), 4e-16 * std::abs(std::sin(y))) << y;
      EXPECT_NEAR(c, std::cos(y), 4e-16) << y;
    }
}

TEST(ClumpDynamics, PrincipalAxisRotationIsTheGeneralOne) {
  // The written-out rotation about e_k against the same rotation by Eigen's general quaternion
  // algebra (q <- q r, pi <- r^T pi, r = rot(e_k, h pi_k / I_k)), for random states and angles
  // from 1e-7 to 0.3 rad (both sides of the series' bound): the same to round-off.
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  const Vec3 I(0.7, 1.1, 1.9);
  for (int trial = 0; trial < 300; ++trial) {
    const Quat q0 = Quat(u(rng), u(rng), u(rng), u(rng)).normalized();
    const int k = trial % 3;
    const double angle = std::pow(10.0, -7 + 6.5 * (trial % 17) / 16.0) * (trial % 2 ? 1 : -1);
    Vec3 pi0(u(rng), u(rng), u(rng));
    pi0[k] = 1.0;
    const double h = angle * I[k] / pi0[k];
    Quat q = q0;
    Vec3 pi = pi0;
    rotate_about_principal_axis(k, h, q, pi, I.cwiseInverse());
    const Quat r(Eigen::AngleAxisd(angle, Vec3::Unit(k)));
    const Quat q_ref = q0 * r;
    const Vec3 pi_ref = r.conjugate() * pi0;
    EXPECT_LT((q.coeffs() - q_ref.coeffs()).norm(), 1e-15) << "trial " << trial;
    EXPECT_LT((pi - pi_ref).norm(), 1e-15 * pi0.norm()) << "trial " << trial;
  }
}

}  // namespace
}  // namespace trackbed::dem
