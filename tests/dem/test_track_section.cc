// The single-sleeper section's geometry (track_section.h) and what a deposited bed keeps of it
// (section_model.h).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "common/input_error.h"
#include "common/track_section.h"
#include "dem/engine/triangle_mesh.h"
#include "dem/samples/section_model.h"

namespace trackbed::dem {
namespace {

TEST(TrackSection, PaperSectionDimensions) {
  const TrackSection s;  // the defaults: the paper's section
  EXPECT_DOUBLE_EQ(s.crest_z(), 0.535);
  EXPECT_DOUBLE_EQ(s.half_crest_width(), 1.8);
  EXPECT_NEAR(s.half_base_width(), 1.8 + 1.75 * 0.535, 1e-15);
  // Trapezoid (3.6 m crest, 5.4725 m base, 0.535 m high) times 0.6 m, minus the sleeper.
  const double expected = 0.5 * (3.6 + 5.4725) * 0.535 * 0.6 - 2.6 * 0.28 * 0.185;
  EXPECT_NEAR(s.profile_volume(), expected, 1e-12);
}

TEST(TrackSection, ProfileVolumeAgreesWithItsMembership) {
  // Monte Carlo over the bounding box: the fraction of points in_profile accepts times the box
  // volume; 10^6 points give a relative standard error of about 1e-3.
  const TrackSection s;
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> ux(-s.half_base_width(), s.half_base_width()),
      uy(-0.5 * s.length, 0.5 * s.length), uz(0, s.crest_z());
  const int n = 1000000;
  int inside = 0;
  for (int k = 0; k < n; ++k) inside += s.in_profile(Vec3(ux(rng), uy(rng), uz(rng)));
  const double box = 2 * s.half_base_width() * s.length * s.crest_z();
  EXPECT_NEAR(box * inside / n, s.profile_volume(), 4e-3 * s.profile_volume());
  EXPECT_FALSE(s.in_profile(Vec3(0, 0, 0.4)));    // inside the sleeper
  EXPECT_TRUE(s.in_profile(Vec3(0, 0, 0.3)));     // under it
  EXPECT_TRUE(s.in_profile(Vec3(1.5, 0, 0.4)));   // the crib beside the sleeper end
  EXPECT_FALSE(s.in_profile(Vec3(2.7, 0, 0.1)));  // beyond the slope
}

// The ballast box: side walls instead of slopes, a wedge-shaped sleeper section 0.3 m wide at the
// bottom and 0.22 m at the top (cases/samples/ballast-box.prm).
TrackSection wedge_box() {
  TrackSection s;
  s.sleeper_length = 0.4;
  s.sleeper_width = 0.22;
  s.sleeper_bottom_width = 0.3;
  s.shoulder_width = 0.15;
  s.slope = 0;
  s.side_walls = true;
  s.depth_under_sleeper = 0.3;
  s.length = 0.6;
  return s;
}

TEST(TrackSection, WedgeDistanceIsTheDistanceToItsFaces) {
  const TrackSection s = wedge_box();
  const double z0 = 0.3, z1 = 0.485;
  EXPECT_DOUBLE_EQ(s.distance_to_sleeper(Vec3(0.1, 0.05, 0.4)), 0);              // inside
  EXPECT_NEAR(s.distance_to_sleeper(Vec3(0.1, 0.05, 0.25)), 0.05, 1e-15);        // below the base
  EXPECT_NEAR(s.distance_to_sleeper(Vec3(0.1, 0.05, 0.5), 0.01), 0.005, 1e-15);  // above, lifted
  EXPECT_NEAR(s.distance_to_sleeper(Vec3(0.3, 0, 0.4)), 0.1, 1e-15);             // beyond the end
  // Beside a slanted side: the distance to the line through (0.15, z0) and (0.11, z1).
  const Vec3 x(0, -0.2, 0.4);
  const double ey = 0.11 - 0.15, ez = z1 - z0;
  const double expected = std::abs((0.2 - 0.15) * ez - (0.4 - z0) * ey) / std::hypot(ey, ez);
  EXPECT_NEAR(s.distance_to_sleeper(x), expected, 1e-15);
  // Beyond a corner: the distance to the bottom edge (y = 0.15, z = z0) and the end (x = 0.2).
  EXPECT_NEAR(s.distance_to_sleeper(Vec3(0.24, 0.19, 0.26)), std::sqrt(3 * 0.0016), 1e-15);
}

TEST(TrackSection, WedgeBoxVolumeAgreesWithItsMembershipAndMesh) {
  const TrackSection s = wedge_box();
  EXPECT_DOUBLE_EQ(s.half_base_width(), s.half_crest_width());
  const double sleeper = 0.4 * 0.5 * (0.22 + 0.3) * 0.185;
  EXPECT_NEAR(s.profile_volume(), 0.7 * 0.6 * 0.485 - sleeper, 1e-15);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> ux(-0.35, 0.35), uy(-0.3, 0.3), uz(0, 0.485);
  const int n = 1000000;  // relative standard error of the sleeper's share about 3e-3
  int in_sleeper = 0;
  for (int k = 0; k < n; ++k) {
    const Vec3 x(ux(rng), uy(rng), uz(rng));
    in_sleeper += !s.in_profile(x);
  }
  EXPECT_NEAR(0.7 * 0.6 * 0.485 * in_sleeper / n, sleeper, 0.02 * sleeper);
  // The mesh the sample's sleeper is made of encloses the same trapezoidal prism.
  const TriangleMesh mesh =
      make_box_mesh(Vec3(-0.2, -0.11, 0.3), Vec3(0.2, 0.11, 0.485), true, 0.3);
  ASSERT_TRUE(mesh.is_closed());
  EXPECT_NEAR(closed_mesh_mass_properties(mesh).volume, sleeper, 1e-15);
  for (const Vec3& v : mesh.vertices) EXPECT_NEAR(s.distance_to_sleeper(v), 0, 1e-15);
}

TEST(TrackSection, BadSectionsAreRefused) {
  TrackSection s;
  s.sleeper_width = 0.7;
  try {
    s.validate("case.prm");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("sleeper width"), std::string::npos) << e.what();
  }
  s = TrackSection();
  s.slope = -1;
  EXPECT_THROW(s.validate(""), InputError);
  s = TrackSection();
  s.side_walls = true;  // on the default 1:1.75 slopes
  try {
    s.validate("box.prm");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("valid: slope 0"), std::string::npos) << e.what();
  }
}

TEST(TrackSection, TrimKeepsTheProfileAndClearsTheSleeper) {
  const TrackSection s;
  Particles p;
  p.add_ball(Vec3(0, 0, 0.2), 0.02, 0, 2800, 0);     // under the sleeper: kept
  p.add_ball(Vec3(0, 0, 0.34), 0.02, 0, 2800, 1);    // under, protruding into it: kept
  p.add_ball(Vec3(0, 0.15, 0.4), 0.02, 0, 2800, 2);  // crib, touching the side: removed
  p.add_ball(Vec3(0, 0.2, 0.4), 0.02, 0, 2800, 3);   // crib, clear: kept
  p.add_ball(Vec3(0, 0, 0.6), 0.02, 0, 2800, 4);     // above the crest: removed
  p.add_ball(Vec3(2.6, 0, 0.2), 0.02, 0, 2800, 5);   // beyond the slope: removed
  // Beyond the slope at its height, inside the mould (0.05 m from its wall): removed.
  p.add_ball(Vec3(s.half_base_width() - 0.05, 0, 0.4), 0.02, 0, 2800, 6);
  const std::vector<char> keep = bodies_in_section(p, s);
  EXPECT_EQ(keep, (std::vector<char>{1, 1, 0, 1, 0, 0, 0}));
  // The protruding ball lifts the sleeper by its top above the bottom: 0.34 + 0.02 - 0.35.
  EXPECT_NEAR(sleeper_lift(p.subset(keep), s), 0.01, 1e-12);
  // A bed kept in its mould (slopes not cut) keeps the two balls beyond the slope, inside the
  // mould; a bed whose sleeper is seated in it keeps the crib ball touching its design side.
  ASSERT_LT(2.6, s.half_base_width());
  EXPECT_EQ(bodies_in_section(p, s, {false, true}), (std::vector<char>{1, 1, 0, 1, 0, 1, 1}));
  EXPECT_EQ(bodies_in_section(p, s, {true, false}), (std::vector<char>{1, 1, 1, 1, 0, 0, 0}));
}

// A conversion's stages add the clumps' material: the ballast without rolling resistance (the
// paper's Table 2 gives it to balls only), so a ball-clump contact has none either, while the
// balls keep theirs and the friction follows the stage.
TEST(SectionModel, ClumpMaterialIsTheBallastWithoutRollingResistance) {
  const SectionModel model(TrackSection{}, SectionMaterials{}, SimulationSettings{});
  EXPECT_EQ(model.material_table().size(), 3);
  const MaterialTable t = model.material_table(StageMaterials{0.5, 1, {}, true});
  ASSERT_EQ(t.size(), 4);
  const int c = model.clump_material();
  EXPECT_EQ(t[c].name, SectionModel::kClumpMaterialName);
  EXPECT_EQ(t[c].rolling_friction, 0.0);
  EXPECT_EQ(t[c].friction, t[0].friction);
  EXPECT_DOUBLE_EQ(t[0].friction, 0.25);
  EXPECT_DOUBLE_EQ(t.pair(0, 0).mu_roll, 0.3);
  EXPECT_EQ(t.pair(0, c).mu_roll, 0.0);
  EXPECT_EQ(t.pair(c, c).mu_roll, 0.0);
  EXPECT_EQ(t.pair(0, c).kn, t.pair(0, 0).kn);
}

// A split settling's equilibrium stage gives the clumps the ballast's rolling friction (the
// shipped cases run them with it), scaled as the balls' is.
TEST(SectionModel, ClumpMaterialWithRollingKeepsTheBallastsRollingFriction) {
  const SectionModel model(TrackSection{}, SectionMaterials{}, SimulationSettings{});
  const MaterialTable t = model.material_table(StageMaterials{1, 0.5, {}, true, true});
  const int c = model.clump_material();
  EXPECT_DOUBLE_EQ(t[c].rolling_friction, 0.15);
  EXPECT_DOUBLE_EQ(t.pair(c, c).mu_roll, 0.15);
  EXPECT_DOUBLE_EQ(t.pair(0, c).mu_roll, t.pair(0, 0).mu_roll);
  EXPECT_EQ(t[c].friction, t[0].friction);
}

}  // namespace
}  // namespace trackbed::dem
