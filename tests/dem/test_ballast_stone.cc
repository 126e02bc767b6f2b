// Ballast stones and shape indices (dem/samples/ballast_stone.h): exact indices of boxes and a
// tetrahedron, and the statistics of generated stones against the ranges in docs/templates.md.
#include "dem/samples/ballast_stone.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "common/input_error.h"
#include "dem/samples/closed_surface.h"
#include "icosphere.h"

namespace trackbed::dem {
namespace {

constexpr double kPi = 3.14159265358979323846;

TriangleMesh moved(TriangleMesh mesh) {
  mesh.rotate(Eigen::AngleAxisd(0.9, Vec3(-1, 2, 0.5).normalized()).matrix(), Vec3::Zero());
  mesh.translate(Vec3(3.0, -2.0, 1.0));
  return mesh;
}

// A box L x I x S, rotated and moved: its principal axes are its edges, so every index is exact.
TEST(ShapeIndices, BoxIsExact) {
  const double l = 0.05, i = 0.04, s = 0.03;
  const ShapeIndices box = shape_indices(moved(make_box_mesh(Vec3::Zero(), Vec3(i, s, l), false)));
  EXPECT_NEAR(box.longest, l, 1e-15);
  EXPECT_NEAR(box.intermediate, i, 1e-15);
  EXPECT_NEAR(box.shortest, s, 1e-15);
  EXPECT_NEAR(box.elongation, i / l, 1e-13);
  EXPECT_NEAR(box.flatness, s / i, 1e-13);
  const double v = l * i * s, a = 2 * (l * i + i * s + s * l);
  EXPECT_NEAR(box.sphericity, std::cbrt(36 * kPi * v * v) / a, 1e-13);
  EXPECT_NEAR(box.angularity, 90.0, 1e-9);  // the face diagonals are flat and do not count
  EXPECT_EQ(box.faces, 6);
  EXPECT_NEAR(box.sieve_size, i, 1e-15);  // S > 0.414 I: it passes square-on

  // A flat box passes the aperture diagonally: (I + S) / sqrt(2) < I.
  const ShapeIndices flat = shape_indices(make_box_mesh(Vec3::Zero(), Vec3(l, i, 0.01), false));
  EXPECT_NEAR(flat.sieve_size, (i + 0.01) / std::sqrt(2.0), 1e-15);
}

// Regular tetrahedron of edge a: exterior dihedral angle 180 - acos(1/3) = 109.47 degrees;
// V = a^3 / (6 sqrt 2) and A = sqrt(3) a^2 give the sphericity 0.6711.
TEST(ShapeIndices, RegularTetrahedron) {
  TriangleMesh t;
  t.vertices = {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};
  t.triangles = {{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 3, 2}};
  t.finalize();
  const ShapeIndices s = shape_indices(t);
  EXPECT_NEAR(s.angularity, 180.0 - std::acos(1.0 / 3.0) * 180.0 / kPi, 1e-9);
  const double edge = std::sqrt(8.0);
  const double v = edge * edge * edge / (6 * std::sqrt(2.0)), a = std::sqrt(3.0) * edge * edge;
  EXPECT_NEAR(s.sphericity, std::cbrt(36 * kPi * v * v) / a, 1e-12);
  EXPECT_NEAR(s.sphericity, 0.6711, 1e-4);
  EXPECT_EQ(s.faces, 4);
}

// A fine sphere mesh: sphericity near 1, every face its own (creases above 1 degree), small
// angularity.
TEST(ShapeIndices, SphereMeshIsRoundAndBarelyAngular) {
  const ShapeIndices s = shape_indices(testing::icosphere(0.02, 3));
  EXPECT_GT(s.sphericity, 0.99);
  EXPECT_LT(s.angularity, 6.0);
  EXPECT_EQ(s.faces, 1280);
  EXPECT_NEAR(s.elongation, 1.0, 0.02);
}

// 200 stones: each a valid closed surface in its principal frame, sieve size in the grading
// range, every index within the bounds of docs/templates.md, and the means and shares of flaky
// and elongated stones within the documented targets.
TEST(BallastStone, StatisticsWithinTheDocumentedRanges) {
  const int n = 200;
  double elongation = 0, flatness = 0, sphericity = 0, angularity = 0, faces = 0;
  int flaky = 0, non_cubical = 0;
  for (int seed = 1; seed <= n; ++seed) {
    const TriangleMesh stone = make_ballast_stone(seed);
    check_closed_surface(stone, "stone " + std::to_string(seed));
    const MeshMassProperties mp = closed_mesh_mass_properties(stone);
    const double size = std::cbrt(mp.volume);
    EXPECT_LT(mp.centroid.norm(), 1e-9 * size) << seed;
    const double offdiagonal =
        std::abs(mp.inertia(0, 1)) + std::abs(mp.inertia(0, 2)) + std::abs(mp.inertia(1, 2));
    EXPECT_LT(offdiagonal, 1e-9 * mp.inertia.trace()) << seed;
    EXPECT_LE(mp.inertia(0, 0), mp.inertia(1, 1)) << seed;  // x the axis of the smallest moment

    const ShapeIndices s = shape_indices(stone);
    EXPECT_GE(s.sieve_size, 0.0224 * (1 - 1e-12)) << seed;
    EXPECT_LE(s.sieve_size, 0.063 * (1 + 1e-12)) << seed;
    EXPECT_GE(s.elongation, 0.35) << seed;
    EXPECT_GE(s.flatness, 0.40) << seed;
    EXPECT_GE(s.sphericity, 0.65) << seed;
    EXPECT_LE(s.sphericity, 0.92) << seed;
    EXPECT_GE(s.angularity, 25.0) << seed;
    EXPECT_LE(s.angularity, 65.0) << seed;
    EXPECT_GE(s.faces, 10) << seed;
    EXPECT_LE(s.faces, 40) << seed;
    elongation += s.elongation / n;
    flatness += s.flatness / n;
    sphericity += s.sphericity / n;
    angularity += s.angularity / n;
    faces += static_cast<double>(s.faces) / n;
    if (s.flatness < 0.625) ++flaky;                  // EN 933-3, approximately (BRE)
    if (s.longest > 3.0 * s.shortest) ++non_cubical;  // EN 933-4
  }
  EXPECT_GT(elongation, 0.65);
  EXPECT_LT(elongation, 0.80);
  EXPECT_GT(flatness, 0.65);
  EXPECT_LT(flatness, 0.82);
  EXPECT_GT(sphericity, 0.78);
  EXPECT_LT(sphericity, 0.86);
  EXPECT_GT(angularity, 35.0);
  EXPECT_LT(angularity, 47.0);
  EXPECT_GT(faces, 17.0);
  EXPECT_LT(faces, 26.0);
  EXPECT_LE(flaky, n * 30 / 100);
  EXPECT_LE(non_cubical, n * 10 / 100);
}

TEST(BallastStone, DeterministicForASeed) {
  const TriangleMesh a = make_ballast_stone(42), b = make_ballast_stone(42);
  const TriangleMesh c = make_ballast_stone(43);
  ASSERT_EQ(a.vertices.size(), b.vertices.size());
  for (std::size_t i = 0; i < a.vertices.size(); ++i) EXPECT_EQ(a.vertices[i], b.vertices[i]);
  EXPECT_EQ(a.triangles, b.triangles);
  EXPECT_FALSE(a.vertices.size() == c.vertices.size() && a.vertices[0] == c.vertices[0]);
}

TEST(BallastStone, SieveSizeFromTheSettings) {
  BallastStoneSettings s;
  s.min_sieve_size = s.max_sieve_size = 0.04;
  EXPECT_NEAR(shape_indices(make_ballast_stone(3, s)).sieve_size, 0.04, 1e-15);
  s.min_sieve_size = 0.05;
  s.max_sieve_size = 0.04;
  try {
    make_ballast_stone(3, s);
    ADD_FAILURE() << "accepted min > max";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("sieve sizes 0.05 to 0.04 m are not valid"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace trackbed::dem
