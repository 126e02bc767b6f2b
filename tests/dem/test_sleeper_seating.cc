// When a sample build counts its sleeper as seated (SectionModel::require_seated_sleeper): the
// means over a check interval of the sleeper's load and speed, each interval on its own; and when
// a conversion lets it go from its servo (SectionModel::release_sleeper_when_carried).
#include <gtest/gtest.h>

#include "dem/mesh_body.h"
#include "dem/section_model.h"
#include "sim_builder.h"

namespace trackbed::dem {
namespace {

// A box "sleeper" pressed by its servo with 50 N onto three balls on a floor (the model of
// MeshContact.ServoSleeperPressesWithItsLoad), above them by `gap` at the start.
Simulation pressed_box(double gap) {
  const double k = 1e6;
  Material m = testing::test_material(k, 0.5);
  m.local_damping = 0.7;
  Particles p;
  for (int i = 0; i < 3; ++i) p.add_ball(Vec3(-0.05 + 0.05 * i, 0, 0.02), 0.02, 0, m.density, i);
  SimulationSettings s;
  s.time_step = 2e-5;
  Simulation sim(testing::table_with_pair(m, k), std::move(p), s);
  sim.add_plane(testing::floor_at(0));
  MeshBody box = MeshBody::from_world_mesh(
      SectionModel::kSleeperName,
      make_box_mesh(Vec3(-0.1, -0.05, 0.04 + gap), Vec3(0.1, 0.05, 0.1 + gap), true), 0, 0,
      Vec3(0, 0, 0.07 + gap));
  box.dof[2].mode = DofMode::servo;
  box.dof[2].value = -50;
  box.dof[2].max_speed = 0.01;  // m/s
  sim.add_mesh_body(std::move(box));
  sim.setup();
  return sim;
}

// Steps `sim` through `intervals` check intervals of `steps` with the criterion's recording, and
// returns the criterion's judgement of each.
std::vector<bool> judge(Simulation& sim, const SettleCriterion& c, int intervals, int steps) {
  std::vector<bool> out;
  for (int i = 0; i < intervals; ++i) {
    for (int s = 0; s < steps; ++s) {
      sim.step();
      c.each_step(sim);
    }
    out.push_back(c.also(sim));
  }
  return out;
}

const SectionModel& model() {
  static const SectionModel m(TrackSection{}, SectionMaterials{}, SimulationSettings{});
  return m;
}

TEST(SleeperSeating, AFallingSleeperIsNotSeatedARestingOneIs) {
  // 2 mm above the balls, the servo drives the box down at its 0.01 m/s limit: 10 mm/s over the
  // first intervals (and no load), so not seated at either speed bound.
  Simulation sim = pressed_box(0.002);
  SettleCriterion slow, fast;
  model().require_seated_sleeper(slow, 1e-4);
  model().require_seated_sleeper(fast, 1e-3);
  for (const bool seated : judge(sim, slow, 5, 20)) EXPECT_FALSE(seated);
  // Once it rests on the balls with its 50 N (0.5 s simulated), both call it seated.
  testing::run_for(sim, 0.5);
  EXPECT_NEAR(sim.meshes()[0].contact_force.z(), 50, 0.05);
  slow.also(sim);  // each starts a fresh interval
  fast.also(sim);
  EXPECT_TRUE(judge(sim, slow, 1, 500).front());
  EXPECT_TRUE(judge(sim, fast, 1, 500).front());
  // A judgement covers the steps since the last one only: an interval without steps is none.
  EXPECT_FALSE(slow.also(sim));
}

TEST(SleeperSeating, ReleasedFromItsServoOnlyOnceTheBedCarriesNoMoreThanItsWeight) {
  // The box starts 0.5 mm into the balls (1.5 kN on them, 30 times the 50 N its servo holds, as a
  // clump growth leaves a sleeper); with a mass whose weight is those 50 N.
  Simulation sim = pressed_box(-0.0005);
  MeshBody& box = sim.meshes()[0];
  box.mass = 50 / 9.81;
  box.weight = true;
  SettleCriterion c;
  model().require_seated_sleeper(c);
  model().release_sleeper_when_carried(c);
  int servo_steps = 0;
  while (box.dof[2].mode == DofMode::servo && servo_steps < 100000) {
    sim.step();
    c.each_step(sim);
    if (box.dof[2].mode == DofMode::servo) {
      EXPECT_GT(box.contact_force.z(), 50) << "step " << sim.step_count();
      ++servo_steps;
    }
  }
  ASSERT_EQ(box.dof[2].mode, DofMode::free);
  EXPECT_GT(servo_steps, 10);  // the servo first lifted it off the pent-up load
  EXPECT_LE(box.contact_force.z(), 50);
  // Free, it comes to rest on the balls carrying its weight, and counts as seated.
  testing::run_for(sim, 0.5);
  EXPECT_NEAR(box.contact_force.z(), 50, 0.05);
  c.also(sim);
  EXPECT_TRUE(judge(sim, c, 1, 500).front());
}

}  // namespace
}  // namespace trackbed::dem
