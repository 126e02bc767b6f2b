// The coupling interface: triangles of a named boundary, consistent nodal loads from point forces,
// and the motion of boundary points.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "fem/boundary_interface.h"
#include "fem/elastic_body.h"
#include "fem/errors.h"

namespace trackbed::fem {
namespace {

Vector3 cross(const Vector3& a, const Vector3& b) {
  return {{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]}};
}

// A 2 m x 1 m x 1 m block with its top as the interface, fixed at the base.
void make_block(ElasticBody& body) {
  body.make_box({{{0, 0, -1}}, {{2, 1, 0}}, {{4, 2, 2}}, {}});
  body.set_material(0, sub_ballast());
  body.fix(body.boundary_id("zmin"));
  SolverParameters solver;
  solver.relative_tolerance = 1e-12;
  body.set_solver(solver);
  body.setup();
}

// Random point forces on random points of the triangles, like DEM contacts.
std::vector<PointForce> contact_forces(const BoundaryInterface& interface, unsigned int n) {
  std::mt19937 random(42);
  std::uniform_real_distribution<double> unit(0.0, 1.0), force(-100.0, 100.0);
  std::vector<PointForce> forces;
  for (unsigned int i = 0; i < n; ++i) {
    double b0 = unit(random), b1 = unit(random);
    if (b0 + b1 > 1.0) b0 = 1.0 - b0, b1 = 1.0 - b1;
    const std::size_t t = random() % interface.triangles().size();
    forces.push_back(
        {{t, {{b0, b1, 1.0 - b0 - b1}}}, {{force(random), force(random), -500.0 + force(random)}}});
  }
  return forces;
}

class FemInterface : public ::testing::TestWithParam<unsigned int> {};

// p x p sub-squares of two triangles per face; areas add up to the top area, normals point out.
TEST_P(FemInterface, TrianglesCoverTheBoundary) {
  const unsigned int p = GetParam();
  ElasticBody body(p, MPI_COMM_WORLD);
  make_block(body);
  const BoundaryInterface top(body, "zmax");
  EXPECT_EQ(top.triangles().size(), 4u * 2u * 2u * p * p);
  double area = 0.0;
  for (const InterfaceTriangle& t : top.triangles()) {
    area += t.area;
    EXPECT_NEAR(t.normal[2], 1.0, 1e-12);
    for (const Vector3& v : t.vertices) EXPECT_NEAR(v[2], 0.0, 1e-12);
  }
  EXPECT_NEAR(area, 2.0, 1e-12);
}

// Shape functions are a partition of unity and reproduce linear fields, so the consistent nodal
// loads sum to the applied forces and their moments to the applied moments, to round-off
// (relative 1e-12 of the largest term).
TEST_P(FemInterface, NodalLoadsSumToForcesAndMoments) {
  ElasticBody body(GetParam(), MPI_COMM_WORLD);
  make_block(body);
  BoundaryInterface top(body, "zmax");
  const auto forces = contact_forces(top, 200);
  top.add_forces(forces);
  const Vector3 reference{{0.3, -0.2, 0.5}};
  Vector3 force{}, moment{};
  for (const PointForce& f : forces) {
    Vector3 arm = top.position(f.where);
    for (int c = 0; c < 3; ++c) arm[c] -= reference[c];
    const Vector3 m = cross(arm, f.force);
    for (int c = 0; c < 3; ++c) force[c] += f.force[c], moment[c] += m[c];
  }
  const LoadResultant resultant = body.interface_load_resultant(reference);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(resultant.force[c], force[c], 1e-12 * 200 * 600);
    EXPECT_NEAR(resultant.moment[c], moment[c], 1e-12 * 200 * 600 * 3);
  }
  // Weights of one point: each component's weights sum to 1.
  for (unsigned int c = 0; c < 3; ++c) {
    double sum = 0.0;
    for (const ShapeWeight& w : top.shape_weights(forces[0].where))
      if (w.component == c) sum += w.weight;
    EXPECT_NEAR(sum, 1.0, 1e-12);
  }
  top.clear_forces();
  EXPECT_NEAR(body.interface_load_resultant(reference).force[2], 0.0, 1e-12);
  EXPECT_THROW(top.position({top.triangles().size(), {{1.0, 0.0, 0.0}}}), InputError);
}

// After a solve under the point forces, the displacement interpolated through the triangles
// equals the FE field evaluated at the same points (relative 1e-10: both evaluate the same shape
// functions, at reference points that differ by round-off). After Newmark steps the same holds
// for the velocity.
TEST_P(FemInterface, BoundaryMotionEqualsFeField) {
  ElasticBody body(GetParam(), MPI_COMM_WORLD);
  make_block(body);
  BoundaryInterface top(body, "zmax");
  const auto forces = contact_forces(top, 50);
  top.add_forces(forces);
  body.solve_static();
  std::vector<TrianglePoint> points;
  std::vector<Vector3> positions;
  for (std::size_t i = 0; i < forces.size(); i += 5) {
    points.push_back(forces[i].where);
    positions.push_back(top.position(forces[i].where));
  }
  auto compare = [&](int which) {
    const auto motion = top.motion(points);
    const auto field = body.probe(positions);
    double scale = 0.0;
    for (const auto& v : field)
      for (int c = 0; c < 3; ++c)
        scale = std::max(scale, std::abs(which == 0 ? v.displacement[c] : v.velocity[c]));
    ASSERT_GT(scale, 0.0);
    for (std::size_t k = 0; k < points.size(); ++k)
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(motion[k][which][c],
                    which == 0 ? field[k].displacement[c] : field[k].velocity[c], 1e-10 * scale);
  };
  compare(0);
  NewmarkParameters newmark;
  newmark.time_step = 1e-4;
  body.start_dynamics(newmark);
  top.clear_forces();  // unloading: the block springs back
  for (int step = 0; step < 3; ++step) body.advance();
  compare(0);
  compare(1);
}

INSTANTIATE_TEST_SUITE_P(Degrees, FemInterface, ::testing::Values(1u, 2u));

}  // namespace
}  // namespace trackbed::fem
