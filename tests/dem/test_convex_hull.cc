// Convex hulls (dem/samples/convex_hull.h): exact polyhedra, degenerate point sets, random points.
#include "dem/samples/convex_hull.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "common/input_error.h"

namespace trackbed::dem {
namespace {

// Largest distance of p outside the hull's face planes: <= 0 inside, 0 on the surface.
double outside_distance(const TriangleMesh& hull, const Vec3& p) {
  double worst = -std::numeric_limits<double>::infinity();
  for (int t = 0; t < static_cast<int>(hull.triangles.size()); ++t) {
    worst = std::max(worst, hull.triangle_normal(t).dot(p - hull.vertices[hull.triangles[t][0]]));
  }
  return worst;
}

double diagonal(const std::vector<Vec3>& points) {
  Vec3 lo = points[0], hi = points[0];
  for (const Vec3& p : points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  return (hi - lo).norm();
}

std::vector<Vec3> unit_cube_corners() {
  std::vector<Vec3> c;
  for (int i = 0; i < 8; ++i) c.emplace_back(i & 1, (i >> 1) & 1, (i >> 2) & 1);
  return c;
}

// The corners of a cube with points on its faces, on its edges, inside it, and repeated within a
// billionth: only the corners may become vertices, and the volume is exact because the corners
// are exactly on the rounding grid.
TEST(ConvexHull, CubeWithCoplanarCollinearAndRepeatedPoints) {
  std::vector<Vec3> points = unit_cube_corners();
  // Repeats moved a billionth inward, so that the bounding box stays the cube.
  for (int i = 0; i < 8; ++i) {
    points.push_back(points[i] + 1e-9 * (Vec3::Constant(0.5) - points[i]).normalized());
  }
  for (int k = 0; k < 3; ++k) {
    Vec3 face = Vec3::Constant(0.5), edge = Vec3::Zero();
    face[k] = 1.0;
    edge[k] = 0.5;
    points.push_back(face);
    points.push_back(edge);
  }
  points.emplace_back(0.3, 0.6, 0.2);
  points.emplace_back(0.25, 0.0, 0.75);  // on the face y = 0
  const TriangleMesh hull = convex_hull(points);
  EXPECT_TRUE(hull.is_closed());
  EXPECT_EQ(hull.vertices.size(), 8u);
  EXPECT_EQ(hull.triangles.size(), 12u);
  const MeshMassProperties mp = closed_mesh_mass_properties(hull);
  EXPECT_NEAR(mp.volume, 1.0, 1e-14);
  EXPECT_LT((mp.centroid - Vec3::Constant(0.5)).norm(), 1e-14);
  for (const Vec3& p : points) EXPECT_LE(outside_distance(hull, p), 1e-8);
}

TEST(ConvexHull, TetrahedronVolume) {
  const std::vector<Vec3> points = {
      {0.1, 0.2, 0.3}, {1.3, 0.1, 0.2}, {0.4, 1.1, 0.1}, {0.5, 0.4, 1.7}, {0.5, 0.45, 0.6}};
  const TriangleMesh hull = convex_hull(points);
  EXPECT_EQ(hull.triangles.size(), 4u);
  const double exact =
      std::abs((points[1] - points[0]).cross(points[2] - points[0]).dot(points[3] - points[0])) /
      6.0;
  // Each coordinate is rounded by at most 2^-18 of the largest extent (3.8e-6), which changes
  // this volume by at most about 1e-5 of itself: 1e-4 leaves a margin and would catch any error
  // in the topology (a missing or doubled face changes it by far more).
  EXPECT_NEAR(closed_mesh_mass_properties(hull).volume, exact, 1e-4 * exact);
  EXPECT_LT(outside_distance(hull, points[4]), 0.0);
}

// Random points inside a box plus its corners: the hull is the box exactly; random points in a
// ball: every point is inside or on the hull, and every hull vertex is one of the points.
TEST(ConvexHull, RandomPoints) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Vec3> box;
  for (const Vec3& c : unit_cube_corners()) box.push_back(c.cwiseProduct(Vec3(2.0, 1.0, 0.5)));
  for (int i = 0; i < 50; ++i) box.emplace_back(2.0 * u(rng), u(rng), 0.5 * u(rng));
  const TriangleMesh box_hull = convex_hull(box);
  EXPECT_EQ(box_hull.vertices.size(), 8u);
  EXPECT_NEAR(closed_mesh_mass_properties(box_hull).volume, 1.0, 1e-14);

  for (int n : {10, 30, 60, 300}) {
    std::vector<Vec3> ball;
    while (static_cast<int>(ball.size()) < n) {
      const Vec3 p(2 * u(rng) - 1, 2 * u(rng) - 1, 2 * u(rng) - 1);
      if (p.norm() <= 1.0) ball.push_back(p + Vec3(5.0, -3.0, 2.0));
    }
    const TriangleMesh hull = convex_hull(ball);
    ASSERT_TRUE(hull.is_closed()) << n;
    EXPECT_GT(closed_mesh_mass_properties(hull).volume, 0.0);
    // The rounding (up to 2^-18 of the extent per coordinate) and the on-hull tolerance, 1e-5
    // of the diagonal, are the only ways a point can stick out.
    const double tol = (kConvexHullTolerance + 1e-5) * diagonal(ball);
    for (const Vec3& p : ball) EXPECT_LE(outside_distance(hull, p), tol) << n;
    for (const Vec3& v : hull.vertices) {
      double nearest = std::numeric_limits<double>::infinity();
      for (const Vec3& p : ball) nearest = std::min(nearest, (p - v).norm());
      EXPECT_LT(nearest, 1e-5 * diagonal(ball)) << n;
    }
    // Convex: every vertex is behind every face.
    for (const Vec3& v : hull.vertices) EXPECT_LE(outside_distance(hull, v), tol) << n;
  }
}

TEST(ConvexHull, RefusesPointSetsWithoutVolume) {
  std::vector<Vec3> plane;
  for (int i = 0; i < 20; ++i) plane.emplace_back(std::cos(i), std::sin(i), 0.2 * i);
  for (Vec3& p : plane) p.z() = 0.5 * p.x() + 0.25 * p.y();
  const std::vector<std::vector<Vec3>> bad = {
      {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)},
      {Vec3(0, 0, 0), Vec3(1, 1, 1), Vec3(2, 2, 2), Vec3(3, 3, 3)},
      {Vec3(1, 2, 3), Vec3(1, 2, 3), Vec3(1, 2, 3), Vec3(1, 2, 3)},
      plane};
  for (const auto& points : bad) {
    try {
      convex_hull(points);
      ADD_FAILURE() << "accepted " << points.size() << " points without volume";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("span no volume"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("at least 4 points"), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(convex_hull({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, NAN)}),
               InputError);
}

}  // namespace
}  // namespace trackbed::dem
