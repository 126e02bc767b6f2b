// Descriptions of the meshes the continuum tier builds in code. Coordinates: x across the track
// (0 on the centre line), y along the track, z up. Lengths in metres.
#pragma once

#include <array>
#include <vector>

namespace trackbed::fem {

using Vector3 = std::array<double, 3>;

// An axis-aligned block, split into horizontal material layers. Boundary ids (and names):
// 0 "xmin", 1 "xmax", 2 "ymin", 3 "ymax", 4 "zmin", 5 "zmax".
struct BoxGeometry {
  struct Layer {
    double z_min, z_max;       // m
    unsigned int material_id;  // cells whose centre lies in [z_min, z_max)
  };
  Vector3 lower{{0.0, 0.0, 0.0}};
  Vector3 upper{{1.0, 1.0, 1.0}};
  std::array<unsigned int, 3> subdivisions{{1, 1, 1}};  // coarse cells per direction
  std::vector<Layer> layers;                            // empty: every cell has material id 0
};

// The continuum under a DEM ballast bed, from the same section parameters as the DEM sample.
// z = 0 is the surface on which the discrete ballast rests. Below it, from the top: an optional
// equivalent-continuum lower ballast layer whose sides continue the ballast shoulder slope, the
// sub-ballast and the embankment fill (a trapezoid with the embankment slope), then a natural
// ground block. The section is extruded along y over section_length.
struct TrackSection {
  // Ballast footprint (shared with the DEM sample).
  double sleeper_length = 2.6;  // m
  double sleeper_height = 0.2;  // m, crib ballast reaches the sleeper top
  double shoulder_width = 0.4;  // m, flat shoulder beyond the sleeper end
  double ballast_depth = 0.3;   // m, discrete ballast under the sleeper soffit
  double shoulder_slope = 1.5;  // horizontal per vertical of the ballast slope
  double section_length = 0.6;  // m along the track (one sleeper spacing)
  // Continuum layers.
  double lower_ballast_thickness = 0.0;  // m, 0: no equivalent-continuum ballast layer
  double sub_ballast_thickness = 0.2;    // m
  double embankment_height = 1.0;        // m of subgrade fill above the natural ground
  double embankment_slope = 1.5;         // horizontal per vertical
  double ground_depth = 3.0;             // m of natural ground below the embankment
  double ground_half_width = 6.0;        // m from the centre line to the lateral boundary
  double element_size = 0.25;            // m, coarse cell size (outside the embankment: twice it)

  // Half-width of the formation (z = 0): half the sleeper plus the shoulder plus the ballast
  // slope over the crib and the depth under the sleeper.
  double formation_half_width() const {
    return 0.5 * sleeper_length + shoulder_width +
           (sleeper_height + ballast_depth) * shoulder_slope;
  }
};

// Material ids and boundary ids of the track section.
namespace track_section {
constexpr unsigned int lower_ballast_id = 1, sub_ballast_id = 2, subgrade_id = 3, ground_id = 4;
// Boundary names: "formation" (0, touches the discrete ballast), "free_surface" (1, slopes and
// ground surface), "ends" (2, y = 0 and y = section_length), "sides" (3), "bottom" (4).
}  // namespace track_section

// A monoblock sleeper as a prismatic beam along x, centred on x = 0, y = soffit_centre[1], with its
// soffit (underside) at z = soffit_centre[2]. Boundary names: "free" (0), "soffit" (1),
// "rail_seat_left" (2, x < 0), "rail_seat_right" (3): the rail seats are the top faces under the
// rail feet. Every cell has material id 0.
struct SleeperGeometry {
  double length = 2.6;             // m (B70: 2.6 m)
  double width = 0.26;             // m, mean width of a B70 (0.30 at the soffit, 0.22 at the top)
  double height = 0.2;             // m, mean height
  double rail_seat_spacing = 1.5;  // m between rail seat centres (1435 mm gauge)
  double rail_seat_width = 0.15;   // m along the sleeper: the rail foot
  double element_size = 0.05;      // m
  Vector3 soffit_centre{{0.0, 0.0, 0.0}};
};

}  // namespace trackbed::fem
