// Ballast-like stones, random angular convex polyhedra, and the shape indices of any closed
// surface (docs/templates.md: definitions, sources, and the ranges of railway ballast).
#pragma once

#include <cstdint>

#include "dem/engine/clump_template.h"
#include "dem/engine/triangle_mesh.h"

namespace trackbed::dem {

struct ShapeIndices {
  // Extents along the principal axes of inertia, sorted: longest >= intermediate >= shortest
  // (L >= I >= S), metres.
  double longest = 0.0, intermediate = 0.0, shortest = 0.0;
  double elongation = 0.0;  // I / L
  double flatness = 0.0;    // S / I
  // Wadell's true sphericity, (36 pi V^2)^(1/3) / A: 1 for a sphere, 0.806 for a cube.
  double sphericity = 0.0;
  // Length-weighted mean exterior dihedral angle of the creased edges (those whose faces meet
  // at more than kFlatEdgeAngleDegrees), degrees: 90 for a box, 0 for a smooth surface.
  double angularity = 0.0;
  // Plane faces: the triangles joined across edges flatter than kFlatEdgeAngleDegrees.
  int faces = 0;
  // The smallest square aperture the L x I x S box passes going through along L,
  // min(I, (I + S) / sqrt 2) (I unless S < 0.414 I), metres.
  double sieve_size = 0.0;
};

// Edges whose faces meet at less than this exterior angle are treated as lying inside one plane
// face: far above the rounding of coplanar triangles (below 0.001 degree for a cut face), and a
// crease too slight to see.
constexpr double kFlatEdgeAngleDegrees = 1.0;

// Shape indices of a closed, outward-oriented surface. Throws InputError for an open or inward
// surface (closed_mesh_mass_properties).
ShapeIndices shape_indices(const TriangleMesh& closed_surface);

// The sieve size of an L x I x S box passing along L: min(I, (I + S) / sqrt 2) (the rule of
// ShapeIndices::sieve_size; any order of the three extents).
double box_sieve_size(double a, double b, double c);
// The sieve size of a clump's pebbles: box_sieve_size of their extents along the template's
// principal axes.
double clump_sieve_size(const ClumpTemplate& clump);

struct BallastStoneSettings {
  // The sieve size of each stone is drawn uniformly from [min, max] (metres): by default the
  // 22.4 to 63 mm of an EN 13450 31.5/63 grading.
  double min_sieve_size = 0.0224;
  double max_sieve_size = 0.063;
};

// One random stone, the same for the same seed (std::mt19937_64, whose output the standard fixes,
// and none of the implementation-defined std distributions): the convex hull of 10 to 16 points
// scattered about an ellipsoid with random semi-axes, with up to three caps cut off as crushed
// faces, in the principal frame of its volume (centroid at the origin, x the axis of the smallest
// moment), and scaled to a sieve size drawn from the settings. Throws InputError for settings out
// of range (sizes not finite, min <= 0 or min > max).
TriangleMesh make_ballast_stone(std::uint64_t seed, const BallastStoneSettings& settings = {});

}  // namespace trackbed::dem
