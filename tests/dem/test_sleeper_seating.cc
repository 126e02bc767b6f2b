// When a sample build counts its sleeper as seated (SectionModel::require_seated_sleeper): the
// means over a check interval of the sleeper's load and speed, each interval on its own; and when
// a conversion lets it go from its servo (SectionModel::release_sleeper_when_carried); where a
// seated sleeper gets its support (sleeper_support).
#include <gtest/gtest.h>

#include "dem/engine/mesh_body.h"
#include "dem/engine/sleeper_support.h"
#include "dem/samples/section_model.h"
#include "sim_builder.h"

namespace trackbed::dem {
namespace {

// A box "sleeper" pressed by its servo with 50 N onto three balls on a floor (the model of
// MeshContact.ServoSleeperPressesWithItsLoad), above them by `gap` at the start; optionally a
// fourth ball dropped onto its top near one end.
Simulation pressed_box(double gap, bool ball_on_top = false) {
  const double k = 1e6;
  Material m = testing::test_material(k, 0.5);
  m.local_damping = 0.7;
  Particles p;
  for (int i = 0; i < 3; ++i) p.add_ball(Vec3(-0.05 + 0.05 * i, 0, 0.02), 0.02, 0, m.density, i);
  if (ball_on_top) p.add_ball(Vec3(0.07, 0, 0.1 + gap + 0.011), 0.01, 0, m.density, 3);
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

TEST(SleeperSupport, ThreeEqualBallsUnderALevelBoxCarryAThirdEach) {
  // Rotations fixed, the box sinks evenly: the three identical balls compress alike and carry
  // 50/3 N each; they lie in the second, third and fourth fifths of its 0.2 m length (x = -0.05,
  // 0, 0.05 against fifths' bounds -0.1, -0.06, -0.02, 0.02, 0.06, 0.1). The ball on its top
  // loads it by that ball's weight, downwards, so the base carries 50 N plus that weight.
  Simulation sim = pressed_box(0.002, true);
  testing::run_for(sim, 0.5);
  const MeshBody& box = sim.meshes()[0];
  ASSERT_NEAR(box.contact_force.z(), 50, 0.05);  // seated (as in the test above)
  const double top_weight = sim.particles().mass[3] * 9.81;
  const SleeperSupport s = sleeper_support(sim, 0);
  ASSERT_EQ(s.parts.size(), 4u);
  const SleeperSupport::Part& base = *s.part("base");
  const SleeperSupport::Part& top = *s.part("top");
  EXPECT_EQ(base.contacts, 3);
  EXPECT_EQ(top.contacts, 1);
  EXPECT_EQ(s.part("sides")->contacts, 0);
  EXPECT_EQ(s.part("ends")->contacts, 0);
  // At rest the dashpots carry nothing: the records' loads are the body's to round-off of the
  // servo's last steps (1e-6 of the load).
  EXPECT_NEAR(s.vertical_load(), box.contact_force.z(), 1e-6 * 50);
  EXPECT_NEAR(top.force.z(), -top_weight, 1e-3 * top_weight);
  EXPECT_NEAR(base.force.z(), 50 + top_weight, 0.05);
  EXPECT_EQ(s.base_contacts, (std::array<int, 5>{0, 1, 1, 1, 0}));
  for (int k : {1, 2, 3}) EXPECT_NEAR(s.base_load[k], (50 + top_weight) / 3, 0.05 / 3) << k;
  EXPECT_EQ(s.base_load[0], 0);
  EXPECT_EQ(s.base_load[4], 0);
  EXPECT_NEAR(s.largest_base_contact, (50 + top_weight) / 3, 0.05 / 3);
}

}  // namespace
}  // namespace trackbed::dem
