// Porosity measured on a point grid (porosity.h) against exact volumes.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "common/input_error.h"
#include "dem/samples/porosity.h"
#include "dem/samples/random_packing.h"

namespace trackbed::dem {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Counting grid points inside a sphere with 20 points per diameter misses its volume by up to
// about 1 % (the error of counting lattice points in a ball falls only slowly with the
// spacing); over a packing the spheres sit at random offsets to the grid and the errors average
// out. The single-sphere tests allow 1.5 %, the packing test 0.3 %.
TEST(Porosity, OneSphereInABox) {
  // A sphere of diameter 40 mm in a 100 mm cube; spacing 2 mm = d/20.
  Particles p;
  p.add_ball(Vec3(0.05, 0.05, 0.05), 0.02, 0, 2800, 0);
  const auto m = porosity_in_box(p, Vec3::Zero(), Vec3::Constant(0.1), 0.002);
  const double solid = 4.0 / 3.0 * kPi * std::pow(0.02, 3) / 1e-3;
  EXPECT_NEAR(1 - m.porosity, solid, 1.5e-2 * solid);
  EXPECT_EQ(m.points, 50 * 50 * 50);
  EXPECT_NEAR(m.box_volume, 1e-3, 1e-15);
}

TEST(Porosity, OverlappingPebblesCountOnceAndTheBoxCuts) {
  // A clump of two coincident pebbles is one sphere; a sphere cut by the box counts only inside.
  const ClumpTemplate t =
      make_clump_template("twin", {{Vec3(0, 0, 0), 0.02}, {Vec3(1e-9, 0, 0), 0.02}});
  Particles p;
  p.add_clump(t, Vec3(0.0, 0.05, 0.05), Quat::Identity(), 0, 2800, 0);
  const auto m = porosity_in_box(p, Vec3::Zero(), Vec3::Constant(0.1), 0.001);
  const double half = 2.0 / 3.0 * kPi * std::pow(0.02, 3) / 1e-3;
  EXPECT_NEAR(1 - m.porosity, half, 1.5e-2 * half);
}

TEST(Porosity, RegionCountsOnlyItsPoints) {
  Particles p;
  p.add_ball(Vec3(0.05, 0.05, 0.05), 0.02, 0, 2800, 0);
  // The half z < 0.05 of the box: half the sphere in half the volume.
  const auto m = porosity_in_region(p, Vec3::Zero(), Vec3::Constant(0.1), 0.002,
                                    [](const Vec3& x) { return x.z() < 0.05; });
  const double solid = 4.0 / 3.0 * kPi * std::pow(0.02, 3) / 1e-3;
  EXPECT_NEAR(1 - m.porosity, solid, 1.5e-2 * solid);
  EXPECT_NEAR(m.box_volume, 0.5e-3, 1e-12);
}

TEST(Porosity, PackingOfManySpheresIsAccurate) {
  // 300 disjoint spheres of 22.4-63 mm (the ballast grading's range) placed at random, measured
  // with the sample builder's spacing: a tenth of the smallest diameter.
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0.0112, 0.0315);
  std::vector<double> r(300);
  double volume = 0;
  for (double& x : r) x = u(rng), volume += 4.0 / 3.0 * kPi * x * x * x;
  const Vec3 hi(0.6, 0.6, 0.6);
  const auto centres = random_sequential_positions(r, Vec3::Zero(), hi, rng, 2000, "test");
  Particles p;
  for (int k = 0; k < 300; ++k) p.add_ball(centres[k], r[k], 0, 2800, k);
  const auto m = porosity_in_box(p, Vec3::Zero(), hi, 0.00224);
  EXPECT_NEAR((1 - m.porosity) * m.box_volume, volume, 3e-3 * volume);
}

TEST(Porosity, BadBoxesAreRefused) {
  Particles p;
  EXPECT_THROW(porosity_in_box(p, Vec3::Zero(), Vec3(1, 0, 1), 0.01), InputError);
  EXPECT_THROW(porosity_in_box(p, Vec3::Zero(), Vec3::Ones(), 0), InputError);
  EXPECT_THROW(porosity_in_box(p, Vec3::Zero(), Vec3::Ones(), 1e-4), InputError);
}

}  // namespace
}  // namespace trackbed::dem
