// Closed surfaces (dem/samples/closed_surface.h): the surfaces refused and their messages, the
// self-intersection search on a large mesh, and the signed distance.
#include "common/input_error.h"
#include "dem/engine/mesh_contact.h"
#include "dem/samples/closed_surface.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include "icosphere.h"
#include "input_error_message.h"

namespace trackbed::dem {
namespace {

using testing::contains;
using testing::icosphere;
using testing::input_error_message;

TriangleMesh box(const Vec3& lower, const Vec3& upper) {
  return make_box_mesh(lower, upper, false);
}

// Two boxes as one mesh: no shared vertices, each closed, so the whole is closed and encloses a
// positive volume.
TriangleMesh two_boxes(const Vec3& shift) {
  TriangleMesh a = box(Vec3::Zero(), Vec3(1, 1, 1));
  const TriangleMesh b = box(shift, shift + Vec3(1, 1, 1));
  const int offset = static_cast<int>(a.vertices.size());
  a.vertices.insert(a.vertices.end(), b.vertices.begin(), b.vertices.end());
  for (auto t : b.triangles) a.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
  a.triangle_part.assign(a.triangles.size(), 0);
  a.finalize();
  return a;
}

TEST(ClosedSurface, AcceptsBoxesSpheresAndSeparateParts) {
  check_closed_surface(box(Vec3(-1, 0, 2), Vec3(3, 0.5, 2.25)), "box");
  check_closed_surface(icosphere(0.02, 3), "sphere");
  check_closed_surface(two_boxes(Vec3(1.5, 0.2, 0.0)), "apart");
}

TEST(ClosedSurface, RefusesAnOpenBox) {
  TriangleMesh mesh = box(Vec3::Zero(), Vec3(1, 1, 1));
  mesh.triangles.pop_back();
  mesh.triangle_part.pop_back();
  mesh.finalize();
  const std::string e = input_error_message([&] { check_closed_surface(mesh, "open.stl"); });
  EXPECT_TRUE(contains(e, "open.stl: the surface is not closed")) << e;
  EXPECT_TRUE(contains(e, "3 edges with one triangle")) << e;
  EXPECT_TRUE(contains(e, "exactly two triangles")) << e;
}

TEST(ClosedSurface, RefusesAMisorientedTriangle) {
  TriangleMesh mesh = box(Vec3::Zero(), Vec3(1, 1, 1));
  std::swap(mesh.triangles[4][1], mesh.triangles[4][2]);
  mesh.finalize();
  const std::string e = input_error_message([&] { check_closed_surface(mesh, "flipped"); });
  EXPECT_TRUE(contains(e, "flipped: the surface is not closed")) << e;
  EXPECT_TRUE(contains(e, "3 between triangles of opposite orientation")) << e;
}

TEST(ClosedSurface, RefusesAnInwardBox) {
  TriangleMesh mesh = box(Vec3::Zero(), Vec3(1, 1, 1));
  for (auto& t : mesh.triangles) std::swap(t[1], t[2]);
  mesh.finalize();
  ASSERT_TRUE(mesh.is_closed());
  const std::string e = input_error_message([&] { check_closed_surface(mesh, "inward.stl"); });
  EXPECT_TRUE(contains(e, "inward.stl: ")) << e;
  EXPECT_TRUE(contains(e, "volume -1")) << e;
  EXPECT_TRUE(contains(e, "counter-clockwise seen from outside")) << e;
}

// Crossing, overlapping in a common face plane, and mostly inside each other.
TEST(ClosedSurface, RefusesIntersectingBoxes) {
  for (const Vec3& shift : {Vec3(0.5, 0.3, 0.2), Vec3(1.0, 0.3, 0.2), Vec3(0.2, 0.3, 0.1)}) {
    const TriangleMesh mesh = two_boxes(shift);
    ASSERT_TRUE(mesh.is_closed());
    const std::string e = input_error_message([&] { check_closed_surface(mesh, "two.stl"); });
    EXPECT_TRUE(contains(e, "two.stl: the surface intersects itself: triangles")) << e;
  }
}

TEST(ClosedSurface, DegenerateTriangleInAnStlNamesFileAndLine) {
  const std::string path = (std::filesystem::temp_directory_path() /
                            ("trackbed_degenerate_" + std::to_string(::getpid()) + ".stl"))
                               .string();
  std::ofstream(path) << "solid s\n"
                         "facet normal 0 0 1\nouter loop\n"
                         "vertex 0 0 0\nvertex 1 0 0\nvertex 2 0 0\n"
                         "endloop\nendfacet\nendsolid s\n";
  const std::string e = input_error_message([&] { read_closed_surface(path); });
  std::filesystem::remove(path);
  EXPECT_TRUE(contains(e, path + ":2: triangle 0")) << e;
  EXPECT_TRUE(contains(e, "is degenerate")) << e;
  EXPECT_TRUE(contains(e, "non-collinear vertices")) << e;
}

// 81,920 triangles: an O(n^2) pair search would test 3.4e9 pairs (minutes); the grid makes it a
// fraction of a second. A point pushed inward through the opposite side makes it cross itself.
TEST(ClosedSurface, LargeMeshIsCheckedFast) {
  TriangleMesh sphere = icosphere(1.0, 6);
  check_closed_surface(sphere, "big sphere");
  sphere.vertices[0] *= -1.2;  // through the far side
  const std::string e = input_error_message([&] { check_closed_surface(sphere, "dented sphere"); });
  EXPECT_TRUE(contains(e, "dented sphere: the surface intersects itself")) << e;
}

// Signed distances equal the brute-force minimum over all triangles, with the sign of the exact
// sphere wherever the polyhedron and the sphere agree (inside the inscribed, outside the
// circumscribed sphere).
TEST(ClosedSurface, SignedDistanceMatchesBruteForce) {
  const double r = 0.03;
  const TriangleMesh mesh = icosphere(r, 2, Vec3(1.0, 2.0, -0.5));
  const SignedDistance distance(mesh);
  double inscribed = r;
  for (int t = 0; t < static_cast<int>(mesh.triangles.size()); ++t) {
    inscribed = std::min(
        inscribed,
        mesh.triangle_normal(t).dot(mesh.vertices[mesh.triangles[t][0]] - Vec3(1.0, 2.0, -0.5)));
  }
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-2.0 * r, 2.0 * r);
  int inside = 0, outside = 0;
  for (int i = 0; i < 2000; ++i) {
    const Vec3 offset(u(rng), u(rng), u(rng));
    const Vec3 p = Vec3(1.0, 2.0, -0.5) + offset;
    double nearest = std::numeric_limits<double>::infinity();
    for (const auto& t : mesh.triangles) {
      const Vec3 q = closest_point_on_triangle(p, mesh.vertices[t[0]], mesh.vertices[t[1]],
                                               mesh.vertices[t[2]])
                         .point;
      nearest = std::min(nearest, (p - q).norm());
    }
    const double d = distance(p);
    EXPECT_NEAR(std::abs(d), nearest, 1e-15);
    if (offset.norm() < inscribed) {
      EXPECT_LT(d, 0.0);
      ++inside;
    }
    if (offset.norm() > r) {
      EXPECT_GT(d, 0.0);
      ++outside;
    }
  }
  EXPECT_GT(inside, 100);
  EXPECT_GT(outside, 1000);
}

// Around a regular tetrahedron, whose edges and corners are sharper than 90 degrees, the sign
// of a point near an edge or corner is wrong from either face's normal alone; the pseudo-normals
// get every point right (checked against "behind every face plane").
TEST(ClosedSurface, SignedDistanceSignAroundSharpEdges) {
  TriangleMesh t;
  t.vertices = {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};
  t.triangles = {{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 3, 2}};
  t.finalize();
  const SignedDistance distance(t);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  for (int i = 0; i < 20000; ++i) {
    const Vec3 p(u(rng), u(rng), u(rng));
    double outside = -1.0;
    for (int f = 0; f < 4; ++f) {
      outside = std::max(outside, t.triangle_normal(f).dot(p - t.vertices[t.triangles[f][0]]));
    }
    EXPECT_EQ(distance(p) > 0.0, outside > 0.0) << p.transpose();
  }
}

// On a non-convex surface (an L-shaped prism): distances and signs near the concave edge.
TEST(ClosedSurface, SignedDistanceOnANonConvexSurface) {
  // L-shaped outline in the xy plane, counter-clockwise, extruded from z = 0 to 1.
  const std::vector<Vec3> outline = {{0, 0, 0}, {2, 0, 0}, {2, 1, 0},
                                     {1, 1, 0}, {1, 2, 0}, {0, 2, 0}};
  TriangleMesh mesh;
  for (const Vec3& p : outline) mesh.vertices.push_back(p);
  for (const Vec3& p : outline) mesh.vertices.push_back(p + Vec3(0, 0, 1));
  const int n = 6;
  // Caps: fan triangulation from vertex 3, the reflex corner, which keeps every triangle inside.
  for (int k = 4; k < 3 + n - 1; ++k) {
    mesh.triangles.push_back({3, (k + 1) % n, k % n});
    mesh.triangles.push_back({n + 3, n + k % n, n + (k + 1) % n});
  }
  for (int k = 0; k < n; ++k) {
    const int a = k, b = (k + 1) % n;
    mesh.triangles.push_back({a, b, n + b});
    mesh.triangles.push_back({a, n + b, n + a});
  }
  mesh.finalize();
  check_closed_surface(mesh, "L");
  EXPECT_NEAR(closed_mesh_mass_properties(mesh).volume, 3.0, 1e-14);
  const SignedDistance distance(mesh);
  EXPECT_NEAR(distance(Vec3(1.2, 1.2, 0.5)), 0.2, 1e-14);               // outside the inner corner
  EXPECT_NEAR(distance(Vec3(1.2, 1.2, 1.5)), std::sqrt(0.29), 1e-14);   // above it: a top edge
  EXPECT_NEAR(distance(Vec3(0.9, 0.9, 0.5)), -std::sqrt(0.02), 1e-14);  // inside: concave edge
  EXPECT_NEAR(distance(Vec3(0.5, 1.5, 0.3)), -0.3, 1e-14);
}

}  // namespace
}  // namespace trackbed::dem
