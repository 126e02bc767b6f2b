// Rolling resistance (PFC rolling resistance linear law) against the analytic motion of a ball.
#include <gtest/gtest.h>

#include <cmath>

#include "sim_builder.h"

namespace trackbed::dem {
namespace {

using testing::floor_at;
using testing::run_for;
using testing::table_with_pair;
using testing::test_material;

constexpr double kR = 0.02, kK = 1e7, kMuR = 0.3, kG = 9.81;

// A ball resting on a floor (overlap m g / k) under gravity `g`.
Simulation ball_on_floor(const Vec3& g, double v0) {
  Material m = test_material(kK, 1.0, kMuR);
  m.local_damping = 0;
  Particles p;
  const double mass = m.density * 4.0 / 3.0 * M_PI * kR * kR * kR;
  p.add_ball(Vec3(0, 0, kR - mass * kG / kK), kR, 0, m.density, 0);
  p.v[0] = Vec3(v0, 0, 0);
  p.w[0] = Vec3(0, v0 / kR, 0);  // rolling without slip
  SimulationSettings s;
  s.time_step = 2e-5;
  s.gravity = g;
  Simulation sim(table_with_pair(m, kK), std::move(p), s);
  sim.add_plane(floor_at(0));
  return sim;
}

TEST(RollingResistance, DecelerationAndStopDistance) {
  // M_r = mu_r R F_n opposes rolling: a = -(5/7) mu_r g, stop distance v0^2 / (2 |a|).
  const double v0 = 0.5, a = 5.0 / 7.0 * kMuR * kG;
  Simulation sim = ball_on_floor(Vec3(0, 0, -kG), v0);
  const double t_stop = v0 / a;
  run_for(sim, 0.5 * t_stop);
  // Half-way in time, v = v0/2: the deceleration is the analytic one to 1 %.
  EXPECT_NEAR(sim.particles().v[0].x(), 0.5 * v0, 0.01 * 0.5 * v0);
  run_for(sim, 0.6 * t_stop);
  const double stop = v0 * v0 / (2 * a);
  EXPECT_NEAR(sim.particles().x[0].x(), stop, 0.01 * stop);
  // At rest it stays: no creep over a further second (only the spring's elastic ~1e-9 m).
  const double x_rest = sim.particles().x[0].x();
  run_for(sim, 1.0);
  EXPECT_NEAR(sim.particles().x[0].x(), x_rest, 1e-6);
}

TEST(RollingResistance, InclineHoldsBelowMuRollsAbove) {
  // A tilted gravity stands for an incline. tan(theta) < mu_r: the ball stays; above, it rolls
  // with a = (5/7) g (sin(theta) - mu_r cos(theta)).
  for (double theta_deg : {10.0, 14.0, 20.0, 25.0}) {
    const double th = theta_deg * M_PI / 180;
    Simulation sim = ball_on_floor(Vec3(kG * std::sin(th), 0, -kG * std::cos(th)), 0);
    const double t = 0.3;
    run_for(sim, t);
    const double x = sim.particles().x[0].x();
    if (std::tan(th) < kMuR) {
      EXPECT_LT(std::abs(x), 1e-6) << theta_deg << " deg";
    } else {
      const double a = 5.0 / 7.0 * kG * (std::sin(th) - kMuR * std::cos(th));
      EXPECT_NEAR(x, 0.5 * a * t * t, 0.01 * 0.5 * a * t * t) << theta_deg << " deg";
    }
  }
}

}  // namespace
}  // namespace trackbed::dem
