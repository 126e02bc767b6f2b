// A flat triangulated square grid, shared by the mesh geometry and mesh contact tests.
#pragma once

#include "dem/engine/triangle_mesh.h"

namespace trackbed::dem::testing {

// A square grid of n x n unit cells in the plane z = 0, each cell split into two triangles along
// one diagonal: the same diagonal everywhere (interior vertices shared by 6 triangles), or
// alternating (4 and 8).
inline TriangleMesh flat_grid(int n, bool alternating) {
  TriangleMesh mesh;
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) mesh.vertices.emplace_back(i, j, 0.0);
  }
  const auto id = [n](int i, int j) { return j * (n + 1) + i; };
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const int a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
      if (alternating && (i + j) % 2 == 1) {
        mesh.triangles.push_back({a, b, d});
        mesh.triangles.push_back({b, c, d});
      } else {
        mesh.triangles.push_back({a, b, c});
        mesh.triangles.push_back({a, c, d});
      }
    }
  }
  mesh.finalize();
  return mesh;
}

}  // namespace trackbed::dem::testing
