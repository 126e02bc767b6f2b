#include "dem/samples/bubble_pack.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <sstream>
#include <unordered_map>

#include "common/input_error.h"
#include "dem/samples/closed_surface.h"

namespace trackbed::dem {
namespace {

constexpr double kPi = 3.14159265358979323846;

void check_settings(const BubblePackSettings& s, const std::string& name) {
  std::ostringstream msg;
  msg << name << ": bubble pack ";
  if (!(s.distance > 0.0 && s.distance <= 180.0)) {
    msg << "distance " << s.distance
        << " is not valid; it is an angle in degrees, > 0 and <= 180 (higher: more pebbles, "
           "tighter fit)";
  } else if (!(s.ratio > 0.0 && s.ratio <= 1.0)) {
    msg << "ratio " << s.ratio
        << " is not valid; it is the smallest over the largest pebble radius, > 0 and <= 1";
  } else if (!(s.resolution >= 8 && s.resolution <= 256)) {
    msg << "resolution " << s.resolution
        << " is not valid; it is the number of grid cells along the longest edge of the bounding "
           "box, 8 to 256";
  } else {
    return;
  }
  throw InputError(msg.str());
}

// Candidate pebbles: the centres of a regular grid of cells over the bounding box that lie inside
// the surface, each with the largest radius a sphere centred there can have, its distance to the
// surface. The grid is centred on the box so that symmetric shapes get symmetric samples.
std::vector<SphereShape> interior_candidates(const TriangleMesh& surface, int resolution,
                                             const std::string& name) {
  Vec3 lower = surface.vertices[0], upper = surface.vertices[0];
  for (const Vec3& v : surface.vertices) {
    lower = lower.cwiseMin(v);
    upper = upper.cwiseMax(v);
  }
  const double h = (upper - lower).maxCoeff() / resolution;
  std::array<int, 3> n;
  Vec3 first;
  for (int k = 0; k < 3; ++k) {
    n[k] = std::max(1, static_cast<int>(std::ceil((upper[k] - lower[k]) / h)));
    first[k] = 0.5 * (lower[k] + upper[k]) - 0.5 * (n[k] - 1) * h;
  }
  const SignedDistance distance(surface);
  std::vector<SphereShape> out;
  for (int z = 0; z < n[2]; ++z) {
    for (int y = 0; y < n[1]; ++y) {
      for (int x = 0; x < n[0]; ++x) {
        const Vec3 p = first + h * Vec3(x, y, z);
        const double d = distance(p);
        if (d < 0.0) out.push_back({p, -d});
      }
    }
  }
  if (out.empty()) {
    std::ostringstream msg;
    msg << name << ": no point of the bubble-pack grid (cell " << h
        << ") lies inside the surface; the stone is thinner than a cell, raise the resolution "
           "(at most 256)";
    throw InputError(msg.str());
  }
  // Largest first; a stable sort keeps grid order among equal radii, so the result is
  // reproducible.
  std::stable_sort(out.begin(), out.end(),
                   [](const SphereShape& a, const SphereShape& b) { return a.radius > b.radius; });
  return out;
}

// The accepted pebbles in a hash grid of cell r_max: a candidate of radius r can only be made
// redundant by a pebble closer than r + r_max, so a query visits a few cells only.
class PebbleGrid {
 public:
  PebbleGrid(const Vec3& origin, double cell) : origin_(origin), cell_(cell) {}

  void add(int id, const Vec3& centre) { cells_[key(index(centre))].push_back(id); }

  template <typename Visit>
  bool any_within(const Vec3& centre, double reach, Visit&& visit) const {
    const std::array<std::int64_t, 3> lo = index(centre - Vec3::Constant(reach));
    const std::array<std::int64_t, 3> hi = index(centre + Vec3::Constant(reach));
    for (std::int64_t x = lo[0]; x <= hi[0]; ++x) {
      for (std::int64_t y = lo[1]; y <= hi[1]; ++y) {
        for (std::int64_t z = lo[2]; z <= hi[2]; ++z) {
          const auto it = cells_.find(key({x, y, z}));
          if (it == cells_.end()) continue;
          for (int id : it->second) {
            if (visit(id)) return true;
          }
        }
      }
    }
    return false;
  }

 private:
  std::array<std::int64_t, 3> index(const Vec3& p) const {
    const Vec3 q = ((p - origin_) / cell_).array().floor();
    return {static_cast<std::int64_t>(q.x()), static_cast<std::int64_t>(q.y()),
            static_cast<std::int64_t>(q.z())};
  }
  // Cell indices lie within a few hundred of 0 (the box over r_max, plus one), far inside the
  // 21 bits each gets.
  static std::int64_t key(const std::array<std::int64_t, 3>& i) {
    constexpr std::int64_t kOffset = 1 << 20;
    return ((i[0] + kOffset) << 42) | ((i[1] + kOffset) << 21) | (i[2] + kOffset);
  }

  Vec3 origin_;
  double cell_;
  std::unordered_map<std::int64_t, std::vector<int>> cells_;
};

// Greedy acceptance, largest first. Pebbles of radii r1, r2 whose surfaces meet at the groove
// angle phi (measured through the outside) have centres d apart, d^2 = r1^2 + r2^2 +
// 2 r1 r2 cos(phi); a candidate closer than that to an accepted pebble is redundant. Candidates
// below ratio * r_max end the packing.
std::vector<SphereShape> accept_pebbles(const std::vector<SphereShape>& candidates,
                                        const BubblePackSettings& settings) {
  const double r_max = candidates.front().radius;
  const double cos_phi = std::cos(settings.distance * kPi / 180.0);
  std::vector<SphereShape> pebbles;
  PebbleGrid grid(candidates.front().centre, r_max);
  for (const SphereShape& c : candidates) {
    if (c.radius < settings.ratio * r_max) break;
    const bool redundant = grid.any_within(c.centre, c.radius + r_max, [&](int id) {
      const SphereShape& p = pebbles[id];
      const double d2 =
          c.radius * c.radius + p.radius * p.radius + 2.0 * c.radius * p.radius * cos_phi;
      return (c.centre - p.centre).squaredNorm() < d2;
    });
    if (redundant) continue;
    grid.add(static_cast<int>(pebbles.size()), c.centre);
    pebbles.push_back(c);
  }
  return pebbles;
}

}  // namespace

BubblePackResult bubble_pack(const TriangleMesh& surface, const BubblePackSettings& settings,
                             const std::string& name) {
  check_settings(settings, name);
  check_closed_surface(surface, name);

  BubblePackResult result;
  result.pebbles =
      accept_pebbles(interior_candidates(surface, settings.resolution, name), settings);
  result.max_radius = result.pebbles.front().radius;
  result.min_radius = result.pebbles.back().radius;

  result.surface_mass = surface_mass_properties(surface);
  result.pebble_mass = sphere_union_mass_properties(result.pebbles);
  result.volume_error =
      (result.pebble_mass.volume - result.surface_mass.volume) / result.surface_mass.volume;
  result.inertia_error = (result.pebble_mass.inertia - result.surface_mass.inertia).norm() /
                         result.surface_mass.inertia.norm();
  result.clump = make_clump_template_with_mass(
      name, result.pebbles,
      settings.mass_source == MassSource::surface ? result.surface_mass : result.pebble_mass);
  return result;
}

}  // namespace trackbed::dem
