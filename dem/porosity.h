// Porosity of a packing in a box, measured on the sphere elements: the box is sampled on a
// regular grid of points (cell centres) and every element marks the points inside it, so
// overlapping pebbles of a clump count once. The error is that of the midpoint rule for the
// indicator function: about (spacing / diameter)^2 relative, far below 1 % for a spacing of a
// tenth of the smallest diameter (docs/samples.md, "Porosity").
#pragma once

#include <functional>

#include "dem/particles.h"

namespace trackbed::dem {

struct PorosityMeasure {
  double porosity;  // 1 - solid fraction
  double box_volume;
  long points;
};

// Throws InputError for an empty box or a spacing that is not positive, or one giving more than
// 2^31 points.
PorosityMeasure porosity_in_box(const Particles& p, const Vec3& lower, const Vec3& upper,
                                double spacing);
// The same over the grid points of the box for which `inside` holds (e.g. a section's profile);
// box_volume is then the volume of those points.
PorosityMeasure porosity_in_region(const Particles& p, const Vec3& lower, const Vec3& upper,
                                   double spacing, const std::function<bool(const Vec3&)>& inside);

}  // namespace trackbed::dem
