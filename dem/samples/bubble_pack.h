// Clump templates from closed surfaces: overlapping spheres ("pebbles") that fill a stone's
// surface, in the manner of PFC's bubble pack (Taghavi 2011), with its two knobs, Distance and
// Ratio (docs/templates.md).
#pragma once

#include <string>
#include <vector>

#include "dem/engine/clump_template.h"
#include "dem/engine/mass_properties.h"
#include "dem/engine/triangle_mesh.h"
#include "dem/engine/types.h"

namespace trackbed::dem {

// Where a template's volume, centroid and inertia come from: the closed surface (as PFC does) or
// the union of its pebbles (what the clump really is as a DEM body).
enum class MassSource { surface, pebbles };

struct BubblePackSettings {
  // Distance phi in degrees, (0, 180]: the groove angle, measured through the outside, at which
  // the surfaces of two neighbouring pebbles may meet at the closest; 180 is a smooth surface.
  // Higher means more pebbles and a tighter fit.
  double distance = 120.0;
  // Ratio R in (0, 1]: the smallest over the largest pebble radius.
  double ratio = 0.5;
  // Cells of the interior sampling grid along the longest edge of the bounding box, [8, 256].
  int resolution = 64;
  MassSource mass_source = MassSource::surface;
};

struct BubblePackResult {
  // The pebbles in the principal frame of the chosen mass properties.
  ClumpTemplate clump;
  // The same pebbles in the surface's own frame (for writing a template file).
  std::vector<SphereShape> pebbles;
  double min_radius = 0.0, max_radius = 0.0;
  MassProperties surface_mass, pebble_mass;
  // (V_pebbles - V_surface) / V_surface: negative, pebbles lie inside the surface.
  double volume_error = 0.0;
  // |I_pebbles - I_surface|_F / |I_surface|_F, each about its own centroid, in the surface's frame.
  double inertia_error = 0.0;

  int pebble_count() const { return static_cast<int>(pebbles.size()); }
};

// Packs the closed surface (it must pass check_closed_surface, which this runs; `name` names the
// template and starts every error message). Deterministic: no randomness. Throws InputError for
// a distance, ratio or resolution out of range, or a surface too thin for the grid.
BubblePackResult bubble_pack(const TriangleMesh& surface, const BubblePackSettings& settings,
                             const std::string& name);

}  // namespace trackbed::dem
