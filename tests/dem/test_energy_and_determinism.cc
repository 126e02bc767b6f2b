// Conservation and reproducibility over a whole packing: the energy budget closes, and the same
// input with the same thread count gives bit-identical results.
#include <gtest/gtest.h>
#include <omp.h>

#include <cstring>

#include "dem/engine/clump_template.h"
#include "dem/engine/mesh_body.h"
#include "dem/engine/triangle_mesh.h"
#include "dem/samples/random_packing.h"
#include "sim_builder.h"

namespace trackbed::dem {
namespace {

// 120 bodies (half clumps) dropped into a box whose one side wall moves inwards: every energy
// term is exercised (friction, rolling, dashpots, local damping, gravity, wall work).
std::unique_ptr<Simulation> mixed_box(double local_damping, double dt = 1e-5) {
  Material m;
  m.name = "ballast";
  m.normal_stiffness = m.shear_stiffness = 4e6;
  m.friction = 0.5;
  m.rolling_friction = 0.2;
  m.normal_damping_ratio = 0.1;
  m.shear_damping_ratio = 0.05;
  m.local_damping = local_damping;
  MaterialTable t;
  t.add(m);
  const ClumpTemplate stone = make_clump_template(
      "stone", {{Vec3(0, 0, 0), 0.012}, {Vec3(0.012, 0, 0), 0.01}, {Vec3(0, 0.01, 0.004), 0.009}});
  Particles p;
  RandomPackingSpec spec;
  spec.lower = Vec3(0, 0, 0);
  spec.upper = Vec3(0.2, 0.2, 0.3);
  spec.count = 120;
  spec.radius_min = 0.01;
  spec.radius_max = 0.016;
  spec.clump_fraction = 0.5;
  spec.clump_template = &stone;
  spec.seed = 11;
  add_random_packing(spec, t, p);
  SimulationSettings s;
  s.time_step = dt;
  s.parallel_threshold = 0;  // threads even for this small model (the determinism test)
  auto sim = std::make_unique<Simulation>(std::move(t), std::move(p), s);
  testing::add_open_box(*sim, 0.2, Vec3(-0.05, 0, 0));
  return sim;
}

// Worst relative balance error over 0.3 s, relative to the energy that entered the system (work
// of gravity and of the moving wall).
double worst_balance_error(double alpha, double dt, EnergyBudget* last = nullptr) {
  auto sim = mixed_box(alpha, dt);
  sim->setup();
  const EnergyBudget e0 = sim->energy();
  double worst = 0;
  for (int block = 0; block < 30; ++block) {
    testing::run_for(*sim, 0.01);
    const EnergyBudget e = sim->energy();
    const double scale = std::abs(e.gravity_work) + std::abs(e.wall_work);
    worst = std::max(worst, std::abs(e.total() - e0.total()) / scale);
  }
  if (last) *last = sim->energy();
  return worst;
}

TEST(EnergyBalance, ClosesToOnePercentAndConvergesWithTheStep) {
  // The dissipation of dashpots and slip is tallied with the velocities the forces were computed
  // from (mid-step), the kinetic energy with the leapfrog velocities: the balance is first order
  // in dt (measured without local damping: 1.4 % at 1e-5 s, 0.69 % at 5e-6 s, 0.34 % at
  // 2.5e-6 s). The test asks for the 1 % closure and for that first-order convergence: halving
  // the step must halve the error (ratio 1.6-2.4), which a missing or double-counted term would
  // not do.
  for (double alpha : {0.0, 0.7}) {
    EnergyBudget e;
    const double coarse = worst_balance_error(alpha, 5e-6);
    const double fine = worst_balance_error(alpha, 2.5e-6, &e);
    EXPECT_LT(coarse, 0.01) << "local damping " << alpha;
    EXPECT_GT(coarse / fine, 1.6) << "local damping " << alpha;
    EXPECT_LT(coarse / fine, 2.4) << "local damping " << alpha;
    EXPECT_GT(e.friction, 0);
    EXPECT_GT(e.rolling, 0);
    EXPECT_GT(e.dashpot, 0);
    EXPECT_GT(std::abs(e.wall_work), 0);
    if (alpha > 0) EXPECT_GT(e.local_damping, 0);
  }
}

// A wall that jitters, moving up and down by v dt in alternate steps, under a ball resting on it
// (a plane floor, then a mesh floor driven the same way). The wall's work must be what the ball
// stores: the trapezoidal rule of Simulation::move_walls is exact for the linear spring, so the
// balance error stays that of the ball's leapfrog velocities, bounded (measured 0.85e-8 J after
// 10,000 steps, 1.26e-8 J after 40,000). The rectangle rule misses k (v dt)^2 / 2 = 5e-9 J in
// every step, 2e-4 J after 40,000 steps, growing with the step count: a servo's jitter.
TEST(EnergyBalance, JitteringWallWorkIsWhatTheBallStores) {
  const double k = 1e6, dt = 1e-5, v = 0.01;
  for (const bool mesh : {false, true}) {
    Material m = testing::test_material(k);
    Particles p;
    p.add_ball(Vec3(0, 0, 0.02), 0.02, 0, m.density, 0);
    SimulationSettings s;
    s.time_step = dt;
    Simulation sim(testing::table_with_pair(m, k), std::move(p), s);
    if (mesh) {
      MeshBody floor = MeshBody::from_world_mesh(
          "floor", make_box_mesh(Vec3(-0.1, -0.1, -0.05), Vec3(0.1, 0.1, 0), false), 0, 0,
          Vec3::Zero());
      floor.dof[2].mode = DofMode::velocity;
      sim.add_mesh_body(std::move(floor));
    } else {
      sim.add_plane(testing::floor_at(0));
    }
    sim.setup();
    const double e0 = sim.energy().total();
    std::vector<double> error;
    for (int i = 1; i <= 40000; ++i) {
      const double up = (i % 2 ? 1 : -1) * v;
      if (mesh)
        sim.meshes()[0].dof[2].value = up;
      else
        sim.planes()[0].velocity = Vec3(0, 0, up);
      sim.step();
      if (i % 10000 == 0) error.push_back(std::abs(sim.energy().total() - e0));
    }
    EXPECT_GT(std::abs(sim.energy().wall_work), 0) << "mesh " << mesh;
    // Bounded: 4 times the measured error, and no growth like the step count's (x4 from the
    // first check to the last; measured x1.5). The rectangle rule: 2e-4 J.
    for (double e : error) EXPECT_LT(e, 5e-8) << "mesh " << mesh;
    EXPECT_LT(error.back(), 2 * error.front()) << "mesh " << mesh;
  }
}

std::vector<double> final_state(int threads) {
  omp_set_num_threads(threads);
  auto sim = mixed_box(0.3);
  testing::run_for(*sim, 0.1);
  std::vector<double> out;
  const Particles& p = sim->particles();
  for (int b = 0; b < p.num_bodies(); ++b) {
    out.insert(out.end(), p.x[b].data(), p.x[b].data() + 3);
    out.insert(out.end(), p.w[b].data(), p.w[b].data() + 3);
    out.insert(out.end(), p.q[b].coeffs().data(), p.q[b].coeffs().data() + 4);
  }
  return out;
}

TEST(Determinism, SameInputAndThreadsGiveBitIdenticalResults) {
  for (int threads : {1, 2}) {
    const auto a = final_state(threads), b = final_state(threads);
    ASSERT_EQ(a.size(), b.size());
    EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(double)), 0)
        << threads << " threads";
  }
}

}  // namespace
}  // namespace trackbed::dem
