// Normal and oblique impacts against closed-form solutions of the linear contact law.
#include <gtest/gtest.h>

#include <cmath>

#include "sim_builder.h"

namespace trackbed::dem {
namespace {

using testing::floor_at;
using testing::table_with_pair;
using testing::test_material;

// Small overlap (delta/R < 1e-3) so the contact lever arm is R to the tolerances used.
constexpr double kR = 0.02, kK = 1e7, kV = 0.05;

// Runs a ball into a floor (gravity off) and records contact duration, maximum overlap and the
// rebound velocity. dt is 1/400 of the contact time, so durations are good to ~1 dt.
struct Impact {
  double duration = 0, max_overlap = 0;
  Vec3 v_out, w_out;
};

Impact impact_on_floor(double mu, double beta, const Vec3& v_in, double dt,
                       double shear_ratio = 1) {
  Material m = test_material(kK, mu, 0, beta);
  Particles p;
  p.add_ball(Vec3(0, 0, kR + 1e-6), kR, 0, m.density, 0);
  p.v[0] = v_in;
  SimulationSettings s;
  s.time_step = dt;
  s.gravity = Vec3::Zero();
  MaterialTable table = table_with_pair(m, kK);
  ContactProperties pair = table.pair(0, 0);
  pair.ks = shear_ratio * kK;
  table.set_pair(0, 0, pair);
  Simulation sim(std::move(table), std::move(p), s);
  sim.add_plane(floor_at(0));
  Impact out;
  bool touched = false;
  for (int i = 0; i < 100000; ++i) {
    sim.step();
    const double overlap = kR - sim.particles().x[0].z();
    if (sim.planes()[0].force.norm() > 0) {
      touched = true;
      out.duration += dt;
    } else if (touched) {
      break;
    }
    out.max_overlap = std::max(out.max_overlap, overlap);
  }
  out.v_out = sim.particles().v[0];
  out.w_out = sim.particles().w[0];
  return out;
}

double ball_mass() {
  return 2800 * 4.0 / 3.0 * M_PI * kR * kR * kR;
}

TEST(NormalImpact, SpherePlaneDurationAndOverlap) {
  const double m = ball_mass(), T = M_PI * std::sqrt(m / kK);
  const double dt = T / 400;
  const Impact r = impact_on_floor(0.5, 0, Vec3(0, 0, -kV), dt);
  EXPECT_NEAR(r.duration, T, 1.5 * dt);
  EXPECT_NEAR(r.max_overlap, kV * std::sqrt(m / kK), 1e-3 * kV * std::sqrt(m / kK));
  EXPECT_NEAR(r.v_out.z(), kV, 1e-3 * kV);  // elastic: e = 1
}

TEST(NormalImpact, SphereSphereDurationAndOverlap) {
  // Two equal balls, m* = m/2: T = pi sqrt(m*/k), max overlap = v_rel sqrt(m*/k).
  Material mat = test_material(kK);
  Particles p;
  p.add_ball(Vec3(-kR - 1e-6, 0, 0), kR, 0, mat.density, 0);
  p.add_ball(Vec3(kR + 1e-6, 0, 0), kR, 0, mat.density, 1);
  p.v[0] = Vec3(kV, 0, 0);
  p.v[1] = Vec3(-kV, 0, 0);
  const double mstar = ball_mass() / 2, T = M_PI * std::sqrt(mstar / kK), dt = T / 400;
  SimulationSettings s;
  s.time_step = dt;
  s.gravity = Vec3::Zero();
  Simulation sim(table_with_pair(mat, kK), std::move(p), s);
  double duration = 0, max_overlap = 0;
  for (int i = 0; i < 2000; ++i) {
    sim.step();
    const double overlap = 2 * kR - (sim.particles().x[1] - sim.particles().x[0]).norm();
    if (sim.num_contacts() > 0) duration += dt;
    max_overlap = std::max(max_overlap, overlap);
  }
  EXPECT_NEAR(duration, T, 1.5 * dt);
  EXPECT_NEAR(max_overlap, 2 * kV * std::sqrt(mstar / kK), 1e-3 * max_overlap);
  EXPECT_NEAR(sim.particles().v[0].x(), -kV, 1e-3 * kV);
  EXPECT_NEAR(sim.particles().v[1].x(), kV, 1e-3 * kV);
}

TEST(NormalImpact, RestitutionFromDashpotRatio) {
  // Linear spring-dashpot with a non-tensile force: the contact ends when the force, not the
  // overlap, returns to zero (Schwager and Poeschel, Granular Matter 9, 465, 2007):
  //   t_end = (pi - atan(2 b w / (w0 (1 - 2 b^2)) ... )) / w,  e = -d'(t_end) / v0
  // with delta(t) = v0/w exp(-b w0 t) sin(w t), w = w0 sqrt(1 - b^2). Evaluated here directly.
  const double m = ball_mass(), w0 = std::sqrt(kK / m);
  for (double beta : {0.05, 0.2, 0.5}) {
    const double w = w0 * std::sqrt(1 - beta * beta);
    // Force k d + c d' = 0 with c = 2 b m w0  <=>  tan(w t) = -w / (2 b w0 ... ) solved below.
    const double t_end =
        (M_PI - std::atan2(2 * beta * std::sqrt(1 - beta * beta), 1 - 2 * beta * beta)) / w;
    const double ddot = kV * std::exp(-beta * w0 * t_end) *
                        (std::cos(w * t_end) - beta * w0 / w * std::sin(w * t_end));
    const double e = -ddot / kV;
    const double T = M_PI / w;
    const Impact r = impact_on_floor(0.5, beta, Vec3(0, 0, -kV), T / 2000);
    EXPECT_NEAR(r.v_out.z() / kV, e, 2e-3) << "beta " << beta;
    // And the plain formula exp(-b pi / sqrt(1 - b^2)) is the lower bound it must exceed.
    EXPECT_GT(r.v_out.z() / kV, std::exp(-beta * M_PI / std::sqrt(1 - beta * beta)) - 1e-3);
  }
}

TEST(ObliqueImpact, SlidingRegimeMatchesRigidBodyTheory) {
  // Gross sliding throughout (v_t / v_n > 7/2 mu (1 + e)): the tangential impulse is mu times
  // the normal one, so v_t' = v_t - mu (1 + e) v_n and w' R = 5/2 mu (1 + e) v_n.
  const double mu = 0.1, vn = kV, vt = 2 * kV, m = ball_mass();
  const double T = M_PI * std::sqrt(m / kK);
  const Impact r = impact_on_floor(mu, 0, Vec3(vt, 0, -vn), T / 1000);
  EXPECT_NEAR(r.v_out.z(), vn, 1e-3 * vn);
  EXPECT_NEAR(r.v_out.x(), vt - mu * 2 * vn, 1e-3 * vt);
  // Spin about -y for motion along +x on a floor below: w_y = +v/R convention check by sign.
  EXPECT_NEAR(std::abs(r.w_out.y()) * kR, 2.5 * mu * 2 * vn, 1e-3 * 2.5 * mu * 2 * vn);
  EXPECT_GT(r.w_out.y(), 0);  // friction at the bottom, pointing -x, spins the ball about +y
}

TEST(ObliqueImpact, StickingRegimeMatchesTangentialCompliance) {
  // No slip (mu = 100): the contact point moves as a tangential oscillator of stiffness k_t and
  // mass m_t = m / (1 + m R^2 / I) = 2m/7 while the normal contact lasts T = pi / w_n. Its
  // velocity leaves as u' = u cos(w_t T), w_t = sqrt(k_t / m_t): rigid-body impact theory with
  // tangential restitution beta_t = -cos(w_t T) (Walton 1993). With k_t = 2/7 k_n, w_t T = pi:
  // full reversal, u' = -u, and the shear force is back to zero when the normal force is, so
  // no slip at the end. The impulse J = m_t (u' - u) gives v_t' = v_t + J/m, w' = -J R / I.
  const double m = ball_mass(), I = 0.4 * m * kR * kR, vn = kV, vt = 0.3 * kV;
  const double mt = m / (1 + m * kR * kR / I), T = M_PI * std::sqrt(m / kK);
  const double kt = 2.0 / 7.0 * kK;
  const double u_out = vt * std::cos(std::sqrt(kt / mt) * T);
  ASSERT_NEAR(u_out, -vt, 1e-12);
  const double J = mt * (u_out - vt);
  const Impact r = impact_on_floor(100, 0, Vec3(vt, 0, -vn), T / 2000, 2.0 / 7.0);
  EXPECT_NEAR(r.v_out.x(), vt + J / m, 2e-3 * vt);
  EXPECT_NEAR(r.w_out.y(), -J * kR / I, 2e-3 * std::abs(J * kR / I));
}

}  // namespace
}  // namespace trackbed::dem
