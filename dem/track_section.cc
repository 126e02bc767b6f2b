#include "dem/track_section.h"

#include <cmath>
#include <string>

#include "dem/input_error.h"
#include "dem/material.h"

namespace trackbed::dem {

Vec3 TrackSection::sleeper_lower() const {
  return Vec3(-0.5 * sleeper_length, -0.5 * sleeper_width, depth_under_sleeper);
}

Vec3 TrackSection::sleeper_upper() const {
  return Vec3(0.5 * sleeper_length, 0.5 * sleeper_width, crest_z());
}

bool TrackSection::in_profile(const Vec3& x) const {
  if (x.z() < 0 || x.z() > crest_z() || std::abs(x.y()) > 0.5 * length) return false;
  // The slope line: |x| = half_base - slope * z.
  if (std::abs(x.x()) > half_base_width() - slope * x.z()) return false;
  const Vec3 lo = sleeper_lower(), hi = sleeper_upper();
  const bool in_sleeper = (x.array() >= lo.array()).all() && (x.array() <= hi.array()).all();
  return !in_sleeper;
}

double TrackSection::profile_volume() const {
  const double area = (half_crest_width() + half_base_width()) * crest_z();
  return area * length - sleeper_length * sleeper_width * sleeper_height;
}

void TrackSection::validate(const std::string& where) const {
  const std::string w = where.empty() ? "section: " : where + ": section: ";
  check_range(w + "sleeper length", sleeper_length, 1e-3, 100);
  check_range(w + "sleeper width", sleeper_width, 1e-3, 100);
  check_range(w + "sleeper height", sleeper_height, 1e-3, 100);
  check_range(w + "sleeper mass", sleeper_mass, 1e-6, 1e6);
  check_range(w + "depth under sleeper", depth_under_sleeper, 1e-3, 100);
  check_range(w + "shoulder width", shoulder_width, 0, 100);
  check_range(w + "slope", slope, 0, 100);
  check_range(w + "length", length, 1e-3, 1000);
  if (sleeper_width > length)
    throw InputError(w + "sleeper width " + std::to_string(sleeper_width) +
                     " m exceeds the section length " + std::to_string(length) +
                     " m; valid: a sleeper narrower than the sleeper spacing");
}

}  // namespace trackbed::dem
