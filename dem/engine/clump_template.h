// Clump templates: the shape of a clump, stored once and shared by every clump of that shape.
// A template lives in its principal frame (centroid at the origin, principal axes along x, y, z),
// so a clump's orientation quaternion maps the template directly to the world and its inertia
// tensor in the body frame is diagonal.
#pragma once

#include <string>
#include <vector>

#include "dem/engine/mass_properties.h"
#include "dem/engine/types.h"

namespace trackbed::dem {

struct ClumpTemplate {
  std::string name;
  // In the principal frame.
  std::vector<SphereShape> spheres;
  // Of the union of the spheres.
  double volume;
  // Per unit density, ascending, about x, y and z of the principal frame.
  Vec3 principal_moments;
  // max |centre| + radius: the smallest sphere about the centroid that encloses the clump.
  double bounding_radius;
  // Where the principal frame sits in the frame the spheres were given in (the template file's
  // frame): input = input_centroid + input_axes * principal. Particle files place clumps by
  // that frame.
  Vec3 input_centroid = Vec3::Zero();
  Mat3 input_axes = Mat3::Identity();

  // Radius of the sphere of the same volume, (3 V / (4 pi))^(1/3).
  double equivalent_radius() const;
};

// Computes the mass properties of the union of `spheres_in_any_frame` (to `relative_tolerance`,
// see sphere_union_mass_properties) and moves the spheres to the principal frame. Throws
// InputError naming the template for invalid spheres or tolerance.
ClumpTemplate make_clump_template(std::string name,
                                  const std::vector<SphereShape>& spheres_in_any_frame,
                                  double relative_tolerance = 1e-4);

// A template of `spheres_in_any_frame` whose mass properties are `mass` (same frame) instead of
// those of the union of the spheres: e.g. the closed surface the spheres were packed into, as PFC's
// bubble pack does. The spheres are moved to the principal frame of `mass`, and volume and moments
// are those of `mass`. Throws InputError naming the template for no spheres, a radius that is not
// finite and > 0, a non-finite centre, or a volume or principal moment that is not finite and > 0.
ClumpTemplate make_clump_template_with_mass(std::string name,
                                            const std::vector<SphereShape>& spheres_in_any_frame,
                                            const MassProperties& mass);

// The same shape scaled geometrically by `factor` about the origin of its input frame: lengths * f,
// volume * f^3, moments * f^5. Throws InputError unless `factor` is finite and > 0.
ClumpTemplate scaled(const ClumpTemplate& clump, double factor);

}  // namespace trackbed::dem
