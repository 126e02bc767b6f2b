// A triangle mesh wall must act exactly like the plane it tiles, wherever a sphere touches it:
// inside a face, across a shared edge, on vertices where four or eight triangles meet.
#include <gtest/gtest.h>

#include "dem/engine/mesh_body.h"
#include "flat_grid.h"
#include "sim_builder.h"

namespace trackbed::dem {
namespace {

using testing::flat_grid;
using testing::floor_at;
using testing::table_with_pair;
using testing::test_material;

// The 4 x 4 alternating grid (vertices joining 4 and 8 triangles) scaled to 0.4 x 0.4 m and
// centred on the origin.
TriangleMesh floor_grid() {
  TriangleMesh m = flat_grid(4, true);
  m.scale(0.1, Vec3::Zero());
  m.translate(Vec3(-0.2, -0.2, 0));
  return m;
}

// Bounces and slides a ball with friction and rolling resistance over the floor; returns the
// trajectory (positions and spins every 50 steps over 0.2 s).
std::vector<Vec3> trajectory(bool mesh, const Vec3& start, const Vec3& v0) {
  const double k = 1e6;
  Material m = test_material(k, 0.3, 0.1, 0.2);
  Particles p;
  p.add_ball(start, 0.02, 0, m.density, 0);
  p.v[0] = v0;
  SimulationSettings s;
  s.time_step = 1e-5;
  Simulation sim(table_with_pair(m, k), std::move(p), s);
  if (mesh) {
    MeshBody body = MeshBody::from_world_mesh("floor", floor_grid(), 0, 0, Vec3::Zero());
    sim.add_mesh_body(std::move(body));
  } else {
    sim.add_plane(floor_at(0));
  }
  std::vector<Vec3> out;
  for (int i = 0; i < 20000; ++i) {
    sim.step();
    if (i % 50 == 0) {
      out.push_back(sim.particles().x[0]);
      out.push_back(sim.particles().w[0]);
    }
  }
  return out;
}

TEST(MeshContact, BounceOnMeshEqualsBounceOnPlane) {
  // Landing on a vertex where eight triangles meet (grid point (0, 0)), on a shared edge, and in a
  // face, each with a sliding velocity that carries the ball across further edges and vertices.
  const std::vector<std::pair<Vec3, Vec3>> cases = {
      {Vec3(0, 0, 0.05), Vec3(0.3, 0.0, -0.5)},
      {Vec3(0.05, 0.01, 0.05), Vec3(0.0, 0.4, -0.3)},
      {Vec3(0.031, -0.017, 0.05), Vec3(0.25, 0.25, -0.4)}};
  for (const auto& [x0, v0] : cases) {
    const auto plane = trajectory(false, x0, v0);
    const auto mesh = trajectory(true, x0, v0);
    ASSERT_EQ(plane.size(), mesh.size());
    double worst = 0;
    for (std::size_t i = 0; i < plane.size(); ++i)
      worst = std::max(worst, (plane[i] - mesh[i]).norm());
    // Same contact law, same normal and overlap up to round-off (1e-16) in the closest point.
    // Each new touch-down of the bouncing ball starts a step earlier or later depending on that
    // round-off, which amplifies it about tenfold per bounce (measured: 1e-15 -> 6e-12 over the
    // first 20,000 steps, 1e-7 by 27,000). A double-counted edge or vertex contact would double
    // the force: an error of the order of the overlap (1e-4 m). 1e-9 separates the two.
    EXPECT_LT(worst, 1e-9) << "start " << x0.transpose();
    // The ball really travelled over several triangles.
    EXPECT_GT((plane.back() - plane.front()).norm(), 0.0);
  }
}

TEST(MeshContact, ServoSleeperPressesWithItsLoad) {
  // A box mesh held by a servo in z on a bed of three balls on a floor: at rest the contact
  // force on the box balances the servo load, and the floor carries balls' weight plus load.
  const double k = 1e6;
  Material m = test_material(k, 0.5);
  m.local_damping = 0.7;
  Particles p;
  for (int i = 0; i < 3; ++i) p.add_ball(Vec3(-0.05 + 0.05 * i, 0, 0.02), 0.02, 0, m.density, i);
  SimulationSettings s;
  s.time_step = 2e-5;
  Simulation sim(table_with_pair(m, k), std::move(p), s);
  sim.add_plane(floor_at(0));
  MeshBody box = MeshBody::from_world_mesh(
      "sleeper", make_box_mesh(Vec3(-0.1, -0.05, 0.045), Vec3(0.1, 0.05, 0.1), true), 0, 0,
      Vec3(0, 0, 0.07));
  box.dof[2].mode = DofMode::servo;
  box.dof[2].value = -50;  // press down with 50 N
  box.dof[2].max_speed = 0.1;
  sim.add_mesh_body(std::move(box));
  testing::run_for(sim, 0.5);
  const MeshBody& b = sim.meshes()[0];
  EXPECT_NEAR(b.contact_force.z(), 50, 0.05);
  double weight = 0;
  for (double mass : sim.particles().mass) weight += mass * 9.81;
  EXPECT_NEAR(-sim.planes()[0].force.z(), weight + 50, 0.05);
  // The base carries it all; sides and ends nothing.
  const auto& names = b.local.part_names;
  for (std::size_t i = 0; i < names.size(); ++i)
    if (names[i] == "base")
      EXPECT_NEAR(b.part_force[i].z(), 50, 0.05);
    else
      EXPECT_NEAR(b.part_force[i].norm(), 0, 1e-12);
}

}  // namespace
}  // namespace trackbed::dem
