// The complete state of a model (dem/io/engine_state.h): saved to HDF5 and restored into a model
// built from the same input, the model steps on bit for bit as the original; a state of another
// model is refused with one line.
#include <gtest/gtest.h>
#include <omp.h>

#include <filesystem>

#include "common/input_error.h"
#include "dem/engine/clump_template.h"
#include "dem/engine/triangle_mesh.h"
#include "dem/io/engine_state.h"
#include "dem/io/hdf5_io.h"
#include "dem/samples/random_packing.h"
#include "sim_builder.h"

namespace trackbed::dem {
namespace {

namespace fs = std::filesystem;

// Balls and clumps with rolling resistance falling into an open box onto a plate pressed down by
// a servo: every kind of contact history (pairs with rolling springs, planes, mesh slots) and a
// mesh control that reads the last step's loads. The plate has a material of its own, with
// rolling resistance; under the min rule its contacts roll only where the stones' do.
std::unique_ptr<Simulation> model(
    int balls, double stone_rolling = 0.3,
    int parallel_threshold = SimulationSettings().parallel_threshold) {
  Material m = testing::test_material(1e6, 0.5, stone_rolling, 0.2);
  m.local_damping = 0.3;
  Material plate_material = testing::test_material(1e6, 0.5, 0.3, 0.2);
  plate_material.name = "plate";
  MaterialTable table;
  table.add(m);
  table.add(plate_material);
  Particles p;
  RandomPackingSpec spec;
  spec.lower = Vec3(0, 0, 0);
  spec.upper = Vec3(0.3, 0.3, 0.3);
  spec.count = balls;
  spec.radius_min = 0.012;
  spec.radius_max = 0.02;
  spec.clump_fraction = 0.5;
  const ClumpTemplate t =
      make_clump_template("pair", {{Vec3(-0.005, 0, 0), 0.01}, {Vec3(0.006, 0, 0), 0.008}});
  spec.clump_template = &t;
  add_random_packing(spec, table, p);
  SimulationSettings s;
  s.time_step = 2e-5;
  s.parallel_threshold = parallel_threshold;
  auto sim = std::make_unique<Simulation>(std::move(table), std::move(p), s);
  testing::add_open_box(*sim, 0.3);
  MeshBody plate = MeshBody::from_world_mesh(
      "plate", make_box_mesh(Vec3(0.02, 0.02, 0.31), Vec3(0.28, 0.28, 0.33), true), 1, 0,
      Vec3(0.15, 0.15, 0.32));
  plate.dof[2].mode = DofMode::servo;
  plate.dof[2].value = -20;
  plate.dof[2].max_speed = 1.0;
  sim->add_mesh_body(std::move(plate));
  return sim;
}

// Steps `a` and `b` on together and expects them to stay bit-identical.
void expect_same_steps(Simulation& a, Simulation& b, int steps) {
  EXPECT_EQ(b.step_count(), a.step_count());
  for (int i = 0; i < steps; ++i) {
    a.step();
    b.step();
  }
  const Particles &pa = a.particles(), &pb = b.particles();
  for (int i = 0; i < pa.num_bodies(); ++i) {
    ASSERT_EQ(pa.x[i], pb.x[i]) << "body " << i;
    ASSERT_EQ(pa.w[i], pb.w[i]) << "body " << i;
  }
  EXPECT_EQ(a.meshes()[0].x, b.meshes()[0].x);
  EXPECT_EQ(a.meshes()[0].contact_force, b.meshes()[0].contact_force);
  EXPECT_EQ(a.num_contacts(), b.num_contacts());
  EXPECT_EQ(a.energy().total(), b.energy().total());
  EXPECT_EQ(a.num_neighbor_builds(), b.num_neighbor_builds());
}

// Runs the model until the bed has landed and the plate presses on it (the servo makes it bounce).
void press_plate_onto_bed(Simulation& a) {
  a.setup();
  testing::run_for(a, 0.45);
  for (int i = 0; i < 5000 && std::abs(a.meshes()[0].contact_force.z()) <= 1.0; ++i) a.step();
  ASSERT_GT(a.num_contacts(), 100);
  ASSERT_GT(std::abs(a.meshes()[0].contact_force.z()), 1.0);
}

// Saved to a file and restored into a model of the same input, never set up or set up (as
// `trackbed resume` restores), on one thread and on two (each thread's share of the pair loop is
// made from the list and the positions at its build, which the state holds: NeighborList::
// balanced_ranges).
void expect_restored_model_steps_on(int threads, bool restore_into_set_up_model) {
  omp_set_num_threads(threads);
  const int threshold = threads > 1 ? 0 : SimulationSettings().parallel_threshold;
  auto a = model(120, 0.3, threshold);
  press_plate_onto_bed(*a);
  const fs::path file = fs::temp_directory_path() / "trackbed_test_engine_state.h5";
  hdf5::write_file(file.string(), "state",
                   [&](hid_t f) { write_engine_state(f, a->engine_state()); });

  auto b = model(120, 0.3, threshold);  // the same input
  if (restore_into_set_up_model) {
    b->setup();
    testing::run_for(*b, 0.05);  // a list and a split of its own, of another state
  }
  {
    hdf5::Handle f(hdf5::open_for_reading(file.string(), "state"), H5Fclose, "open");
    b->restore_engine_state(read_engine_state(f, file.string()));
  }
  fs::remove(file);
  expect_same_steps(*a, *b, 3000);
  omp_set_num_threads(1);
}

TEST(EngineState, RestoredModelStepsOnBitForBit) {
  expect_restored_model_steps_on(1, false);
}

TEST(EngineState, RestoredModelStepsOnBitForBitOnTwoThreads) {
  expect_restored_model_steps_on(2, false);
  expect_restored_model_steps_on(2, true);
}

// A step runs in two parallel regions, the force pass with one barrier (docs/theory.md, "Two
// parallel regions a step"). From the same state, steps on two threads must give the one-thread
// steps' bodies, plate and contacts to round-off: the threads only sum each body's loads in
// another order (about 1e-16 of a force, moving a body by far less than 1e-12 m in ten steps of
// 2e-5 s), while a load lost or counted twice by a race moves a stone of this pressed bed by
// about F dt^2 / m, 1e-9 to 1e-7 m a step.
TEST(EngineState, TwoThreadsStepAsOneToRoundOff) {
  omp_set_num_threads(1);
  auto a = model(120, 0.3, 0);  // every model parallel: this one has 180 elements
  press_plate_onto_bed(*a);
  auto b = model(120, 0.3, 0);
  b->restore_engine_state(a->engine_state());
  for (int i = 0; i < 10; ++i) a->step();
  omp_set_num_threads(2);
  for (int i = 0; i < 10; ++i) b->step();
  omp_set_num_threads(1);
  const Particles &pa = a->particles(), &pb = b->particles();
  for (int i = 0; i < pa.num_bodies(); ++i) {
    ASSERT_LT((pa.x[i] - pb.x[i]).norm(), 1e-12) << "body " << i;
    ASSERT_LT((pa.w[i] - pb.w[i]).norm(), 1e-9) << "body " << i;  // rad/s
  }
  const Vec3 fa = a->meshes()[0].contact_force, fb = b->meshes()[0].contact_force;
  EXPECT_LT((fa - fb).norm(), 1e-9 * fa.norm());
  EXPECT_EQ(a->num_contacts(), b->num_contacts());
}

TEST(EngineState, StateOfAnotherModelIsRefused) {
  auto a = model(120);
  a->setup();
  testing::run_for(*a, 0.01);
  auto fewer = model(100);
  try {
    fewer->restore_engine_state(a->engine_state());
    ADD_FAILURE() << "no error for the state of another model";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bodies: 120 in the saved state, 100 in the model"),
              std::string::npos)
        << e.what();
  }
  // A damaged list (a partner out of range) is refused, not followed out of bounds.
  EngineState broken = a->engine_state();
  ASSERT_FALSE(broken.list_partners.empty());
  broken.list_partners.back() = broken.particles.num_elements();
  auto same = model(120);
  EXPECT_THROW(same->restore_engine_state(std::move(broken)), InputError);
}

// Rolling springs are kept only where a contact the stones can make rolls: not for stones without
// rolling resistance, though the plate has some. A state saved with springs there (as builds
// before this rule wrote) is restored without them and steps on as the model that never had them;
// a state without springs is refused by a model whose stones roll.
TEST(EngineState, RollingSpringsOnlyWhereAContactRolls) {
  auto rolling = model(120);
  rolling->setup();
  testing::run_for(*rolling, 0.05);
  const EngineState with_springs = rolling->engine_state();
  ASSERT_FALSE(with_springs.list_partners.empty());
  EXPECT_EQ(with_springs.pair_roll.size(), with_springs.list_partners.size());

  auto a = model(120, 0.0);
  a->setup();
  testing::run_for(*a, 0.45);
  EngineState saved = a->engine_state();
  EXPECT_TRUE(saved.pair_roll.empty());
  saved.pair_roll.assign(saved.list_partners.size(), Vec3::Zero());  // an older build's state
  auto b = model(120, 0.0);
  b->restore_engine_state(saved);
  EXPECT_TRUE(b->engine_state().pair_roll.empty());
  expect_same_steps(*a, *b, 2000);

  saved.pair_roll.clear();
  auto c = model(120);
  try {
    c->restore_engine_state(saved);
    ADD_FAILURE() << "no error for a state without the rolling springs this model needs";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no rolling springs"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace trackbed::dem
