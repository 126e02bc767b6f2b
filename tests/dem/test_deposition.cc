// Deposition and settling (dem/samples/deposition.h, dem/samples/settling.h) on a small bed that
// runs in about a second: a loose cloud of balls falls into an open box and settles. What must
// hold for any bed: both stages reach their criterion, no ball leaves the box, the settled bed
// rests on its walls (the walls carry its weight up to the unbalanced force the criterion
// allows), and the same seed gives the same bed bit for bit.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "dem/samples/deposition.h"
#include "sim_builder.h"

namespace trackbed::dem {
namespace {

using testing::add_open_box;
using testing::test_material;

constexpr double kBox = 0.25;  // m, side of the open box

struct DepositedBed {
  Simulation sim;
  std::vector<StageReport> reports;
};

DepositedBed deposit_bed(std::uint64_t seed) {
  // 120 balls of 30-50 mm, a ballast-like grading at a tenth of the section's count.
  std::vector<double> sizes;
  for (int i = 0; i < 120; ++i) sizes.push_back(0.03 + 0.02 * (i % 5) / 4.0);
  const double density = 2650;
  Material fall = test_material(2e6, 0.5, 0, 0.05, density);
  Material settle = fall;
  settle.local_damping = 0.7;
  DepositionStages stages;
  stages.fall.add(fall);
  stages.settle.add(settle);
  stages.ratio = 1e-3;
  Particles cloud = ball_cloud(sizes, Vec3(0, 0, 0.01), Vec3(kBox, kBox, 0), 0.2, 0, density, seed);
  SimulationSettings settings;
  settings.time_step = 2e-5;  // 0.14 of sqrt(m / k) of the smallest ball
  DepositedBed bed{Simulation(stages.fall, std::move(cloud), settings), {}};
  add_open_box(bed.sim, kBox);
  bed.sim.setup();
  StageRunner runner;
  deposit(bed.sim, stages, runner, bed.reports);
  return bed;
}

TEST(Deposition, BedSettlesInsideItsBoxAndRestsOnItsWalls) {
  DepositedBed bed = deposit_bed(7);
  ASSERT_EQ(bed.reports.size(), 2u);
  for (const StageReport& r : bed.reports) EXPECT_TRUE(r.converged) << r.name;
  const Particles& p = bed.sim.particles();
  // Inside the box: a centre may come no closer to a wall than its radius less the largest
  // overlap a resting contact has here (weight of the bed over one stiffness: well under 1 mm).
  for (int e = 0; e < p.num_elements(); ++e) {
    const double r = p.radius[e] - 1e-3;
    for (int c = 0; c < 2; ++c) {
      EXPECT_GT(p.pos[e][c], r) << "element " << e;
      EXPECT_LT(p.pos[e][c], kBox - r) << "element " << e;
    }
    EXPECT_GT(p.pos[e].z(), r) << "element " << e;
  }
  // Equilibrium on the walls: summed over the bodies, the contact forces between balls cancel,
  // so |wall forces + weight| is at most the summed unbalanced force, which the settling
  // criterion bounds by ratio times the summed contact force magnitudes and weights.
  Vec3 walls = Vec3::Zero();
  double magnitudes = 0;
  bed.sim.for_each_contact([&](const ContactRecord& c) {
    if (c.element_i < 0) walls += c.force;
    magnitudes += (c.element_i < 0 ? 1 : 2) * c.force.norm();
  });
  double weight = 0;
  for (int b = 0; b < p.num_bodies(); ++b) weight += p.mass[b] * 9.81;
  magnitudes += weight;
  const double allowed = bed.reports.back().final_ratio * magnitudes;
  EXPECT_LE((walls + Vec3(0, 0, -weight)).norm(), allowed);
  // And the floor and side walls do carry it: more than half the weight reaches them upward.
  EXPECT_GT(walls.z(), 0.5 * weight);
}

TEST(Deposition, SameSeedSameBedOtherSeedOtherBed) {
  const DepositedBed a = deposit_bed(3), b = deposit_bed(3), c = deposit_bed(4);
  const Particles &pa = a.sim.particles(), &pb = b.sim.particles(), &pc = c.sim.particles();
  ASSERT_EQ(pa.num_elements(), pb.num_elements());
  bool other = false;
  for (int e = 0; e < pa.num_elements(); ++e) {
    EXPECT_EQ(pa.pos[e], pb.pos[e]) << "element " << e;
    other = other || pa.pos[e] != pc.pos[e];
  }
  EXPECT_EQ(a.sim.step_count(), b.sim.step_count());
  EXPECT_TRUE(other);
}

}  // namespace
}  // namespace trackbed::dem
