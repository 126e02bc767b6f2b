// Deformable mesh walls (MeshBody::make_deformable, Simulation::set_mesh_vertices): the wall an
// FE boundary becomes in coupled runs. A plate whose vertices move together must act as the same
// plate moved as a rigid body; each contact force is split to its triangle's vertices by the
// contact point's barycentric weights, which keeps the force and its moment; the loads average
// over an interval; the energy ledger closes with the work of moving vertices; the neighbour
// list follows the vertices; and a checkpoint carries the vertex state bit for bit.
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <filesystem>
#include <memory>
#include <vector>

#include "dem/engine/mesh_body.h"
#include "dem/io/engine_state.h"
#include "dem/io/hdf5_io.h"
#include "sim_builder.h"

namespace trackbed::dem {
namespace {

using testing::table_with_pair;
using testing::test_material;

constexpr double kStiffness = 1e6;  // N/m per contact
constexpr double kRadius = 0.02;    // m

// A square plate of two triangles, 0.4 m wide, centred on the origin at z = 0, normal up.
TriangleMesh plate() {
  TriangleMesh m;
  m.vertices = {Vec3(-0.2, -0.2, 0), Vec3(0.2, -0.2, 0), Vec3(0.2, 0.2, 0), Vec3(-0.2, 0.2, 0)};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  m.finalize();
  return m;
}

// A ball dropped with a sideways velocity on the plate (friction, rolling resistance and normal
// damping, so every part of the contact law acts). The plate rises at `plate_velocity`: as a
// rigid body with velocity DOFs, or as a deformable mesh whose vertices move at that velocity.
std::unique_ptr<Simulation> ball_on_plate(bool deformable, const Vec3& plate_velocity,
                                          double damping = 0.2,
                                          const Vec3& start = Vec3(0.013, -0.021, kRadius + 0.002),
                                          const Vec3& velocity = Vec3(0.2, 0.1, -0.3)) {
  const Material m = test_material(kStiffness, 0.3, 0.1, damping);
  Particles p;
  p.add_ball(start, kRadius, 0, m.density, 0);
  p.v[0] = velocity;
  SimulationSettings s;
  s.time_step = 1e-5;  // 0.05 of sqrt(m / k)
  auto sim = std::make_unique<Simulation>(table_with_pair(m, kStiffness), std::move(p), s);
  MeshBody body = MeshBody::from_world_mesh("plate", plate(), 0, 0, Vec3::Zero());
  if (deformable) {
    body.make_deformable();
    body.deformation.velocity.assign(4, plate_velocity);
  } else {
    for (int k = 0; k < 3; ++k) body.dof[k] = {DofMode::velocity, plate_velocity[k]};
  }
  sim->add_mesh_body(std::move(body));
  sim->setup();
  return sim;
}

TEST(DeformableMesh, UniformlyMovingVerticesActAsTheRigidPlate) {
  // The same motion given two ways; only rounding separates them (a vertex moved by v dt each
  // step against the body's reference point moved by v dt plus its offset; barycentric weights
  // that sum to 1 within 1e-16). Over 5,000 steps (a landing, then a ride with sliding) the ball's
  // path agrees to 1e-12 m and the plate's load to 1e-9 of the weight-scale force k r.
  const Vec3 up(0.01, 0, 0.05);
  auto rigid = ball_on_plate(false, up, 0.9), soft = ball_on_plate(true, up, 0.9);
  int touching = 0;
  for (int i = 0; i < 5000; ++i) {
    rigid->step();
    soft->step();
    if (rigid->meshes()[0].contact_force.norm() > 0) ++touching;
    ASSERT_NEAR((rigid->particles().x[0] - soft->particles().x[0]).norm(), 0, 1e-12) << i;
    ASSERT_NEAR((rigid->meshes()[0].contact_force - soft->meshes()[0].contact_force).norm(), 0,
                1e-9 * kStiffness * kRadius)
        << i;
  }
  EXPECT_GT(touching, 3000);  // the comparison covers the ball riding on the plate (3,371)
}

TEST(DeformableMesh, VertexLoadsKeepTheForceAndItsMoment) {
  // The barycentric split is exact: the vertex loads sum to the contact force and, since the
  // contact point is the weighted mean of the vertices, their moment about any point is the
  // force's moment about it (to rounding, 1e-12 of |F| times the plate's size).
  auto sim = ball_on_plate(true, Vec3::Zero());
  for (int i = 0; i < 400; ++i) {
    sim->step();
    const MeshBody& b = sim->meshes()[0];
    Vec3 sum = Vec3::Zero(), moment = Vec3::Zero();
    for (std::size_t v = 0; v < 4; ++v) {
      sum += b.deformation.load[v];
      moment += b.world.vertices[v].cross(b.deformation.load[v]);
    }
    const double scale = 1e-12 * (b.contact_force.norm() + 1e-30);
    EXPECT_NEAR((sum - b.contact_force).norm(), 0, scale) << i;
    EXPECT_NEAR((moment - (b.contact_moment + b.x.cross(b.contact_force))).norm(), 0, 0.4 * scale)
        << i;
  }
}

TEST(DeformableMesh, RestingBallLoadsEachVertexByItsWeight) {
  // A ball at rest at barycentric point (0.2, 0.3, 0.5) of triangle (0, 1, 2): the mean vertex
  // loads over the last 2,000 steps are those shares of its weight. Settled with damping until
  // its speed is below 1e-9 m/s, so the load is the weight to 1e-6.
  const TriangleMesh m = plate();
  const Vec3 at = 0.2 * m.vertices[0] + 0.3 * m.vertices[1] + 0.5 * m.vertices[2];
  auto sim = ball_on_plate(true, Vec3::Zero(), 0.9, at + Vec3(0, 0, kRadius), Vec3::Zero());
  const Particles& p = sim->particles();
  testing::run_for(*sim, 0.2);
  sim->meshes()[0].deformation.take_mean_load();  // a new interval from here
  testing::run_for(*sim, 0.02);
  ASSERT_LT(sim->particles().v[0].norm(), 1e-9);
  const std::vector<Vec3> mean = sim->meshes()[0].deformation.take_mean_load();
  const double weight = p.mass[0] * 9.81;
  const double share[4] = {0.2, 0.3, 0.5, 0};
  for (int v = 0; v < 4; ++v)
    EXPECT_NEAR(mean[v].z(), -share[v] * weight, 1e-6 * weight) << "vertex " << v;
}

TEST(DeformableMesh, EnergyLedgerClosesWithTheVerticesWork) {
  // No damping, no friction loss beyond what the ledger tallies: a plate whose vertices are
  // driven up and down (velocities set every step, and a jump of 0.1 mm set once between steps)
  // under a ball. The ledger's total stays at its start within 1e-3 of the work the plate did,
  // the trapezoidal rule's error over so many steps being far below that.
  auto sim = ball_on_plate(true, Vec3::Zero(), 0.0);
  const double e0 = sim->energy().total();
  for (int i = 0; i < 20000; ++i) {
    const double t = sim->time();
    std::vector<Vec3> x = sim->meshes()[0].world.vertices;
    if (i == 7000)
      for (Vec3& v : x) v.z() += 1e-4;
    const Vec3 u(0, 0, 0.05 * std::cos(2 * M_PI * 10 * t));
    sim->set_mesh_vertices(0, x, std::vector<Vec3>(4, u));
    sim->step();
  }
  const EnergyBudget e = sim->energy();
  ASSERT_GT(std::abs(e.wall_work), 1e-6);
  EXPECT_NEAR(e.total(), e0, 1e-3 * std::abs(e.wall_work)) << "wall work " << e.wall_work;
}

TEST(DeformableMesh, NeighbourListFollowsTheVertices) {
  // The list is rebuilt once a vertex has moved more than half the skin since the last build,
  // whether by its velocity or by a jump.
  auto sim = ball_on_plate(true, Vec3::Zero());
  sim->step();
  const int builds = sim->num_neighbor_builds();
  const double half = 0.5 * sim->settings().skin;
  std::vector<Vec3> x = sim->meshes()[0].world.vertices;
  x[2].z() -= 0.9 * half;
  sim->set_mesh_vertices(0, x, std::vector<Vec3>(4, Vec3::Zero()));
  sim->step();
  EXPECT_EQ(sim->num_neighbor_builds(), builds);
  x[2].z() -= 0.2 * half;
  sim->set_mesh_vertices(0, x, std::vector<Vec3>(4, Vec3::Zero()));
  sim->step();
  EXPECT_EQ(sim->num_neighbor_builds(), builds + 1);
}

TEST(DeformableMesh, CheckpointCarriesTheVertexState) {
  // Saved mid-interval (an impulse accumulated, a jump pending) to HDF5 and restored into a model
  // of the same input: it steps on bit for bit, loads and mean loads included.
  auto drive = [](Simulation& sim, int steps) {
    for (int i = 0; i < steps; ++i) {
      std::vector<Vec3> x = sim.meshes()[0].world.vertices;
      x[1].z() += 1e-7;
      sim.set_mesh_vertices(0, x, std::vector<Vec3>(4, Vec3(0, 0, 0.01)));
      sim.step();
    }
  };
  auto a = ball_on_plate(true, Vec3::Zero());
  drive(*a, 3000);
  const std::filesystem::path file =
      std::filesystem::temp_directory_path() / "trackbed_test_deformable_mesh.h5";
  hdf5::write_file(file.string(), "state",
                   [&](hid_t f) { write_engine_state(f, a->engine_state()); });
  auto b = ball_on_plate(true, Vec3::Zero());
  {
    hdf5::Handle f(hdf5::open_for_reading(file.string(), "state"), H5Fclose, "open");
    b->restore_engine_state(read_engine_state(f, file.string()));
  }
  std::filesystem::remove(file);
  drive(*a, 2000);
  drive(*b, 2000);
  EXPECT_EQ(a->particles().x[0], b->particles().x[0]);
  EXPECT_EQ(a->meshes()[0].world.vertices, b->meshes()[0].world.vertices);
  EXPECT_EQ(a->meshes()[0].deformation.take_mean_load(),
            b->meshes()[0].deformation.take_mean_load());
  EXPECT_EQ(a->energy().wall_work, b->energy().wall_work);
}

TEST(DeformableMesh, RefusesAMovingRigidBodyAndWrongSizes) {
  MeshBody body = MeshBody::from_world_mesh("plate", plate(), 0, 0, Vec3::Zero());
  body.dof[2] = {DofMode::free};
  EXPECT_THROW(body.make_deformable(), InputError);
  auto sim = ball_on_plate(true, Vec3::Zero());
  EXPECT_THROW(sim->set_mesh_vertices(0, std::vector<Vec3>(3), std::vector<Vec3>(4)),
               std::invalid_argument);
  auto rigid = ball_on_plate(false, Vec3::Zero());
  EXPECT_THROW(rigid->set_mesh_vertices(0, std::vector<Vec3>(4), std::vector<Vec3>(4)),
               std::invalid_argument);
}

}  // namespace
}  // namespace trackbed::dem
