// Descriptions of the meshes the continuum tier builds in code. Coordinates: x across the track
// (0 on the centre line), y along the track, z up. Lengths in metres.
#pragma once

#include <array>
#include <vector>

#include "common/track_section.h"

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

// The continuum under the ballast bed is built from trackbed's one TrackSection
// (common/track_section.h), the geometry the DEM sample is built from, so the formation (z = 0)
// is the ballast base. Its material ids and boundary ids:
namespace track_section {
constexpr unsigned int lower_ballast_id = 1, sub_ballast_id = 2, subgrade_id = 3, ground_id = 4;
// Boundary names: "formation" (0, touches the discrete ballast), "free_surface" (1, slopes and
// ground surface), "ends" (2, y = -length/2 and y = length/2), "sides" (3), "bottom" (4).
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
