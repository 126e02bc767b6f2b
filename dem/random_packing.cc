#include "dem/random_packing.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>
#include <unordered_map>

#include "dem/input_error.h"

namespace trackbed::dem {

void add_random_packing(const RandomPackingSpec& spec, const MaterialTable& materials,
                        Particles& particles) {
  check_range("particle generator: number", spec.count, 0, 1e9);
  check_range("particle generator: minimum radius", spec.radius_min, 1e-9, 1e3);
  check_range("particle generator: maximum radius", spec.radius_max, spec.radius_min, 1e3);
  check_range("particle generator: clump fraction", spec.clump_fraction, 0, 1);
  if (spec.clump_fraction > 0 && !spec.clump_template)
    throw InputError("particle generator: clump fraction > 0 needs a clump template");
  const Vec3 size = spec.upper - spec.lower;
  if (!(size.minCoeff() > 0))
    throw InputError("particle generator: region upper corner must exceed the lower corner");

  std::mt19937_64 rng(spec.seed);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  // Bounding spheres of the placed bodies on a hash grid of cell 2*r_bound_max.
  const double ratio = spec.clump_template ? spec.clump_template->bounding_radius /
                                                 spec.clump_template->equivalent_radius()
                                           : 1.0;
  const double cell = 2 * spec.radius_max * std::max(ratio, 1.0);
  struct Placed {
    Vec3 c;
    double r;
  };
  std::unordered_map<std::int64_t, std::vector<Placed>> grid;
  auto key = [&](int i, int j, int k) {
    return (static_cast<std::int64_t>(i) * 73856093) ^ (static_cast<std::int64_t>(j) * 19349663) ^
           (static_cast<std::int64_t>(k) * 83492791);
  };
  auto cell_of = [&](const Vec3& x, int& i, int& j, int& k) {
    i = static_cast<int>(std::floor((x.x() - spec.lower.x()) / cell));
    j = static_cast<int>(std::floor((x.y() - spec.lower.y()) / cell));
    k = static_cast<int>(std::floor((x.z() - spec.lower.z()) / cell));
  };
  const double density = materials[spec.material].density;
  const std::int64_t first_id = particles.num_bodies();

  // Sizes and kinds are drawn first and placed largest first: a large body drawn late would
  // find no hole big enough among many small ones (the usual remedy in sample generators).
  struct Draw {
    double r;
    bool clump;
  };
  std::vector<Draw> draws(spec.count);
  for (auto& d : draws) {
    d.r = spec.radius_min + (spec.radius_max - spec.radius_min) * u01(rng);
    d.clump = u01(rng) < spec.clump_fraction;
  }
  std::stable_sort(draws.begin(), draws.end(), [&](const Draw& a, const Draw& b) {
    return a.r * (a.clump ? ratio : 1.0) > b.r * (b.clump ? ratio : 1.0);
  });

  for (int n = 0; n < spec.count; ++n) {
    const double r = draws[n].r;
    const bool clump = draws[n].clump;
    const double bound = clump ? r * ratio : r;
    bool placed = false;
    for (int a = 0; a < spec.attempts_per_body && !placed; ++a) {
      Vec3 c;
      for (int k = 0; k < 3; ++k) c[k] = spec.lower[k] + bound + (size[k] - 2 * bound) * u01(rng);
      if ((size.array() < 2 * bound).any()) break;
      int ci, cj, ck;
      cell_of(c, ci, cj, ck);
      bool free = true;
      for (int i = ci - 1; i <= ci + 1 && free; ++i)
        for (int j = cj - 1; j <= cj + 1 && free; ++j)
          for (int k = ck - 1; k <= ck + 1 && free; ++k) {
            auto it = grid.find(key(i, j, k));
            if (it == grid.end()) continue;
            for (const Placed& p : it->second)
              if ((p.c - c).squaredNorm() < (p.r + bound) * (p.r + bound)) {
                free = false;
                break;
              }
          }
      if (!free) continue;
      grid[key(ci, cj, ck)].push_back({c, bound});
      if (clump) {
        // A uniformly random orientation (Shoemake's method).
        const double u1 = u01(rng), u2 = 2 * M_PI * u01(rng), u3 = 2 * M_PI * u01(rng);
        const Quat q(std::sqrt(u1) * std::cos(u3), std::sqrt(1 - u1) * std::sin(u2),
                     std::sqrt(1 - u1) * std::cos(u2), std::sqrt(u1) * std::sin(u3));
        const ClumpTemplate t =
            scaled(*spec.clump_template, r / spec.clump_template->equivalent_radius());
        particles.add_clump(t, c, q, spec.material, density, first_id + n);
      } else {
        particles.add_ball(c, r, spec.material, density, first_id + n);
      }
      placed = true;
    }
    if (!placed) {
      std::ostringstream s;
      s << "particle generator: placed only " << n << " of " << spec.count
        << " bodies in the region (too dense for random addition); valid: fewer bodies or a "
           "larger region (random addition reaches solid fractions of about 0.35)";
      throw InputError(s.str());
    }
  }
}

}  // namespace trackbed::dem
