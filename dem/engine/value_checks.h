// Checks of values read back from files (samples, checkpoints): every number finite, positive
// where it must be, orientations and normals of unit length. The readers refuse a file that fails
// one, so that a damaged value never reaches the engine.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "dem/engine/types.h"

namespace trackbed::dem {

// The engine normalises quaternions and wall normals as it writes them, to round-off (about
// 1e-16); a stored norm further than this from 1 was not written by it.
inline constexpr double kUnitNormTolerance = 1e-6;

inline bool all_finite(const std::vector<double>& v) {
  return std::all_of(v.begin(), v.end(), [](double a) { return std::isfinite(a); });
}

inline bool all_finite(const std::vector<Vec3>& v) {
  return std::all_of(v.begin(), v.end(), [](const Vec3& a) { return a.allFinite(); });
}

inline bool positive_finite(double a) {
  return std::isfinite(a) && a > 0;
}

inline bool unit_norm(const Quat& q) {
  return std::abs(q.norm() - 1) < kUnitNormTolerance;
}

inline bool unit_norm(const Vec3& n) {
  return std::abs(n.norm() - 1) < kUnitNormTolerance;
}

}  // namespace trackbed::dem
