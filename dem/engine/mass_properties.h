// Mass properties of rigid bodies per unit density. A clump is the UNION of its spheres: where
// pebbles overlap, the material is counted once, so mass, centre and inertia are integrals over
// the union, not sums over spheres.
#pragma once

#include <vector>

#include "dem/engine/types.h"

namespace trackbed::dem {

struct SphereShape {
  Vec3 centre;
  double radius;
};

// Everything is per unit density: multiply volume and inertia by the density to get mass and
// moments of inertia.
struct MassProperties {
  double volume;
  Vec3 centroid;
  // About the centroid, axes of the input frame: integral of (r.r I - r r^T) dV.
  Mat3 inertia;
  // Eigenvalues of `inertia`, ascending.
  Vec3 principal_moments;
  // Columns are the unit principal axes in the order of `principal_moments`; det = +1, so the
  // matrix is a rotation from the principal frame to the input frame.
  Mat3 principal_axes;
};

// Fills principal_moments (ascending) and principal_axes (right-handed; each of the first two
// axes with its largest component positive, so the result does not depend on the eigen
// solver's arbitrary signs) from mp.inertia. Every mass source uses it, so that the same shape
// gets the same frame.
void set_principal_frame(MassProperties& mp);

// Volume, centroid and inertia of the union of `spheres`, converged to `relative_tolerance` in
// volume and in the trace of the inertia (docs/clumps.md). One sphere, and spheres that do not
// overlap once those inside another sphere are dropped, are integrated exactly. Throws InputError
// for an empty list, a radius that is not finite and positive, a non-finite centre, or a
// tolerance outside [1e-6, 0.1].
MassProperties sphere_union_mass_properties(const std::vector<SphereShape>& spheres,
                                            double relative_tolerance = 1e-4);

}  // namespace trackbed::dem
