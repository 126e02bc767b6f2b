// An infinite plane wall: a solid half-space { x : (x - point) . normal < 0 } that may translate
// at a prescribed velocity. Particles touch it from the side the normal points to.
#pragma once

#include <string>

#include "dem/engine/types.h"

namespace trackbed::dem {

struct PlaneWall {
  std::string name;
  Vec3 point = Vec3::Zero();
  Vec3 normal = Vec3::UnitZ();  // unit, pointing out of the wall into the particles
  Vec3 velocity = Vec3::Zero();
  int material = 0;

  // Result of the last step: the force and moment (about `point`) the particles exert on it.
  Vec3 force = Vec3::Zero();
  Vec3 moment = Vec3::Zero();

  double distance(const Vec3& x) const { return (x - point).dot(normal); }
};

}  // namespace trackbed::dem
