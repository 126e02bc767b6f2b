// Free rotation of a rigid body over one step by the symmetric splitting of Dullweber, Leimkuhler
// and McLachlan (J. Chem. Phys. 107, 5840, 1997): the free-body Hamiltonian is split into
// rotations about the three principal axes, composed as 1(h/2) 2(h/2) 3(h) 2(h/2) 1(h/2). Each
// sub-rotation is exact, so |L| is conserved to round-off and the energy error stays bounded
// (second order, symplectic, time-reversible). See docs/theory.md, "Rotation of clumps".
//
// Written out for a rotation about a coordinate axis, which touches two components of the
// momentum and is one sparse quaternion product: a clump's step spent more on five general
// quaternion rotations and five sincos calls than on all its contacts.
#pragma once

#include <cmath>

#include "dem/engine/types.h"

namespace trackbed::dem {

// sin x and cos x. For |x| <= 0.03 by their Taylor polynomials to x^7 and x^8, whose remainders
// (x^9/9!, x^10/10!) are below 2e-18 of the value, under the last bit of a double; libm beyond.
// A body turns by 1e-6 to 1e-3 rad in a step.
inline void sin_cos(double x, double& s, double& c) {
  const double x2 = x * x;
  if (x2 > 9e-4) {
    s = std::sin(x);
    c = std::cos(x);
    return;
  }
  s = x * (1 - x2 * (1.0 / 6) * (1 - x2 * (1.0 / 20) * (1 - x2 * (1.0 / 42))));
  c = 1 - x2 * 0.5 * (1 - x2 * (1.0 / 12) * (1 - x2 * (1.0 / 30) * (1 - x2 * (1.0 / 56))));
}

// Turns the body (q: principal frame -> world) about its principal axis k by angle h pi_k / I_k:
// q <- q rot(e_k, a), and its body-frame momentum pi by -a (pi <- rot(e_k, a)^T pi).
// inv_I: the inverse principal moments 1 / I_k (multiplied, not divided: the five turns are one
// chain of dependent operations, and a division in it costs as much as the rest of a turn).
inline void rotate_about_principal_axis(int k, double h, Quat& q, Vec3& pi, const Vec3& inv_I) {
  const int i = (k + 1) % 3, j = (k + 2) % 3;  // (i, j, k) cyclic
  double s, c;                                 // of the half angle: rot(e_k, a) = (c, s e_k)
  sin_cos(0.5 * h * pi[k] * inv_I[k], s, c);
  const double ca = c * c - s * s, sa = 2 * s * c;  // of the angle
  const double pi_i = pi[i], pi_j = pi[j];
  pi[i] = ca * pi_i + sa * pi_j;
  pi[j] = ca * pi_j - sa * pi_i;
  // q (c, s e_k): w = c q_w - s q_k, v = c q_v + s q_w e_k + s q_v x e_k, (q_v x e_k) = (q_j, -q_i,
  // 0) in (i, j, k).
  Eigen::Vector4d& v = q.coeffs();  // x, y, z, w
  const double qi = v[i], qj = v[j], qk = v[k], qw = v[3];
  v[i] = c * qi + s * qj;
  v[j] = c * qj - s * qi;
  v[k] = c * qk + s * qw;
  v[3] = c * qw - s * qk;
}

// Rotates the body (orientation q: principal frame -> world) freely for time h with world
// angular momentum L, which a free rotation leaves unchanged. inv_I: the inverse principal
// moments. Returns the angular momentum in the body frame at the end, R^T L.
inline Vec3 free_rotation(Quat& q, const Vec3& L, const Vec3& inv_I, double h) {
  Vec3 pi = q.conjugate() * L;
  rotate_about_principal_axis(0, 0.5 * h, q, pi, inv_I);
  rotate_about_principal_axis(1, 0.5 * h, q, pi, inv_I);
  rotate_about_principal_axis(2, h, q, pi, inv_I);
  rotate_about_principal_axis(1, 0.5 * h, q, pi, inv_I);
  rotate_about_principal_axis(0, 0.5 * h, q, pi, inv_I);
  q.normalize();
  return pi;
}

}  // namespace trackbed::dem
