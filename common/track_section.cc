#include "common/track_section.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "common/input_error.h"

namespace trackbed {

TrackSection::Vec3 TrackSection::sleeper_lower() const {
  return Vec3(-0.5 * sleeper_length, -0.5 * std::max(sleeper_width, bottom_width()),
              depth_under_sleeper);
}

TrackSection::Vec3 TrackSection::sleeper_upper() const {
  return Vec3(0.5 * sleeper_length, 0.5 * std::max(sleeper_width, bottom_width()), crest_z());
}

double TrackSection::distance_to_sleeper(const Vec3& x, double lift) const {
  // The solid is the product of the interval |x| <= L/2 and the trapezoid T in (y, z), so the
  // distance is sqrt(dx^2 + d_T^2) with d_T the plane distance to T: 0 inside, otherwise the
  // least distance to its four edges.
  const double dx = std::max(std::abs(x.x()) - 0.5 * sleeper_length, 0.0);
  const double z0 = depth_under_sleeper + lift, z1 = z0 + sleeper_height;
  const double b = 0.5 * bottom_width(), t = 0.5 * sleeper_width;
  const double y = std::abs(x.y()), z = x.z();  // T is symmetric in y
  // The slanted edge from (b, z0) to (t, z1); inside T: z0 <= z <= z1 and left of that edge.
  const double ey = t - b, ez = sleeper_height;
  const bool left_of_edge = (y - b) * ez - (z - z0) * ey <= 0;
  double d_t = 0;
  if (z < z0 || z > z1 || !left_of_edge) {
    auto to_segment = [&](double ay, double az, double by, double bz) {
      const double sy = by - ay, sz = bz - az;
      const double u = std::clamp(((y - ay) * sy + (z - az) * sz) / (sy * sy + sz * sz), 0.0, 1.0);
      return std::hypot(y - ay - u * sy, z - az - u * sz);
    };
    d_t = std::min({to_segment(0, z0, b, z0), to_segment(b, z0, t, z1), to_segment(0, z1, t, z1)});
  }
  return std::hypot(dx, d_t);
}

bool TrackSection::in_profile(const Vec3& x) const {
  if (x.z() < 0 || x.z() > crest_z() || std::abs(x.y()) > 0.5 * length) return false;
  // The slope line: |x| = half_base - slope * z.
  if (std::abs(x.x()) > half_base_width() - slope * x.z()) return false;
  return distance_to_sleeper(x) > 0;
}

double TrackSection::profile_volume() const {
  const double area = (half_crest_width() + half_base_width()) * crest_z();
  const double sleeper = sleeper_length * 0.5 * (sleeper_width + bottom_width()) * sleeper_height;
  return area * length - sleeper;
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
  check_range(w + "sleeper bottom width", sleeper_bottom_width, 0, 100);
  check_range(w + "lower ballast thickness", lower_ballast_thickness, 0, 100);
  check_range(w + "sub-ballast thickness", sub_ballast_thickness, 1e-3, 100);
  check_range(w + "embankment height", embankment_height, 1e-3, 100);
  check_range(w + "embankment slope", embankment_slope, 0, 100);
  check_range(w + "ground depth", ground_depth, 1e-3, 1000);
  check_range(w + "ground half width", ground_half_width, 1e-3, 1e4);
  if (std::max(sleeper_width, bottom_width()) > length)
    throw InputError(w + "sleeper width " +
                     std::to_string(std::max(sleeper_width, bottom_width())) +
                     " m exceeds the section length " + std::to_string(length) +
                     " m; valid: a sleeper narrower than the sleeper spacing");
  if (side_walls && slope != 0)
    throw InputError(w + "sides = walls with slope " + std::to_string(slope) +
                     "; valid: slope 0 (a box's side walls stand at the crest's edges)");
}

}  // namespace trackbed
