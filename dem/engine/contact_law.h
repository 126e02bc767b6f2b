// The PFC "linear" and "rolling resistance linear" contact laws, composed of small parts in the
// manner of LAMMPS/LIGGGHTS granular models: a normal part, a tangential part and a rolling part.
// The same law serves sphere-sphere, sphere-plane and sphere-triangle contacts.
// Equations and sources: docs/theory.md, "Contact law".
#pragma once

#include <algorithm>
#include <cmath>

#include "dem/engine/material.h"
#include "dem/engine/types.h"

namespace trackbed::dem {

// Kinematics of one contact between side i and side j; n points from i toward j.
struct ContactKinematics {
  Vec3 n;          // unit normal
  double overlap;  // > 0, m
  Vec3 v_rel;      // velocity of j's contact point minus i's, m/s
  Vec3 w_rel;      // angular velocity of j minus i, rad/s
  double m_eff;    // m_i m_j / (m_i + m_j), kg (m_j for a wall)
  double r_eff;    // r_i r_j / (r_i + r_j), m (r_j for a wall)
};

// Energy dissipated by one contact in one step, J.
struct Dissipation {
  double friction = 0;  // Coulomb slip
  double rolling = 0;   // rolling-resistance slip
  double dashpot = 0;   // normal and shear dashpots
  Dissipation& operator+=(const Dissipation& o) {
    friction += o.friction, rolling += o.rolling, dashpot += o.dashpot;
    return *this;
  }
};

// Rotates a history vector into the current contact plane, keeping its magnitude (the contact
// plane turns with the bodies; the spring must follow it).
inline void rotate_into_plane(Vec3& h, const Vec3& n) {
  const double before = h.squaredNorm();
  if (before == 0) return;
  h -= n.dot(h) * n;
  const double after = h.squaredNorm();
  if (after > 0) h *= std::sqrt(before / after);
}

// The dashpot coefficients, N s/m: c_n is the LAMMPS form gamma_n m_eff plus the critical-ratio
// form 2 beta_n sqrt(m_eff k_n); c_s = 2 beta_s sqrt(m_eff k_s). The critical time step sums them
// per body like the stiffnesses (docs/theory.md, "Critical timestep").
inline double normal_dashpot(const ContactProperties& p, double m_eff) {
  return p.normal_damping_rate * m_eff + 2 * p.normal_damping_ratio * std::sqrt(m_eff * p.kn);
}
inline double shear_dashpot(const ContactProperties& p, double m_eff) {
  return p.shear_damping_ratio > 0 ? 2 * p.shear_damping_ratio * std::sqrt(m_eff * p.ks) : 0.0;
}

// Normal part: F_n = k_n * overlap - c_n * v_n, never tensile.
inline double normal_force(const ContactProperties& p, const ContactKinematics& k, double vn) {
  return std::max(p.kn * k.overlap - normal_dashpot(p, k.m_eff) * vn, 0.0);
}

// Incremental spring with a Coulomb (or rolling) cap: s <- s - k * increment, |s| <= limit.
// Returns the slip work (>= 0) if Energy.
template <bool Energy>
inline double capped_spring(Vec3& s, double k, const Vec3& increment, double limit,
                            bool& slipping) {
  const Vec3 before = s;
  s -= k * increment;
  const double s2 = s.squaredNorm();
  slipping = s2 > limit * limit;
  if (!slipping) return 0;
  const Vec3 trial = s;
  s *= limit / std::sqrt(s2);
  if constexpr (!Energy) return 0;
  // Slip displacement (s - trial)/k, worked against the mean spring force of the step.
  return -0.5 * (before + s).dot(s - trial) / k;
}

// The full law. Returns the force on j (on i it is the opposite) and, through roll_moment, the
// rolling-resistance moment on j. `shear` and `roll` are the contact's history.
template <bool Rolling, bool Energy>
inline Vec3 linear_contact(const ContactProperties& p, const ContactKinematics& k, double dt,
                           Vec3& shear, Vec3& roll, Vec3& roll_moment, Dissipation& d) {
  const double vn = k.v_rel.dot(k.n);
  const double fn = normal_force(p, k, vn);

  // Slip limits use the spring (linear) part of the normal force, F_n^l = k_n overlap, as PFC's
  // linear and rolling resistance linear models do; the dashpots are PFC's dp_mode 1: the normal
  // dashpot never makes the total normal force tensile, the shear dashpot acts throughout.
  const double fn_linear = p.kn * k.overlap;
  rotate_into_plane(shear, k.n);
  const Vec3 vt = k.v_rel - vn * k.n;
  bool slipping;
  const double slip_work = capped_spring<Energy>(shear, p.ks, vt * dt, p.mu * fn_linear, slipping);
  Vec3 force = fn * k.n + shear;
  const double cs = shear_dashpot(p, k.m_eff);
  if (cs > 0) force -= cs * vt;
  if constexpr (Energy) {
    d.friction += slip_work;
    d.dashpot += -(fn - fn_linear) * vn * dt + cs * vt.squaredNorm() * dt;
  }

  if constexpr (Rolling) {
    roll_moment.setZero();
    if (p.mu_roll > 0) {
      const double kr = p.ks * k.r_eff * k.r_eff;
      rotate_into_plane(roll, k.n);
      const Vec3 bend = (k.w_rel - k.w_rel.dot(k.n) * k.n) * dt;
      bool rolling_slip;
      d.rolling +=
          capped_spring<Energy>(roll, kr, bend, p.mu_roll * k.r_eff * fn_linear, rolling_slip);
      roll_moment = roll;
    }
  }
  return force;
}

// Elastic energy stored in one contact's springs, J.
inline double contact_strain_energy(const ContactProperties& p, double overlap, const Vec3& shear,
                                    const Vec3& roll, double r_eff) {
  double e = 0.5 * p.kn * overlap * overlap;
  if (p.ks > 0) e += 0.5 * shear.squaredNorm() / p.ks;
  const double kr = p.ks * r_eff * r_eff;
  if (kr > 0) e += 0.5 * roll.squaredNorm() / kr;
  return e;
}

}  // namespace trackbed::dem
