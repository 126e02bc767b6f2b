// Free rotation of a rigid body over one step by the symmetric splitting of Dullweber, Leimkuhler
// and McLachlan (J. Chem. Phys. 107, 5840, 1997): the free-body Hamiltonian is split into
// rotations about the three principal axes, composed as 1(h/2) 2(h/2) 3(h) 2(h/2) 1(h/2). Each
// sub-rotation is exact, so |L| is conserved to round-off and the energy error stays bounded
// (second order, symplectic, time-reversible). See docs/theory.md, "Rotation of clumps".
#pragma once

#include <cmath>

#include "dem/types.h"

namespace trackbed::dem {

// Rotates the body (orientation q: principal frame -> world) freely for time h with world
// angular momentum L, which a free rotation leaves unchanged. I: principal moments.
inline void free_rotation(Quat& q, const Vec3& L, const Vec3& I, double h) {
  Vec3 pi = q.conjugate() * L;  // angular momentum in the body frame
  auto about = [&](int k, double dt) {
    const double angle = dt * pi[k] / I[k];
    const Quat r(Eigen::AngleAxisd(angle, Vec3::Unit(k)));
    pi = r.conjugate() * pi;  // the body turns by +angle, so body-frame vectors turn by -angle
    q = q * r;
  };
  about(0, 0.5 * h);
  about(1, 0.5 * h);
  about(2, h);
  about(1, 0.5 * h);
  about(0, 0.5 * h);
  q.normalize();
}

// World angular velocity from world angular momentum: w = R I^-1 R^T L.
inline Vec3 angular_velocity(const Quat& q, const Vec3& L, const Vec3& I) {
  return q * (q.conjugate() * L).cwiseQuotient(I);
}

}  // namespace trackbed::dem
