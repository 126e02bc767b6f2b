// Bubble packing (dem/samples/bubble_pack.h): a sphere gives one pebble, boxes respond to Distance
// and Ratio as documented, pebbles stay inside, mass properties come from the chosen source.
#include "common/input_error.h"
#include "dem/engine/mesh_contact.h"
#include "dem/samples/ballast_stone.h"
#include "dem/samples/bubble_pack.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "icosphere.h"

namespace trackbed::dem {
namespace {

using testing::icosphere;

constexpr double kPi = 3.14159265358979323846;

BubblePackSettings setting(double distance, double ratio) {
  BubblePackSettings s;
  s.distance = distance;
  s.ratio = ratio;
  return s;
}

// Brute-force distance from p to the surface.
double distance_to(const TriangleMesh& mesh, const Vec3& p) {
  double nearest = std::numeric_limits<double>::infinity();
  for (const auto& t : mesh.triangles) {
    const Vec3 q =
        closest_point_on_triangle(p, mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]])
            .point;
    nearest = std::min(nearest, (p - q).norm());
  }
  return nearest;
}

// Inside a convex surface: behind every face plane.
bool inside_convex(const TriangleMesh& mesh, const Vec3& p) {
  for (int t = 0; t < static_cast<int>(mesh.triangles.size()); ++t) {
    if (mesh.triangle_normal(t).dot(p - mesh.vertices[mesh.triangles[t][0]]) >= 0.0) return false;
  }
  return true;
}

// A sphere mesh holds one pebble, at the grid point nearest its centre (x0, a fraction of a cell
// off). A candidate at rho from the centre on the far side escapes the Distance rule only if
// 2 r r0 (1 + cos phi) < 4 rho |x0|; with r >= R r0 that needs phi above 160 degrees at R = 0.5.
TEST(BubblePack, SphereGivesOnePebble) {
  const double r = 0.02;
  const Vec3 centre(0.3, -0.1, 0.05);
  const TriangleMesh sphere = icosphere(r, 3, centre);
  double inscribed = r;  // distance from the centre to the nearest face plane
  for (int t = 0; t < static_cast<int>(sphere.triangles.size()); ++t) {
    inscribed = std::min(
        inscribed, sphere.triangle_normal(t).dot(sphere.vertices[sphere.triangles[t][0]] - centre));
  }
  for (double distance : {60.0, 120.0, 150.0}) {
    const BubblePackResult p = bubble_pack(sphere, setting(distance, 0.5), "ball");
    ASSERT_EQ(p.pebble_count(), 1) << distance;
    // The grid points nearest the centre are half a cell off along each axis, sqrt(3)/2 cells in
    // all, so the radius is short of the inscribed one by at most that.
    const double cell = 2.0 * r / 64.0;
    EXPECT_LE(p.max_radius, inscribed);
    EXPECT_GE(p.max_radius, inscribed - std::sqrt(3.0) / 2.0 * cell);
    EXPECT_LE((p.pebbles[0].centre - centre).norm(), std::sqrt(3.0) / 2.0 * cell + 1e-15);
  }
}

// A 3 x 2 x 1 box: more pebbles and a tighter fit as Distance rises, more pebbles as Ratio falls.
TEST(BubblePack, BoxRespondsToDistanceAndRatio) {
  const TriangleMesh box = make_box_mesh(Vec3(0, 0, 0), Vec3(0.03, 0.02, 0.01), false);
  int previous_count = 0;
  double previous_error = 1.0;
  for (double distance : {90.0, 120.0, 140.0, 160.0}) {
    const BubblePackResult p = bubble_pack(box, setting(distance, 0.4), "box");
    EXPECT_GT(p.pebble_count(), previous_count) << distance;
    EXPECT_LT(p.volume_error, 0.0) << distance;  // pebbles lie inside
    EXPECT_LT(std::abs(p.volume_error), previous_error) << distance;
    previous_count = p.pebble_count();
    previous_error = std::abs(p.volume_error);
  }
  std::vector<int> counts;
  for (double ratio : {0.9, 0.7, 0.5, 0.3, 0.15}) {
    const BubblePackResult p = bubble_pack(box, setting(130.0, ratio), "box");
    counts.push_back(p.pebble_count());
    EXPECT_GE(p.min_radius, ratio * p.max_radius) << ratio;
  }
  for (std::size_t i = 1; i < counts.size(); ++i) EXPECT_GE(counts[i], counts[i - 1]);
  EXPECT_GT(counts.back(), counts.front());
}

// The Distance rule between every pair of pebbles: the smaller one was accepted, so it is at
// least d = sqrt(r1^2 + r2^2 + 2 r1 r2 cos(phi)) from the larger; and each pebble is a largest
// inscribed sphere, centre inside, radius its distance to the surface.
TEST(BubblePack, PebblesObeyTheDistanceRuleAndStayInside) {
  const TriangleMesh stone = make_ballast_stone(11);
  for (const auto& [distance, ratio] : {std::pair{120.0, 0.5}, std::pair{130.0, 0.4}}) {
    const BubblePackResult p = bubble_pack(stone, setting(distance, ratio), "stone");
    const double c = std::cos(distance * kPi / 180.0);
    for (int i = 0; i < p.pebble_count(); ++i) {
      const SphereShape& a = p.pebbles[i];
      EXPECT_TRUE(inside_convex(stone, a.centre)) << i;
      EXPECT_NEAR(a.radius, distance_to(stone, a.centre), 1e-15) << i;
      for (int j = 0; j < i; ++j) {
        const SphereShape& b = p.pebbles[j];
        EXPECT_GE(b.radius, a.radius);  // largest first
        const double d2 = a.radius * a.radius + b.radius * b.radius + 2 * a.radius * b.radius * c;
        EXPECT_GE((a.centre - b.centre).squaredNorm(), d2) << i << " " << j;
      }
    }
  }
}

// Surface source: volume, centroid, moments and frame are those of closed_mesh_mass_properties;
// pebble source: those of the union of the pebbles. The error measures follow their definitions.
TEST(BubblePack, MassPropertiesFromTheChosenSource) {
  TriangleMesh stone = make_ballast_stone(5);
  stone.rotate(Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).matrix(), Vec3::Zero());
  stone.translate(Vec3(2.0, -1.0, 0.5));
  const MeshMassProperties mesh = closed_mesh_mass_properties(stone);

  BubblePackSettings s = setting(130.0, 0.4);
  const BubblePackResult surface = bubble_pack(stone, s, "stone");
  EXPECT_NEAR(surface.clump.volume, mesh.volume, 1e-15 * mesh.volume);
  EXPECT_LT((surface.clump.input_centroid - mesh.centroid).norm(), 1e-15);
  const Mat3 a = surface.clump.input_axes;
  const Mat3 diagonal = a.transpose() * mesh.inertia * a;
  const double scale = mesh.inertia.norm();
  EXPECT_LT((diagonal - Mat3(surface.clump.principal_moments.asDiagonal())).norm(), 1e-12 * scale);
  EXPECT_NEAR(a.determinant(), 1.0, 1e-12);
  for (int i = 0; i < surface.pebble_count(); ++i) {
    const Vec3 back = mesh.centroid + a * surface.clump.spheres[i].centre;
    EXPECT_LT((back - surface.pebbles[i].centre).norm(), 1e-15);
  }

  s.mass_source = MassSource::pebbles;
  const BubblePackResult pebbles = bubble_pack(stone, s, "stone");
  const MassProperties union_mp = sphere_union_mass_properties(pebbles.pebbles);
  EXPECT_DOUBLE_EQ(pebbles.clump.volume, union_mp.volume);
  EXPECT_LT(pebbles.clump.volume, surface.clump.volume);
  EXPECT_NEAR(surface.volume_error, (union_mp.volume - mesh.volume) / mesh.volume, 1e-12);
  EXPECT_NEAR(surface.inertia_error, (union_mp.inertia - mesh.inertia).norm() / scale, 1e-12);
}

// make_clump_template_with_mass refuses what no packing could give: no pebbles, a bad pebble, or
// mass properties that are not those of a solid.
TEST(BubblePack, GivenMassPropertiesAreChecked) {
  const MassProperties good = sphere_union_mass_properties({{Vec3::Zero(), 0.01}});
  const std::vector<SphereShape> one = {{Vec3::Zero(), 0.01}};
  EXPECT_EQ(make_clump_template_with_mass("ok", one, good).spheres.size(), 1u);
  MassProperties flat = good;
  flat.principal_moments[0] = 0.0;
  const std::vector<std::pair<std::vector<SphereShape>, MassProperties>> bad = {
      {{}, good}, {{{Vec3::Zero(), -0.01}}, good}, {one, flat}};
  for (const auto& [spheres, mass] : bad) {
    try {
      make_clump_template_with_mass("stone3", spheres, mass);
      ADD_FAILURE() << "accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("clump template 'stone3'"), std::string::npos)
          << e.what();
    }
  }
}

TEST(BubblePack, Deterministic) {
  const TriangleMesh stone = make_ballast_stone(8);
  const BubblePackResult a = bubble_pack(stone, setting(130.0, 0.4), "a");
  const BubblePackResult b = bubble_pack(stone, setting(130.0, 0.4), "b");
  ASSERT_EQ(a.pebble_count(), b.pebble_count());
  for (int i = 0; i < a.pebble_count(); ++i) {
    EXPECT_EQ(a.pebbles[i].centre, b.pebbles[i].centre);
    EXPECT_EQ(a.pebbles[i].radius, b.pebbles[i].radius);
  }
}

TEST(BubblePack, RefusesSettingsOutOfRangeAndBadSurfaces) {
  const TriangleMesh box = make_box_mesh(Vec3(0, 0, 0), Vec3(1, 1, 1), false);
  const std::vector<std::pair<BubblePackSettings, std::string>> bad = {
      {setting(0.0, 0.5), "distance 0 is not valid"},
      {setting(180.5, 0.5), "distance 180.5 is not valid"},
      {setting(120.0, 0.0), "ratio 0 is not valid"},
      {setting(120.0, 1.2), "ratio 1.2 is not valid"}};
  for (const auto& [s, message] : bad) {
    try {
      bubble_pack(box, s, "stone7.stl");
      ADD_FAILURE() << message;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("stone7.stl: bubble pack " + message), std::string::npos)
          << e.what();
    }
  }
  BubblePackSettings coarse = setting(120.0, 0.5);
  coarse.resolution = 4;
  EXPECT_THROW(bubble_pack(box, coarse, "x"), InputError);
  // Two plates a tenth of a cell thick, 2.4 cells apart: the three layers of grid points
  // (0.25, 1.25 and 2.25 cells up) all miss them, so there is nothing to pack.
  const double h = 1.0 / 64;
  TriangleMesh plates = make_box_mesh(Vec3(0, 0, 0), Vec3(1, 1, 0.1 * h), false);
  const TriangleMesh upper = make_box_mesh(Vec3(0, 0, 2.4 * h), Vec3(1, 1, 2.5 * h), false);
  for (const auto& t : upper.triangles) plates.triangles.push_back({t[0] + 8, t[1] + 8, t[2] + 8});
  plates.vertices.insert(plates.vertices.end(), upper.vertices.begin(), upper.vertices.end());
  plates.triangle_part.assign(plates.triangles.size(), 0);
  plates.finalize();
  try {
    bubble_pack(plates, setting(120.0, 0.5), "plates");
    ADD_FAILURE() << "packed plates thinner than a cell";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("plates: no point of the bubble-pack grid"),
              std::string::npos)
        << e.what();
  }
  TriangleMesh inward = box;
  for (auto& t : inward.triangles) std::swap(t[1], t[2]);
  inward.finalize();
  EXPECT_THROW(bubble_pack(inward, setting(120.0, 0.5), "inward"), InputError);
}

}  // namespace
}  // namespace trackbed::dem
