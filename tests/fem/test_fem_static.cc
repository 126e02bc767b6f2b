// Quasi-static verification against analytic elasticity: uniaxial and layered columns, the
// Boussinesq-Love stress under a loaded rectangle, and a sleeper in four-point bending.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "fem/boundary_interface.h"
#include "fem/elastic_body.h"

namespace trackbed::fem {
namespace {

constexpr double g = 9.81;

SolverParameters tight() {
  SolverParameters s;
  s.relative_tolerance = 1e-12;
  return s;
}

// A column with free sides under a top pressure p: sigma_zz = -p, u_z = -p z / E,
// u_x = nu p x / E, u_y = nu p y / E. Linear, so Q1 reproduces it exactly and the only error
// is the solver's (relative tolerance 1e-12; 1e-9 leaves three orders of margin for round-off).
void uniaxial_column(const SolverParameters::Method method) {
  ElasticBody body(1, MPI_COMM_WORLD);
  body.make_box({{{0, 0, 0}}, {{1, 1, 2}}, {{2, 2, 4}}, {}});
  const Material m{"soil", 80e6, 0.3, 1900};
  body.set_material(0, m);
  body.set_gravity({{0, 0, 0}});
  body.fix(body.boundary_id("xmin"), {{true, false, false}});
  body.fix(body.boundary_id("ymin"), {{false, true, false}});
  body.fix(body.boundary_id("zmin"), {{false, false, true}});
  const double p = 1e5;
  body.set_traction(body.boundary_id("zmax"), {{0, 0, -p}});
  SolverParameters s = tight();
  s.method = method;
  body.set_solver(s);
  body.setup();
  body.solve_static();
  const std::vector<Vector3> points{{{0.3, 0.7, 1.9}}, {{1.0, 1.0, 2.0}}, {{0.5, 0.1, 0.4}}};
  const auto values = body.probe(points);
  const double u_scale = p * 2.0 / m.youngs_modulus;
  for (std::size_t k = 0; k < points.size(); ++k) {
    const Vector3& x = points[k];
    EXPECT_NEAR(values[k].displacement[0], m.poisson_ratio * p * x[0] / m.youngs_modulus,
                1e-9 * u_scale);
    EXPECT_NEAR(values[k].displacement[1], m.poisson_ratio * p * x[1] / m.youngs_modulus,
                1e-9 * u_scale);
    EXPECT_NEAR(values[k].displacement[2], -p * x[2] / m.youngs_modulus, 1e-9 * u_scale);
    EXPECT_NEAR(values[k].stress[2][2], -p, 1e-9 * p);
    EXPECT_NEAR(values[k].stress[0][0], 0.0, 1e-9 * p);
    EXPECT_NEAR(values[k].stress[0][2], 0.0, 1e-9 * p);
  }
}

TEST(FemStatic, UniaxialColumnCgAmg) {
  uniaxial_column(SolverParameters::Method::cg_amg);
}
TEST(FemStatic, UniaxialColumnDirect) {
  uniaxial_column(SolverParameters::Method::direct);
}

// Quasi-static re-solves: the second solve reuses the preconditioner (no setup time) and, the
// problem being linear, doubling the load doubles the displacement (1e-8 relative: two solves
// to 1e-12).
TEST(FemStatic, ResolveReusesPreconditionerAndIsLinear) {
  ElasticBody body(1, MPI_COMM_WORLD);
  body.make_box({{{0, 0, -2}}, {{2, 2, 0}}, {{6, 6, 6}}, {}});
  body.set_material(0, subgrade_fill());
  body.set_gravity({{0, 0, 0}});
  body.fix(body.boundary_id("zmin"));
  body.mark_boundary("patch", 6, [](const Vector3& c) { return c[2] > -1e-9 && c[0] < 1.0; });
  body.set_traction(body.boundary_id("patch"), {{1e3, 0, -1e4}});
  body.set_solver(tight());
  body.setup();
  const SolveReport first = body.solve_static();
  const Vector3 point{{0.5, 1.0, -0.5}};
  const Vector3 u1 = body.probe({point})[0].displacement;
  body.set_traction(body.boundary_id("patch"), {{2e3, 0, -2e4}});
  const SolveReport second = body.solve_static();
  const Vector3 u2 = body.probe({point})[0].displacement;
  EXPECT_GT(first.preconditioner_seconds, 0.0);
  EXPECT_EQ(second.preconditioner_seconds, 0.0);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(u2[c], 2 * u1[c], 1e-8 * std::abs(u1[2]));
}

// A laterally confined column of three layers under gravity and a top pressure q (the
// oedometric, 1-D state). Equilibrium d sigma_zz / dz = rho g gives
//   sigma_zz(z) = -(q + int_z^H rho g ds),  sigma_xx = sigma_yy = nu / (1 - nu) sigma_zz,
//   u_z(z) = int_0^z sigma_zz / M ds,  M = lambda + 2 mu,
// piecewise quadratic with kinks at the layer interfaces, which are cell faces. Q2 reproduces it
// exactly; Q1 is exact at the nodes (1-D linear elements with an exactly integrated load) and
// its constant strain equals the exact strain at the cell centre.
struct Layer {
  double z_min, z_max;
  Material material;
};

class LayeredColumn {
 public:
  LayeredColumn() {
    layers_ = {
        {0.0, 1.5, natural_ground()}, {1.5, 2.5, subgrade_fill()}, {2.5, 3.0, sub_ballast()}};
  }
  double sigma_zz(double z) const {
    double s = -q_;
    for (const Layer& l : layers_) {
      const double top = l.z_max, bottom = std::max(l.z_min, z);
      if (top > bottom) s -= l.material.density * g * (top - bottom);
    }
    return s;
  }
  const Layer& layer_at(double z) const {
    for (const Layer& l : layers_)
      if (z >= l.z_min && z < l.z_max) return l;
    return layers_.back();
  }
  // Exact integral of the piecewise linear sigma_zz / M: Simpson's rule per layer piece.
  double u_z(double z) const {
    double u = 0.0;
    for (const Layer& l : layers_) {
      const double a = l.z_min, b = std::min(l.z_max, z);
      if (b <= a) continue;
      const double m = l.material.constrained_modulus();
      u += (b - a) / 6.0 * (sigma_zz(a) + 4.0 * sigma_zz(0.5 * (a + b)) + sigma_zz(b)) / m;
    }
    return u;
  }
  void solve(ElasticBody& body) const {
    BoxGeometry box{{{0, 0, 0}}, {{0.5, 0.5, 3.0}}, {{1, 1, 12}}, {}};
    for (unsigned int i = 0; i < layers_.size(); ++i)
      box.layers.push_back({layers_[i].z_min, layers_[i].z_max, i + 2});
    body.make_box(box);
    for (unsigned int i = 0; i < layers_.size(); ++i) body.set_material(i + 2, layers_[i].material);
    for (const char* side : {"xmin", "xmax"})
      body.fix(body.boundary_id(side), {{true, false, false}});
    for (const char* side : {"ymin", "ymax"})
      body.fix(body.boundary_id(side), {{false, true, false}});
    body.fix(body.boundary_id("zmin"));
    body.set_traction(body.boundary_id("zmax"), {{0, 0, -q_}});
    body.set_solver(tight());
    body.setup();
    body.solve_static();
  }

 private:
  std::vector<Layer> layers_;
  double q_ = 2e4;  // Pa, the weight of ~1.2 m of ballast
};

TEST(FemStatic, LayeredColumnUnderGravityQ2) {
  LayeredColumn column;
  ElasticBody body(2, MPI_COMM_WORLD);
  column.solve(body);
  std::vector<Vector3> points;
  for (double z = 0.1; z < 3.0; z += 0.23) points.push_back({{0.17, 0.31, z}});
  const auto values = body.probe(points);
  const double u_scale = std::abs(column.u_z(3.0)), s_scale = std::abs(column.sigma_zz(0.0));
  for (std::size_t k = 0; k < points.size(); ++k) {
    const double z = points[k][2];
    const double nu = column.layer_at(z).material.poisson_ratio;
    EXPECT_NEAR(values[k].displacement[2], column.u_z(z), 1e-9 * u_scale) << "z = " << z;
    EXPECT_NEAR(values[k].displacement[0], 0.0, 1e-9 * u_scale);
    EXPECT_NEAR(values[k].stress[2][2], column.sigma_zz(z), 1e-8 * s_scale) << "z = " << z;
    EXPECT_NEAR(values[k].stress[0][0], nu / (1 - nu) * column.sigma_zz(z), 1e-8 * s_scale);
  }
}

TEST(FemStatic, LayeredColumnUnderGravityQ1NodesAndCentres) {
  LayeredColumn column;
  ElasticBody body(1, MPI_COMM_WORLD);
  column.solve(body);
  std::vector<Vector3> nodes, centres;
  for (unsigned int i = 0; i <= 12; ++i) nodes.push_back({{0.5, 0.0, 0.25 * i}});
  for (unsigned int i = 0; i < 12; ++i) centres.push_back({{0.25, 0.25, 0.25 * i + 0.125}});
  const auto at_nodes = body.probe(nodes), at_centres = body.probe(centres);
  const double u_scale = std::abs(column.u_z(3.0)), s_scale = std::abs(column.sigma_zz(0.0));
  for (std::size_t k = 0; k < nodes.size(); ++k)
    EXPECT_NEAR(at_nodes[k].displacement[2], column.u_z(nodes[k][2]), 1e-9 * u_scale);
  for (std::size_t k = 0; k < centres.size(); ++k)
    EXPECT_NEAR(at_centres[k].stress[2][2], column.sigma_zz(centres[k][2]), 1e-8 * s_scale);
}

// Vertical stress under the corner of a uniformly loaded B x L rectangle on an elastic
// half-space, from Boussinesq's point load integrated by Holl (1940); see Poulos & Davis,
// "Elastic Solutions for Soil and Rock Mechanics", 1974, eq. 3.29:
//   sigma_z = q / (2 pi) [atan(B L / (z R3)) + B L z / R3 (1 / R1^2 + 1 / R2^2)],
//   R1^2 = L^2 + z^2, R2^2 = B^2 + z^2, R3^2 = B^2 + L^2 + z^2.
double holl_corner(double q, double b, double l, double z) {
  const double r1 = std::hypot(l, z), r2 = std::hypot(b, z), r3 = std::sqrt(b * b + l * l + z * z);
  return q / (2 * M_PI) *
         (std::atan(b * l / (z * r3)) + b * l * z / r3 * (1 / (r1 * r1) + 1 / (r2 * r2)));
}

// A 2 m x 2 m footing (a sleeper pair's loaded area) on a quarter of a 12 m x 12 m x 8 m block:
// symmetry planes x = 0 and y = 0, rigid base at 8 m, free far sides. Under the centre the
// stress is 4 times the corner value of a 1 m x 1 m rectangle. Measured deviation with Q2 on
// 0.5 m cells: -0.7 % at 1 m, -1.0 % at 2 m, +2.5 % at 3 m depth, where the rigid base (4 footing
// widths down) attracts stress. Tolerances: 2 % down to 2 m, 5 % at 3 m.
TEST(FemStatic, BoussinesqRectangleUnderCentre) {
  ElasticBody body(2, MPI_COMM_WORLD);
  body.make_box({{{0, 0, -8}}, {{6, 6, 0}}, {{12, 12, 16}}, {}});
  body.set_material(0, {"half-space", 50e6, 0.3, 1900});
  body.set_gravity({{0, 0, 0}});
  body.mark_boundary("footing", 6,
                     [](const Vector3& c) { return c[2] > -1e-9 && c[0] < 1.0 && c[1] < 1.0; });
  const double q = 1e5;
  body.fix(body.boundary_id("xmin"), {{true, false, false}});
  body.fix(body.boundary_id("ymin"), {{false, true, false}});
  body.fix(body.boundary_id("zmin"));
  body.set_traction(body.boundary_id("footing"), {{0, 0, -q}});
  SolverParameters s;
  s.relative_tolerance = 1e-10;
  body.set_solver(s);
  body.setup();
  const SolveReport report = body.solve_static();
  EXPECT_LT(report.iterations, 100u);
  const std::vector<std::pair<double, double>> depth_tolerance{
      {1.0, 0.02}, {2.0, 0.02}, {3.0, 0.05}};
  for (const auto& [depth, tolerance] : depth_tolerance) {
    const double exact = -4.0 * holl_corner(q, 1.0, 1.0, depth);
    const auto value = body.probe({{{0.01, 0.01, -depth}}})[0];
    RecordProperty("relative_deviation_at_" + std::to_string(depth) + "_m",
                   std::to_string(value.stress[2][2] / exact - 1.0));
    EXPECT_NEAR(value.stress[2][2], exact, tolerance * std::abs(exact)) << "depth " << depth;
  }
}

// A B70-like sleeper clamped at its left end and loaded at the right rail seat by Q: a
// cantilever. Timoshenko beam theory gives the deflection under the load, a from the clamp:
//   w = Q a^3 / (3 E I) + Q a / (kappa G A),  kappa = 5/6 (rectangle).
// A clamped face is stiffer than the beam's clamp (it also stops the Poisson contraction and the
// warping of the section) and the load is spread over the rail seat. Measured: -0.45 % with Q2
// on 0.1 m cells (a / h = 10); tolerance 2 %.
TEST(FemStatic, SleeperCantileverMatchesBeamTheory) {
  ElasticBody body(2, MPI_COMM_WORLD);
  SleeperGeometry sleeper;
  sleeper.element_size = 0.1;
  body.make_sleeper(sleeper);
  const Material concrete = sleeper_concrete();
  body.set_material(0, concrete);
  body.set_gravity({{0, 0, 0}});
  const double half = 0.5 * sleeper.length;
  body.mark_boundary("clamp", 7, [&](const Vector3& c) { return c[0] < -half + 1e-9; });
  body.fix(body.boundary_id("clamp"));
  const double Q = 1e5;  // N
  body.set_boundary_force(body.boundary_id("rail_seat_right"), {{0, 0, -Q}});
  body.set_solver(tight());
  body.setup();
  body.solve_static();
  const double a = half + 0.5 * sleeper.rail_seat_spacing;
  const double I = sleeper.width * std::pow(sleeper.height, 3) / 12.0;
  const double A = sleeper.width * sleeper.height;
  const double w = Q * std::pow(a, 3) / (3 * concrete.youngs_modulus * I) +
                   Q * a / (5.0 / 6.0 * concrete.shear_modulus() * A);
  const auto at_load = body.probe({{{-half + a, 0.0, 0.5 * sleeper.height}}})[0];
  RecordProperty("relative_deviation", std::to_string(-at_load.displacement[2] / w - 1.0));
  EXPECT_NEAR(-at_load.displacement[2], w, 0.02 * w);
}

// The track section mesh: the formation under the ballast is 2 b0 wide (b0 from the ballast
// footprint), the bottom is 2 W wide; both over the section length. Their triangle areas must
// add up to that exactly (flat faces), and every layer must have its material. The formation is
// the DEM bed's base in the one TrackSection frame: |x| <= b0, |y| <= length / 2 at z = 0, to
// rounding (1e-12 m on coordinates of metres).
TEST(FemStatic, TrackSectionGeometryAndGravitySolve) {
  TrackSection section;
  section.lower_ballast_thickness = 0.15;
  section.ground_depth = 2.0;
  ElasticBody body(1, MPI_COMM_WORLD);
  body.make_track_section(section, 0.5);
  body.set_material(track_section::lower_ballast_id, lower_ballast_equivalent());
  body.set_material(track_section::sub_ballast_id, sub_ballast());
  body.set_material(track_section::subgrade_id, subgrade_fill());
  body.set_material(track_section::ground_id, natural_ground());
  body.fix(body.boundary_id("bottom"));
  body.fix(body.boundary_id("ends"), {{false, true, false}});
  body.fix(body.boundary_id("sides"), {{true, false, false}});
  body.set_solver(tight());
  body.setup();
  const SolveReport report = body.solve_static();
  EXPECT_GT(report.iterations, 0u);
  double formation = 0.0, bottom = 0.0;
  const BoundaryInterface formation_interface(body, "formation"), bottom_interface(body, "bottom");
  Vector3 lower{{1e9, 1e9, 1e9}}, upper{{-1e9, -1e9, -1e9}};
  for (const auto& t : formation_interface.triangles()) {
    formation += t.area;
    EXPECT_NEAR(t.normal[2], 1.0, 1e-12);
    for (const Vector3& v : t.vertices)
      for (int c = 0; c < 3; ++c) {
        lower[c] = std::min(lower[c], v[c]);
        upper[c] = std::max(upper[c], v[c]);
      }
  }
  const Vector3 base_lower{{-section.half_base_width(), -0.5 * section.length, 0.0}};
  const Vector3 base_upper{{section.half_base_width(), 0.5 * section.length, 0.0}};
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(lower[c], base_lower[c], 1e-12);
    EXPECT_NEAR(upper[c], base_upper[c], 1e-12);
  }
  for (const auto& t : bottom_interface.triangles()) bottom += t.area;
  EXPECT_NEAR(formation, 2 * section.half_base_width() * section.length, 1e-10);
  EXPECT_NEAR(bottom, 2 * section.ground_half_width * section.length, 1e-10);
  // Under gravity the formation centre settles, and more than its shoulder edge.
  const double b0 = section.half_base_width();
  const auto v = body.probe({{{0.0, 0.0, 0.0}}, {{b0 - 1e-3, 0.0, 0.0}}});
  EXPECT_LT(v[0].displacement[2], v[1].displacement[2]);
  EXPECT_LT(v[1].displacement[2], 0.0);
}

}  // namespace
}  // namespace trackbed::fem
