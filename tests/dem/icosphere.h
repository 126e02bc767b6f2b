// A sphere mesh for the template tests: an icosahedron whose triangles are split into four,
// `levels` times, with every vertex pushed out to the sphere (20 * 4^levels triangles).
#pragma once

#include <map>
#include <utility>

#include "dem/engine/triangle_mesh.h"

namespace trackbed::dem::testing {

inline TriangleMesh icosphere(double radius, int levels, const Vec3& centre = Vec3::Zero()) {
  const double g = (1.0 + std::sqrt(5.0)) / 2.0;  // the golden ratio
  std::vector<Vec3> v = {{-1, g, 0},  {1, g, 0},  {-1, -g, 0}, {1, -g, 0}, {0, -1, g},  {0, 1, g},
                         {0, -1, -g}, {0, 1, -g}, {g, 0, -1},  {g, 0, 1},  {-g, 0, -1}, {-g, 0, 1}};
  std::vector<std::array<int, 3>> t = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                       {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                       {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                       {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int level = 0; level < levels; ++level) {
    std::map<std::pair<int, int>, int> midpoint;
    const auto mid = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      const auto it = midpoint.find(key);
      if (it != midpoint.end()) return it->second;
      v.push_back(0.5 * (v[a] + v[b]));
      return midpoint[key] = static_cast<int>(v.size()) - 1;
    };
    std::vector<std::array<int, 3>> finer;
    for (const auto& f : t) {
      const int ab = mid(f[0], f[1]), bc = mid(f[1], f[2]), ca = mid(f[2], f[0]);
      finer.push_back({f[0], ab, ca});
      finer.push_back({f[1], bc, ab});
      finer.push_back({f[2], ca, bc});
      finer.push_back({ab, bc, ca});
    }
    t.swap(finer);
  }
  TriangleMesh mesh;
  for (const Vec3& p : v) mesh.vertices.push_back(centre + radius * p.normalized());
  mesh.triangles = t;
  mesh.finalize();
  return mesh;
}

}  // namespace trackbed::dem::testing
