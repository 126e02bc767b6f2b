// Static equilibrium: wall reactions carry the weight of a column and of a packed box.
#include <gtest/gtest.h>

#include <algorithm>

#include "dem/samples/random_packing.h"
#include "sim_builder.h"

namespace trackbed::dem {
namespace {

using testing::floor_at;
using testing::run_for;

Material damped_ballast() {
  Material m;
  m.name = "ballast";
  m.density = 2800;
  m.normal_stiffness = m.shear_stiffness = 4e6;
  m.friction = 0.5;
  m.local_damping = 0.7;
  // Rolling resistance, as for the paper's balls: without it, spheres in a box keep creeping
  // for seconds (slow rolling rearrangements) before they rest.
  m.rolling_friction = 0.3;
  return m;
}

double total_weight(const Particles& p, double g) {
  double m = 0;
  for (double x : p.mass) m += x;
  return m * g;
}

TEST(StaticEquilibrium, ColumnReactionEqualsWeight) {
  MaterialTable t;
  t.add(damped_ballast());
  Particles p;
  const double r = 0.02;
  for (int i = 0; i < 10; ++i) p.add_ball(Vec3(0, 0, r + i * 2.05 * r), r, 0, 2800, i);
  SimulationSettings s;
  s.time_step = 2e-5;
  Simulation sim(std::move(t), std::move(p), s);
  sim.add_plane(floor_at(0));
  run_for(sim, 0.5);
  const double w = total_weight(sim.particles(), 9.81);
  // At rest the floor carries the weight; 0.1 % allows for the residual damped vibration.
  EXPECT_NEAR(-sim.planes()[0].force.z(), w, 1e-3 * w);
  EXPECT_LT(sim.particles().kinetic_energy(), 1e-8);
}

TEST(StaticEquilibrium, PackedBoxReactionsEqualWeight) {
  MaterialTable t;
  t.add(damped_ballast());
  Particles p;
  RandomPackingSpec spec;
  spec.lower = Vec3(0, 0, 0);
  spec.upper = Vec3(0.3, 0.3, 0.3);
  spec.count = 250;
  spec.radius_min = 0.012;
  spec.radius_max = 0.02;
  spec.seed = 3;
  add_random_packing(spec, t, p);
  SimulationSettings s;
  s.time_step = 1.5e-5;
  s.track_energy = false;
  Simulation sim(std::move(t), std::move(p), s);
  testing::add_open_box(sim, 0.3);
  // Settle until every body is at rest (translational speed below 1e-4 m/s) for 0.1 s, at most
  // 6 s. Spin about a contact normal is not resisted in the PFC laws (no twisting resistance, and
  // local damping scales with the unbalanced moment), so a few balls may keep twisting in place;
  // that moves no load.
  int quiet = 0;
  for (int block = 0; block < 120 && quiet < 2; ++block) {
    run_for(sim, 0.05);
    double vmax = 0;
    for (const auto& v : sim.particles().v) vmax = std::max(vmax, v.norm());
    quiet = vmax < 1e-4 ? quiet + 1 : 0;
  }
  ASSERT_EQ(quiet, 2) << "the packing did not come to rest";
  const double w = total_weight(sim.particles(), 9.81);
  // At rest the walls together carry the weight: the sum of the forces the particles exert on
  // them (normal and frictional) is (0, 0, -W), to 0.1 % of W.
  Vec3 total = Vec3::Zero();
  for (const auto& wall : sim.planes()) total += wall.force;
  EXPECT_NEAR(-total.z(), w, 1e-3 * w);
  EXPECT_NEAR(total.x(), 0, 1e-3 * w);
  EXPECT_NEAR(total.y(), 0, 1e-3 * w);
  // The side walls really are loaded (a granular bed pushes sideways).
  EXPECT_GT(sim.planes()[3].force.x(), 0.01 * w);
}

// Density scaling (Simulation::scale_density_for_step) lets a column of small and large balls
// take three times the step its smallest ball allows and rests where the unscaled column rests:
// gravity keeps the true masses, so the static equilibrium is the same.
TEST(StaticEquilibrium, DensityScaledColumnRestsWhereTheUnscaledOneRests) {
  auto column = [] {
    MaterialTable t;
    t.add(damped_ballast());
    Particles p;
    double z = 0;
    for (int i = 0; i < 8; ++i) {
      const double r = i % 2 ? 0.01 : 0.03;
      p.add_ball(Vec3(0, 0, z + r), r, 0, 2800, i);
      z += 2 * r;
    }
    SimulationSettings s;
    s.time_step = 1e-6;
    Simulation sim(std::move(t), std::move(p), s);
    sim.add_plane(floor_at(0));
    sim.setup();
    return sim;
  };
  const double fraction = 0.8;
  Simulation reference = column();
  reference.set_time_step(fraction * reference.critical_timestep());
  run_for(reference, 1.0);

  Simulation scaled = column();
  const double dt = 3 * fraction * scaled.critical_timestep();
  EXPECT_THROW(scaled.set_time_step(dt), InputError);  // above the unscaled critical step
  // The smallest step's ball needs a factor 9.
  EXPECT_GE(scaled.scale_density_for_step(dt, fraction), 9 * (1 - 1e-12));
  EXPECT_EQ(scaled.time_step(), dt);
  EXPECT_GE(fraction * scaled.critical_timestep(), dt * (1 - 1e-12));
  for (int block = 0; block < 20; ++block) {  // renewed as in a conversion's settling
    run_for(scaled, 0.05);
    scaled.scale_density_for_step(dt, fraction);
  }
  const double w = total_weight(scaled.particles(), 9.81);
  EXPECT_NEAR(-scaled.planes()[0].force.z(), w, 1e-3 * w);
  EXPECT_LT(scaled.unbalanced_force_ratio(), 1e-3);
  // Heights to a thousandth of the smallest overlap, a small ball's weight over k (5.8e-8 m):
  // both columns are damped to rest (they agree to 1e-16 m on this machine).
  const double k = scaled.materials().pair(0, 0).kn;
  const auto& m = scaled.particles().mass;
  const double tolerance = 1e-3 * *std::min_element(m.begin(), m.end()) * 9.81 / k;
  for (int b = 0; b < scaled.particles().num_bodies(); ++b) {
    const int id = static_cast<int>(scaled.particles().id[b]);
    int r = 0;
    while (reference.particles().id[r] != id) ++r;
    EXPECT_NEAR(scaled.particles().x[b].z(), reference.particles().x[r].z(), tolerance) << id;
  }
  scaled.end_density_scaling();
  EXPECT_FALSE(scaled.density_scaled());
  EXPECT_THROW(scaled.set_time_step(dt), InputError);
}

// Scaled for the neighbours within the skin (a clump conversion's growth), a ball is scaled as if
// it touched them: a row of three balls 1 mm apart (within the 4 mm skin) gets the factors the
// same row touching gets for its contacts, with the free-body contact of a ball that touches
// nothing besides, and larger ones than for its contacts, none, alone.
TEST(StaticEquilibrium, DensityScaledWithinSkinCountsTheNeighboursAsContacts) {
  auto row = [](double gap) {
    MaterialTable t;
    t.add(damped_ballast());
    Particles p;
    const double r = 0.02;
    for (int i = 0; i < 3; ++i) p.add_ball(Vec3(i * (2 * r + gap), 0, 0.5), r, 0, 2800, i);
    SimulationSettings s;
    s.time_step = 1e-6;
    Simulation sim(std::move(t), std::move(p), s);
    sim.setup();
    return sim;
  };
  Simulation apart = row(0.001);
  Simulation touching = row(-1e-9);
  const double fraction = 0.8;
  // The middle ball touching two: its step sqrt(2) or more below a free ball's.
  const double dt = 3 * fraction * touching.critical_timestep();
  const double by_contacts = touching.scale_density_for_step(dt, fraction);
  EXPECT_GT(by_contacts, 1);
  // The middle ball's rotation governs (I = 0.4 m r^2): touching two, k_rot = 2 x 1.25 k_s r^2
  // (the shear springs' k_s r^2 and the rolling spring's k_s r^2 / 4); apart, within the skin, the
  // free-body contact's k_s r^2 more: 3.5 against 2.5.
  EXPECT_NEAR(apart.scale_density_for_step(dt, fraction, true), 1.4 * by_contacts,
              1e-9 * by_contacts);
  EXPECT_GE(fraction * apart.critical_timestep(), dt * (1 - 1e-12));
  // By its contacts alone the middle ball is free (one contact's stiffness, no rolling spring):
  // 0.4 of the factor (its rotation governs: I / k_rot = 0.16 m / k_s against 0.4 m / k_s).
  EXPECT_NEAR(apart.scale_density_for_step(dt, fraction), 0.4 * by_contacts, 1e-9 * by_contacts);
}

// A body that touches nothing is estimated as if it had its first contact at its first
// element's far side (theory.md, free-body rule); within the skin it is estimated with that
// contact and its neighbours' besides, never with fewer springs than it is checked with. Here a
// rod of three pebbles, touching nothing, and a ball 1 mm above its middle pebble: that
// neighbour's lever is a third of the free-body rule's, and scaled for it alone the rod's
// rotation would be scaled too little for the step the model then checks (a scaled-down
// conversion growing at three times its step stopped so at its first renewal).
TEST(StaticEquilibrium, DensityScaledWithinSkinKeepsTheFreeBodyContact) {
  MaterialTable t;
  t.add(damped_ballast());
  Particles p;
  const double r = 0.02, a = 0.04, density = 2800;
  const double pebble = density * 4.0 / 3.0 * M_PI * r * r * r;
  const Vec3 inertia(3 * 0.4 * pebble * r * r, 3 * 0.4 * pebble * r * r + 2 * pebble * a * a,
                     3 * 0.4 * pebble * r * r + 2 * pebble * a * a);
  p.add_body_with_elements(Vec3(0, 0, 0.5), Quat::Identity(), 3 * pebble, inertia, 0, true, 0,
                           {{Vec3(-a, 0, 0), r}, {Vec3(0, 0, 0), r}, {Vec3(a, 0, 0), r}});
  p.add_ball(Vec3(0, 0, 0.5 + 2 * r + 0.001), r, 0, density, 1);
  SimulationSettings s;
  s.time_step = 1e-6;
  Simulation sim(std::move(t), std::move(p), s);
  sim.setup();
  const double fraction = 0.8;
  const double dt = 3 * fraction * sim.critical_timestep();
  EXPECT_NO_THROW(sim.scale_density_for_step(dt, fraction, true));
  EXPECT_GE(fraction * sim.critical_timestep(), dt * (1 - 1e-12));
}

}  // namespace
}  // namespace trackbed::dem
