// The convex hull of a point set as a closed, outward-oriented triangle mesh (docs/templates.md).
// Used to make angular ballast stones from random points.
#pragma once

#include <vector>

#include "dem/engine/triangle_mesh.h"
#include "dem/engine/types.h"

namespace trackbed::dem {

// The finalized, closed, outward-oriented hull of `points`. The hull is built by incremental
// insertion with exact integer orientation tests on the points rounded to a grid of 2^-17 of the
// bounding box's largest extent, so coplanar, collinear and repeated points cannot break its
// topology; vertices are those rounded points. Points within kConvexHullTolerance times the
// bounding-box diagonal of the hull are treated as on it (merged, or left out), which also keeps
// every triangle's smallest height above that tolerance. Throws InputError when the points do not
// span a volume (fewer than 4 points off one plane, at that tolerance) or are not finite.
TriangleMesh convex_hull(const std::vector<Vec3>& points);

// 1e-5 of the size: 0.4 um on a 40 mm stone, 10 times the vertex-merging tolerance of
// TriangleMesh::finalize() so that no hull triangle is ever refused as degenerate.
constexpr double kConvexHullTolerance = 1e-5;

}  // namespace trackbed::dem
