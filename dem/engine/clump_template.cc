#include "dem/engine/clump_template.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <utility>

#include "common/input_error.h"

namespace trackbed::dem {
namespace {

constexpr double kPi = 3.14159265358979323846;

}  // namespace

double ClumpTemplate::equivalent_radius() const {
  return std::cbrt(3.0 * volume / (4.0 * kPi));
}

ClumpTemplate make_clump_template(std::string name,
                                  const std::vector<SphereShape>& spheres_in_any_frame,
                                  double relative_tolerance) {
  MassProperties mp;
  try {
    mp = sphere_union_mass_properties(spheres_in_any_frame, relative_tolerance);
  } catch (const InputError& e) {
    throw InputError("clump template '" + name + "': " + e.what());
  }
  return make_clump_template_with_mass(std::move(name), spheres_in_any_frame, mp);
}

ClumpTemplate make_clump_template_with_mass(std::string name,
                                            const std::vector<SphereShape>& spheres_in_any_frame,
                                            const MassProperties& mass) {
  const std::string what = "clump template '" + name + "'";
  if (spheres_in_any_frame.empty()) throw InputError(what + " has no spheres; give at least one");
  for (std::size_t i = 0; i < spheres_in_any_frame.size(); ++i) {
    const SphereShape& sp = spheres_in_any_frame[i];
    if (!(std::isfinite(sp.radius) && sp.radius > 0.0) || !sp.centre.allFinite()) {
      std::ostringstream msg;
      msg << what << ": sphere " << i << " (radius " << sp.radius
          << ") is not valid; a sphere needs a finite centre and a finite radius > 0";
      throw InputError(msg.str());
    }
  }
  if (!(std::isfinite(mass.volume) && mass.volume > 0.0) || !mass.principal_moments.allFinite() ||
      !(mass.principal_moments.minCoeff() > 0.0)) {
    std::ostringstream msg;
    msg << what << ": volume " << mass.volume << " and principal moments ("
        << mass.principal_moments.transpose()
        << ") are not valid mass properties; they must be finite and > 0";
    throw InputError(msg.str());
  }
  ClumpTemplate t;
  t.name = std::move(name);
  t.volume = mass.volume;
  t.principal_moments = mass.principal_moments;
  t.input_centroid = mass.centroid;
  t.input_axes = mass.principal_axes;
  t.bounding_radius = 0.0;
  // principal_axes maps principal to input coordinates; its transpose maps back.
  const Mat3 to_principal = mass.principal_axes.transpose();
  t.spheres.reserve(spheres_in_any_frame.size());
  for (const SphereShape& sp : spheres_in_any_frame) {
    const SphereShape moved{to_principal * (sp.centre - mass.centroid), sp.radius};
    t.bounding_radius = std::max(t.bounding_radius, moved.centre.norm() + moved.radius);
    t.spheres.push_back(moved);
  }
  return t;
}

ClumpTemplate scaled(const ClumpTemplate& clump, double factor) {
  if (!(std::isfinite(factor) && factor > 0.0)) {
    std::ostringstream msg;
    msg << "clump template '" << clump.name << "': scale factor " << factor
        << " is not valid; it must be finite and > 0";
    throw InputError(msg.str());
  }
  ClumpTemplate t = clump;
  for (SphereShape& sp : t.spheres) {
    sp.centre *= factor;
    sp.radius *= factor;
  }
  t.volume *= factor * factor * factor;
  // Inertia per unit density is a volume times a squared length.
  t.principal_moments *= std::pow(factor, 5);
  t.bounding_radius *= factor;
  t.input_centroid *= factor;  // scaling is about the origin of the template's own frame
  return t;
}

}  // namespace trackbed::dem
