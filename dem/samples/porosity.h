// Porosity of a packing in a box, measured on the sphere elements: the box is sampled on a
// regular grid of points (cell centres) and every element marks the points inside it, so
// overlapping pebbles of a clump count once. For one sphere with 20 points per diameter the count
// misses its volume by up to about 1 %; over a packing the spheres sit at random offsets to the
// grid and the errors average out, to well below 0.3 % of the solid volume for a few hundred
// stones at a spacing of a tenth of the smallest (tests/dem/test_porosity.cc; docs/samples.md,
// "Porosity").
#pragma once

#include <functional>

#include "dem/engine/particles.h"

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
