// The contact springs a model saves (contact_state.h) restore into a model built again from the
// same bodies, in another order: the restored model steps exactly as the original goes on.
// Also: growth of radii between steps rebuilds the lists (particles_changed), and the mean
// unbalanced force ratio is 1 in free fall and vanishes at rest.
#include <gtest/gtest.h>

#include <random>

#include "dem/samples/random_packing.h"
#include "sim_builder.h"

namespace trackbed::dem {
namespace {

using testing::add_open_box;
using testing::floor_at;
using testing::run_for;
using testing::table_with_pair;
using testing::test_material;

// Balls and clumps settled in a box, with frictional springs that carry load.
Simulation settled_box() {
  const ClumpTemplate t =
      make_clump_template("pair", {{Vec3(-0.006, 0, 0), 0.008}, {Vec3(0.006, 0, 0), 0.008}});
  RandomPackingSpec spec;
  spec.lower = Vec3(0, 0, 0);
  spec.upper = Vec3(0.12, 0.12, 0.25);
  spec.count = 160;
  spec.radius_min = 0.006;
  spec.radius_max = 0.01;
  spec.clump_fraction = 0.3;
  spec.clump_template = &t;
  spec.seed = 5;
  const MaterialTable m = table_with_pair(test_material(1e5, 0.5, 0.2), 1e5);
  Particles p;
  add_random_packing(spec, m, p);
  SimulationSettings s;
  s.time_step = 2e-5;
  s.track_energy = false;
  Simulation sim(m, p, s);
  add_open_box(sim, 0.12);
  run_for(sim, 0.4);
  return sim;
}

TEST(ContactState, RestoredSpringsContinueTheRunExactly) {
  Simulation original = settled_box();
  const ContactState state = original.contact_state();
  ASSERT_GT(state.pairs.size(), 30u);
  ASSERT_GT(state.walls.size(), 10u);

  // A model built again from the same bodies, listed in reverse order: setup sorts them again
  // and every element index changes meaning, but the keys name bodies by id.
  const Particles& p = original.particles();
  Particles reversed;
  for (int b = p.num_bodies() - 1; b >= 0; --b) {
    std::vector<SphereShape> el;
    for (int e = p.first_element[b]; e < p.first_element[b + 1]; ++e)
      el.push_back({p.offset[e], p.radius[e]});
    const int k = reversed.add_body_with_elements(p.x[b], p.q[b], p.mass[b], p.inertia[b],
                                                  p.body_material[b], p.is_clump[b], p.id[b], el);
    reversed.v[k] = p.v[b], reversed.w[k] = p.w[b];
  }
  SimulationSettings s = original.settings();
  Simulation copy(original.materials(), reversed, s);
  add_open_box(copy, 0.12);
  copy.setup();
  EXPECT_EQ(copy.restore_contact_state(state),
            static_cast<int>(state.pairs.size() + state.walls.size()));

  for (int k = 0; k < 200; ++k) original.step(), copy.step();
  // Same bodies by id, same positions to round-off of the summation order (the pair loop runs
  // in another element order).
  std::map<std::int64_t, Vec3> where;
  for (int b = 0; b < original.particles().num_bodies(); ++b)
    where[original.particles().id[b]] = original.particles().x[b];
  double worst = 0;
  for (int b = 0; b < copy.particles().num_bodies(); ++b)
    worst = std::max(worst, (copy.particles().x[b] - where[copy.particles().id[b]]).norm());
  EXPECT_LT(worst, 1e-9);
  EXPECT_NEAR(copy.planes()[0].force.z(), original.planes()[0].force.z(),
              1e-8 * std::abs(original.planes()[0].force.z()));
}

TEST(ContactState, WithoutSpringsTheBedLosesItsFrictionalSupport) {
  // The reason the springs are saved: restarting the same state without them changes the run.
  Simulation original = settled_box();
  Simulation fresh(original.materials(), original.particles(), original.settings());
  add_open_box(fresh, 0.12);
  for (int k = 0; k < 200; ++k) original.step(), fresh.step();
  double worst = 0;
  for (int b = 0; b < fresh.particles().num_bodies(); ++b)
    worst = std::max(worst, (fresh.particles().x[b] - original.particles().x[b]).norm());
  EXPECT_GT(worst, 1e-7);
}

TEST(ParticlesChanged, GrowingRadiiFindTheirContacts) {
  // Two balls 10 mm apart with a 4 mm skin: not neighbours. Growing both by 6 mm makes them
  // overlap by 2 mm; particles_changed must rebuild so the next step pushes them apart.
  Particles p;
  p.add_ball(Vec3(0, 0, 0), 0.01, 0, 2800, 0);
  p.add_ball(Vec3(0.03, 0, 0), 0.01, 0, 2800, 1);
  SimulationSettings s;
  s.time_step = 1e-6;
  s.gravity = Vec3::Zero();
  Simulation sim(table_with_pair(test_material(1e6), 1e6), p, s);
  sim.setup();
  sim.step();
  EXPECT_EQ(sim.num_contacts(), 0);
  for (double& r : sim.particles().radius) r = 0.016;
  sim.particles_changed();
  sim.step();
  EXPECT_EQ(sim.num_contacts(), 1);
  EXPECT_LT(sim.particles().v[0].x(), 0);
  EXPECT_GT(sim.particles().v[1].x(), 0);
}

TEST(UnbalancedForceRatio, OneInFreeFallZeroAtRest) {
  SimulationSettings s;
  s.time_step = 1e-5;
  s.track_energy = false;
  Material m = test_material(1e6);
  m.local_damping = 0.7;
  MaterialTable t;
  t.add(m);
  Particles one;
  one.add_ball(Vec3(0, 0, 0.0099), 0.01, 0, 2800, 0);
  Simulation rest(t, one, s);
  rest.add_plane(floor_at(0));
  run_for(rest, 0.2);
  EXPECT_LT(rest.unbalanced_force_ratio(), 1e-6);
  Particles flying;
  flying.add_ball(Vec3(0, 0, 1), 0.01, 0, 2800, 0);
  Simulation fall(t, flying, s);
  fall.step();
  EXPECT_DOUBLE_EQ(fall.unbalanced_force_ratio(), 1.0);
}

}  // namespace
}  // namespace trackbed::dem
