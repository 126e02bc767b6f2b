// The single-sleeper track section, the one geometry the discrete ballast (dem/) and the
// continuum below it (fem/) are built from, so the two meet: the ballast cross-section under and
// around one sleeper, one sleeper spacing long (after Jia, Markine and Guo 2023), and the
// continuum layers under its base.
//
// Frame: x across the track, along the sleeper (the lateral push direction); y along the track,
// the section over |y| <= length/2; z up, the ballast base (the formation) at z = 0. The sleeper is
// centred on x = y = 0 with its bottom at z = depth_under_sleeper. The ballast fills, for |y| <=
// length/2, the trapezoid whose crest (at the top of the sleeper, crest_z) reaches shoulder_width
// beyond each sleeper end and whose slopes fall 1 : slope (vertical : horizontal) to the base; the
// crib between sleepers is filled to the crest; the sleeper's own solid is not ballast.
//
// The ballast box test (cases/ballast_box/) is the same bed in a box: side walls at
// x = +-half_crest_width instead of slopes (slope 0), and a wedge-shaped sleeper section, its
// cross-section (y, z) a trapezoid sleeper_bottom_width wide at the bottom and sleeper_width at the
// top.
//
// Below the formation (z < 0) the continuum tier continues the section: from the top, an optional
// equivalent-continuum lower ballast layer whose sides continue the ballast slope, the
// sub-ballast and the embankment fill (a trapezoid with the embankment slope), then a natural
// ground block ground_half_width wide on each side (fem::ElasticBody::make_track_section).
#pragma once

#include <Eigen/Core>
#include <string>

namespace trackbed {

struct TrackSection {
  using Vec3 = Eigen::Vector3d;

  // The ballast bed and its sleeper (the discrete tiers).
  double sleeper_length = 2.6;        // m, along x
  double sleeper_width = 0.28;        // m, along y
  double sleeper_height = 0.185;      // m
  double sleeper_mass = 380;          // kg
  double depth_under_sleeper = 0.35;  // m, ballast between base and sleeper bottom
  double shoulder_width = 0.5;        // m, crest beyond each sleeper end
  double slope = 1.75;                // horizontal per vertical
  double length = 0.6;      // m, along y (one sleeper spacing; walls or periodic at +-length/2)
  bool periodic = false;    // along y: periodic boundary instead of crib walls
  bool side_walls = false;  // a box: vertical walls at x = +-half_crest_width (needs slope 0)
  double sleeper_bottom_width = 0;  // m, along y at the bottom; 0: sleeper_width (a box)

  // The continuum below the formation (the FE tier).
  double lower_ballast_thickness = 0;  // m, equivalent-continuum ballast; 0: none
  double sub_ballast_thickness = 0.2;  // m
  double embankment_height = 1.0;      // m of subgrade fill above the natural ground
  double embankment_slope = 1.5;       // horizontal per vertical
  double ground_depth = 3.0;           // m of natural ground below the embankment
  double ground_half_width = 6.0;      // m from the centre line to the lateral boundary

  double crest_z() const { return depth_under_sleeper + sleeper_height; }
  double half_crest_width() const { return 0.5 * sleeper_length + shoulder_width; }
  // Half-width of the ballast base, the formation on which the continuum tier meets it.
  double half_base_width() const { return half_crest_width() + slope * crest_z(); }
  double bottom_width() const {
    return sleeper_bottom_width > 0 ? sleeper_bottom_width : sleeper_width;
  }
  // The sleeper's bounding box at its design position.
  Vec3 sleeper_lower() const;
  Vec3 sleeper_upper() const;
  // Distance from x to the sleeper's solid at its design position raised by `lift` (0 inside).
  double distance_to_sleeper(const Vec3& x, double lift = 0) const;
  Vec3 sleeper_centre() const { return 0.5 * (sleeper_lower() + sleeper_upper()); }

  // Inside the ballast's design profile (the trapezoid prism without the sleeper).
  bool in_profile(const Vec3& x) const;
  // Volume of the design profile, m^3: trapezoid area times length minus the sleeper.
  double profile_volume() const;
  // Throws InputError naming the parameter for a non-physical section.
  void validate(const std::string& where) const;
};

}  // namespace trackbed
