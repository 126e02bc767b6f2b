// The critical time step with dashpots (docs/theory.md, "Critical timestep"): the leapfrog update
// takes a contact's dashpot force from the velocity half a step old, so a degree of freedom of
// mass m on a spring k with a dashpot c is stable only for
//   dt < 2 (sqrt(1 + zeta^2) - zeta) sqrt(m / k),   zeta = c / (2 sqrt(m k)),
// and the engine's estimate is half that, summed per body like PFC's undamped sqrt(m / k). These
// tests check the limit where it is exact (one contact, one mode) at 0.99 and 1.01 of it, the
// estimate against it, and a bed that the undamped estimate let blow up.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>

#include "sim_builder.h"

namespace trackbed::dem {
namespace {

using testing::floor_at;
using testing::test_material;

constexpr double kR = 0.02, kK = 1e7;

double damped_factor(double zeta) {
  return std::sqrt(1 + zeta * zeta) - zeta;
}

double ball_mass() {
  return 2800 * 4.0 / 3.0 * M_PI * kR * kR * kR;
}

// A ball of radius R touching the floor z = -R with one contact pair of the given properties,
// its centre at z (near 0).
Simulation ball_on_floor(const ContactProperties& pair, double dt, double z, const Vec3& gravity) {
  Particles p;
  p.add_ball(Vec3(0, 0, z), kR, 0, 2800, 0);
  MaterialTable table;
  table.add(test_material(kK));
  table.set_pair(0, 0, pair);
  SimulationSettings s;
  s.time_step = dt;
  s.allow_supercritical_step = true;
  s.gravity = gravity;
  Simulation sim(std::move(table), std::move(p), s);
  sim.add_plane(floor_at(-kR));
  return sim;
}

// Largest |value| over the last 20 of `steps` steps, `value` read after each step.
template <class Value>
double late_amplitude(Simulation& sim, int steps, Value value) {
  double largest = 0;
  for (int i = 0; i < steps; ++i) {
    sim.step();
    if (i >= steps - 20) largest = std::max(largest, std::abs(value(sim)));
  }
  return largest;
}

// Normal dashpot, normal mode: the limit is exact. The ball starts 1e-9 of its static overlap
// away from rest; the mode it excites changes by the spectral radius each step, which at 0.99
// (1.01) of the limit is at most 0.972 (at least 1.028) for zeta in [0.3, 1]: over 250 steps a
// factor below 1/1300 (above 1100). The test asks for 1/100 and 100. The perturbation stays
// below 0.02 of the static overlap (at most 1.6e7 times 1e-9), so the never-tensile cap of the
// normal force does not act, and 2,600 times the resolution of the overlap (the floor's distance
// resolves 3.5e-18 m at 0.02 m): a soft contact, 1e5 N/m, makes the static overlap 9.2e-6 m.
TEST(CriticalStep, NormalDashpotLimitIsExactOnOneContact) {
  const double k = 1e5, m = ball_mass(), omega = std::sqrt(k / m), g = 9.81;
  for (double zeta : {0.3, 0.7, 1.0}) {
    ContactProperties pair;
    pair.kn = k;
    pair.normal_damping_ratio = zeta;  // k_s = 0: the normal mode alone
    const double limit = 2 * damped_factor(zeta) / omega;
    const double rest = -m * g / k, start = 1e-9 * m * g / k;
    const Vec3 gravity(0, 0, -g);
    {
      Simulation probe = ball_on_floor(pair, 1e-7, rest, gravity);
      probe.setup();
      EXPECT_NEAR(probe.critical_timestep(), limit / 2, 1e-12 * limit) << "zeta " << zeta;
    }
    for (double fraction : {0.99, 1.01}) {
      Simulation sim = ball_on_floor(pair, fraction * limit, rest + start, gravity);
      sim.setup();
      const double amplitude = late_amplitude(
          sim, 250, [&](const Simulation& s) { return s.particles().x[0].z() - rest; });
      if (fraction < 1)
        EXPECT_LT(amplitude, start / 100) << "zeta " << zeta;
      else
        EXPECT_GT(amplitude, 100 * start) << "zeta " << zeta;
    }
  }
}

// Shear dashpot, the mode that blew up beds: the contact point of a ball moves with its centre and
// its spin, 1/m_c = 1/m + R^2/I = 3.5/m, so the tangential spring's mode has omega^2 = 3.5 k_s/m
// and the dashpot's ratio in it is sqrt(3.5) zeta_s: 0.94 for a stated 0.5. Exact for one
// contact: the ball rolls freely in the other mode, and the tangential spring force shows this
// one. Spectral radius at 0.99 (1.01) of the limit: at most 0.971 (at least 1.029) for zeta_s
// 0.25 and 0.5; over 300 steps below 1/7000 (above 5000), asked: 1/100 (100) of the amplitude of
// the first 21 steps. The engine's estimate must lie below the limit (it takes the spin and the
// slide apart). zeta_s = 1 is left out: its slow, overdamped mode needs thousands of steps.
TEST(CriticalStep, ShearDashpotLimitOfTheSpinningBall) {
  const double m = ball_mass();
  const double omega = std::sqrt(3.5 * kK / m), rest = -m * 9.81 / kK;
  const Vec3 gravity(0, 0, -9.81);
  for (double zeta_s : {0.25, 0.5}) {
    ContactProperties pair;
    pair.kn = pair.ks = kK;
    pair.mu = 10;  // no slip
    pair.shear_damping_ratio = zeta_s;
    const double limit = 2 * damped_factor(std::sqrt(3.5) * zeta_s) / omega;
    for (double fraction : {0.99, 1.01}) {
      Simulation sim = ball_on_floor(pair, fraction * limit, rest, gravity);
      sim.setup();
      sim.particles().v[0].x() = 1e-9;
      const double first =
          late_amplitude(sim, 21, [](const Simulation& s) { return s.planes()[0].force.x(); });
      const double amplitude =
          late_amplitude(sim, 300, [](const Simulation& s) { return s.planes()[0].force.x(); });
      if (fraction < 1)
        EXPECT_LT(amplitude, first / 100) << "zeta_s " << zeta_s;
      else
        EXPECT_GT(amplitude, 100 * first) << "zeta_s " << zeta_s;
    }
    Simulation probe = ball_on_floor(pair, 1e-7, rest, gravity);
    probe.setup();
    EXPECT_LT(probe.critical_timestep(), limit) << "zeta_s " << zeta_s;
  }
}

// A simple cubic block of 4 x 4 x 4 touching balls (R = 0.01 m, contacts 1e6 N/m, friction 0.5,
// rolling friction 0.3, local damping 0.7) in a box under gravity, every contact with normal
// and shear dashpots of ratio `zeta`; its time step `fraction` of the critical step, of the
// damped estimate or, with `undamped_estimate`, of the same block's estimate without dashpots.
std::unique_ptr<Simulation> damped_block(double zeta, double fraction, bool undamped_estimate) {
  auto make = [](double ratio) {
    Material m = test_material(1e6, 0.5, 0.3);
    m.normal_damping_ratio = m.shear_damping_ratio = ratio;
    m.local_damping = 0.7;
    MaterialTable t;
    t.add(m);
    Particles p;
    const double r = 0.01;
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j)
        for (int k = 0; k < 4; ++k)
          p.add_ball(Vec3((2 * i + 1) * r, (2 * j + 1) * r, (2 * k + 1) * r - 1e-6 * (k + 1)), r, 0,
                     m.density, 16 * i + 4 * j + k);
    SimulationSettings s;
    s.time_step = 1e-7;
    s.allow_supercritical_step = true;  // the undamped estimate's step is above the damped one
    auto sim = std::make_unique<Simulation>(std::move(t), std::move(p), s);
    testing::add_open_box(*sim, 8 * r);
    sim->setup();
    return sim;
  };
  const double critical = make(undamped_estimate ? 0 : zeta)->critical_timestep();
  auto sim = make(zeta);
  sim->set_time_step(fraction * critical);
  return sim;
}

// The largest |energy balance| over `steps` steps, checked every 100, relative to the energy
// that entered the block (gravity's work).
double worst_ledger(Simulation& sim, int steps) {
  const EnergyBudget e0 = sim.energy();
  double worst = 0;
  for (int i = 1; i <= steps; ++i) {
    sim.step();
    if (i % 100) continue;
    const EnergyBudget e = sim.energy();
    worst = std::max(worst, std::abs(e.total() - e0.total()) / std::abs(e.gravity_work));
  }
  return worst;
}

// The bed that blew up: dashpots of 0.5 on every contact. Half the undamped estimate, the step
// a case file's fraction 0.5 took before the dashpots were counted, is 1.09 times the damped
// estimate here, and the block's spin mode (neighbours turning alike, each contact's shear
// dashpot acting on twice the spin) runs away within 400 steps. At 0.8 of the damped estimate
// (the full-size push cases' fraction) it settles to rest: kinetic energy below 1e-9 J after
// 5,000 steps (measured 6e-14 J) and the energy ledger within 3 % of gravity's work, the
// ledger's first-order error being 1.0-1.3 % at 0.5-0.8 of the estimate; a blow-up makes it
// far larger than 1 (5e6 at 0.9, where the contacts made while settling have brought the
// estimate below the step).
TEST(CriticalStep, DampedBedStableAtTheDampedEstimate) {
  auto undamped = damped_block(0.5, 0.5, true);
  EXPECT_THROW(worst_ledger(*undamped, 5000), std::runtime_error);

  auto damped = damped_block(0.5, 0.8, false);
  EXPECT_LT(worst_ledger(*damped, 5000), 0.03);
  EXPECT_LT(damped->particles().kinetic_energy(), 1e-9);
}

// The silent blow-up caught: at 0.9 of the setup's damped estimate the settling block's new
// contacts bring the estimate below the step and it blows up without a runaway overlap (its
// ledger off by 5e6 after 5,000 steps). check_energy stops it, naming the step; at 0.8 it passes
// the same checks.
TEST(CriticalStep, BlowUpStopsAtTheEnergyCheck) {
  auto check_every_100 = [](Simulation& sim) {
    const EnergyBudget initial = sim.energy();
    for (int i = 1; i <= 5000; ++i) {
      sim.step();
      if (i % 100 == 0) sim.check_energy(initial);
    }
  };
  auto sound = damped_block(0.5, 0.8, false);
  EXPECT_NO_THROW(check_every_100(*sound));
  auto blowing_up = damped_block(0.5, 0.9, false);
  try {
    check_every_100(*blowing_up);
    ADD_FAILURE() << "no blow-up found";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("blew up"), std::string::npos) << what;
    EXPECT_NE(what.find("(step "), std::string::npos) << what;
    EXPECT_NE(what.find("energy from nowhere"), std::string::npos) << what;
  }
}

// A non-finite velocity stops the very step that made it, naming the body.
TEST(CriticalStep, NonFiniteStateStopsTheStep) {
  auto sim = damped_block(0.5, 0.5, false);
  sim->step();
  sim->particles().v[5].x() = std::numeric_limits<double>::quiet_NaN();
  try {
    sim->step();
    ADD_FAILURE() << "no stop";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("non-finite"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace trackbed::dem
