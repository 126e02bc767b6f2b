// Convergence with a manufactured solution: the L2 error must fall as h^(p+1) and the H1 error as
// h^p for FE_Q elements of degree p = 1, 2 (Brenner & Scott, "The Mathematical Theory of Finite
// Element Methods", 2008, thm. 5.4.8 and sec. 11.4).
#include <gtest/gtest.h>

#include <cmath>

#include "fem/elastic_body.h"

namespace trackbed::fem {
namespace {

// u_k(x) = a_k sin(pi x) sin(pi y) sin(pi z) + (B x)_k on the unit cube, with lambda = mu = 1
// (E = 2.5, nu = 0.25). The sine part vanishes on the boundary; the linear part makes the
// Dirichlet data non-zero. The body force is f = -mu lap u - (lambda + mu) grad div u:
//   f_k = 3 pi^2 mu a_k S - (lambda + mu) pi^2 (-a_k S + sum_{i != k} a_i c_i c_k s_m),
// S = s_x s_y s_z, s_i = sin(pi x_i), c_i = cos(pi x_i), m the index other than i and k.
class ManufacturedSolution {
 public:
  Vector3 value(const Vector3& x) const {
    Vector3 u{};
    const double S = std::sin(M_PI * x[0]) * std::sin(M_PI * x[1]) * std::sin(M_PI * x[2]);
    for (int k = 0; k < 3; ++k) {
      u[k] = a_[k] * S;
      for (int j = 0; j < 3; ++j) u[k] += b_[k][j] * x[j];
    }
    return u;
  }
  Tensor3 gradient(const Vector3& x) const {
    Tensor3 grad{};
    for (int j = 0; j < 3; ++j) {
      double derivative = M_PI * std::cos(M_PI * x[j]);
      for (int l = 0; l < 3; ++l)
        if (l != j) derivative *= std::sin(M_PI * x[l]);
      for (int k = 0; k < 3; ++k) grad[k][j] = a_[k] * derivative + b_[k][j];
    }
    return grad;
  }
  Vector3 body_force(const Vector3& x) const {
    double s[3], c[3];
    for (int i = 0; i < 3; ++i) {
      s[i] = std::sin(M_PI * x[i]);
      c[i] = std::cos(M_PI * x[i]);
    }
    const double S = s[0] * s[1] * s[2], pi2 = M_PI * M_PI;
    Vector3 f{};
    for (int k = 0; k < 3; ++k) {
      double grad_div = -a_[k] * S;
      for (int i = 0; i < 3; ++i)
        if (i != k) grad_div += a_[i] * c[i] * c[k] * s[3 - i - k];
      f[k] = 3 * pi2 * mu * a_[k] * S - (lambda + mu) * pi2 * grad_div;
    }
    return f;
  }
  static constexpr double lambda = 1.0, mu = 1.0;

 private:
  const double a_[3] = {1.0, -0.5, 0.75};
  const double b_[3][3] = {{0.1, 0.02, 0.0}, {0.0, -0.05, 0.03}, {0.01, 0.0, 0.08}};
};

ErrorNorms solve_on(unsigned int degree, unsigned int n) {
  const ManufacturedSolution exact;
  ElasticBody body(degree, MPI_COMM_WORLD);
  body.make_box({{{0, 0, 0}}, {{1, 1, 1}}, {{n, n, n}}, {}});
  body.set_material(0, {"manufactured", 2.5, 0.25, 1.0});  // lambda = mu = 1
  body.set_gravity({{0, 0, 0}});
  body.set_body_force([&](const Vector3& x) { return exact.body_force(x); });
  for (const char* side : {"xmin", "xmax", "ymin", "ymax", "zmin", "zmax"})
    body.fix(body.boundary_id(side), {{true, true, true}},
             [&](const Vector3& x) { return exact.value(x); });
  SolverParameters solver;
  solver.relative_tolerance = 1e-12;  // far below the discretisation error
  body.set_solver(solver);
  body.setup();
  body.solve_static();
  return body.error_norms([&](const Vector3& x) { return exact.value(x); },
                          [&](const Vector3& x) { return exact.gradient(x); });
}

// Rates from the two finest meshes. The asymptotic rates are p + 1 (L2) and p (H1); measured:
// Q1 1.99 and 1.00 (8 -> 16 cells per side), Q2 3.00 and 2.01 (4 -> 8). The bounds,
// [p + 1 - 0.1, p + 1 + 0.2] and [p - 0.1, p + 0.2], fail for an element or quadrature of the
// wrong order and for a wrong body force or boundary data (the rates then collapse to 0).
void check_rates(unsigned int degree, const std::vector<unsigned int>& meshes) {
  std::vector<ErrorNorms> errors;
  for (const unsigned int n : meshes) errors.push_back(solve_on(degree, n));
  for (std::size_t i = 1; i < errors.size(); ++i) {
    const double l2_rate = std::log2(errors[i - 1].l2 / errors[i].l2);
    const double h1_rate = std::log2(errors[i - 1].h1 / errors[i].h1);
    std::cout << "Q" << degree << " n = " << meshes[i] << ": L2 " << errors[i].l2 << " rate "
              << l2_rate << ", H1 " << errors[i].h1 << " rate " << h1_rate << "\n";
    if (i + 1 == errors.size()) {
      EXPECT_GT(l2_rate, degree + 1 - 0.1);
      EXPECT_LT(l2_rate, degree + 1 + 0.2);
      EXPECT_GT(h1_rate, degree - 0.1);
      EXPECT_LT(h1_rate, degree + 0.2);
    }
  }
}

TEST(FemConvergence, ManufacturedSolutionQ1) {
  check_rates(1, {4, 8, 16});
}
TEST(FemConvergence, ManufacturedSolutionQ2) {
  check_rates(2, {2, 4, 8});
}

}  // namespace
}  // namespace trackbed::fem
