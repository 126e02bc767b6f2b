#include "dem/samples/random_packing.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>
#include <unordered_map>

#include "common/input_error.h"

namespace trackbed::dem {

std::vector<Vec3> random_sequential_positions(const std::vector<double>& radii, const Vec3& lower,
                                              const Vec3& upper, std::mt19937_64& rng,
                                              int attempts_per_body, const std::string& what) {
  const int n = static_cast<int>(radii.size());
  std::vector<Vec3> centres(n, Vec3::Zero());
  if (n == 0) return centres;
  const Vec3 size = upper - lower;
  if (!(size.minCoeff() > 0))
    throw InputError(what + ": region upper corner must exceed the lower corner");
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  // A large sphere placed late would find no hole among many small ones (the usual remedy in
  // sample generators): largest first.
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return radii[a] > radii[b]; });
  const double cell = 2 * radii[order[0]];
  // Placed spheres on a hash grid of cell 2 r_max: a new sphere can only meet the 27 cells
  // around its own.
  std::unordered_map<std::int64_t, std::vector<int>> grid;
  auto key = [](std::int64_t i, std::int64_t j, std::int64_t k) {
    return (i * 73856093) ^ (j * 19349663) ^ (k * 83492791);
  };
  auto cell_of = [&](const Vec3& x, int c[3]) {
    for (int k = 0; k < 3; ++k) c[k] = static_cast<int>(std::floor((x[k] - lower[k]) / cell));
  };
  int placed = 0;
  for (const int b : order) {
    const double r = radii[b];
    bool ok = false;
    for (int a = 0; a < attempts_per_body && !ok; ++a) {
      if ((size.array() < 2 * r).any()) break;
      Vec3 c;
      for (int k = 0; k < 3; ++k) c[k] = lower[k] + r + (size[k] - 2 * r) * u01(rng);
      int ci[3];
      cell_of(c, ci);
      bool free = true;
      for (int i = ci[0] - 1; i <= ci[0] + 1 && free; ++i)
        for (int j = ci[1] - 1; j <= ci[1] + 1 && free; ++j)
          for (int k = ci[2] - 1; k <= ci[2] + 1 && free; ++k) {
            const auto it = grid.find(key(i, j, k));
            if (it == grid.end()) continue;
            for (const int o : it->second)
              if ((centres[o] - c).squaredNorm() < (radii[o] + r) * (radii[o] + r)) {
                free = false;
                break;
              }
          }
      if (!free) continue;
      centres[b] = c;
      grid[key(ci[0], ci[1], ci[2])].push_back(b);
      ok = true;
    }
    if (!ok) {
      std::ostringstream s;
      s << what << ": placed only " << placed << " of " << n
        << " bodies in the region (too dense for random addition); valid: fewer bodies or a "
           "larger region (random addition reaches solid fractions of about 0.35)";
      throw InputError(s.str());
    }
    ++placed;
  }
  return centres;
}

Quat random_rotation(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  const double u1 = u01(rng), u2 = 2 * M_PI * u01(rng), u3 = 2 * M_PI * u01(rng);
  return Quat(std::sqrt(u1) * std::cos(u3), std::sqrt(1 - u1) * std::sin(u2),
              std::sqrt(1 - u1) * std::cos(u2), std::sqrt(u1) * std::sin(u3));
}

void add_random_packing(const RandomPackingSpec& spec, const MaterialTable& materials,
                        Particles& particles) {
  check_range("particle generator: number", spec.count, 0, 1e9);
  check_range("particle generator: minimum radius", spec.radius_min, 1e-9, 1e3);
  check_range("particle generator: maximum radius", spec.radius_max, spec.radius_min, 1e3);
  check_range("particle generator: clump fraction", spec.clump_fraction, 0, 1);
  if (spec.clump_fraction > 0 && !spec.clump_template)
    throw InputError("particle generator: clump fraction > 0 needs a clump template");
  if (!((spec.upper - spec.lower).minCoeff() > 0))
    throw InputError("particle generator: region upper corner must exceed the lower corner");

  // Random sequential addition jams at a solid fraction of about 0.35: bodies whose smallest
  // spheres alone would fill half the region cannot be placed, and are refused before their
  // arrays are allocated (a count in the hundreds of millions would exhaust the memory first).
  const double region = (spec.upper - spec.lower).prod();
  const double smallest = 4.0 / 3.0 * M_PI * std::pow(spec.radius_min, 3);
  if (spec.count * smallest > 0.5 * region) {
    std::ostringstream s;
    s << "particle generator: number = " << spec.count << " bodies of radius >= " << spec.radius_min
      << " m would fill " << spec.count * smallest / region
      << " of the region's volume; valid: at most " << std::floor(0.5 * region / smallest)
      << " (random addition reaches solid fractions of about 0.35)";
    throw InputError(s.str());
  }

  std::mt19937_64 rng(spec.seed);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  const double ratio = spec.clump_template ? spec.clump_template->bounding_radius /
                                                 spec.clump_template->equivalent_radius()
                                           : 1.0;
  // Sizes and kinds are drawn first, then placed largest first by their bounding spheres.
  std::vector<double> r(spec.count), bound(spec.count);
  std::vector<char> clump(spec.count);
  for (int n = 0; n < spec.count; ++n) {
    r[n] = spec.radius_min + (spec.radius_max - spec.radius_min) * u01(rng);
    clump[n] = u01(rng) < spec.clump_fraction;
    bound[n] = clump[n] ? r[n] * ratio : r[n];
  }
  std::vector<int> order(spec.count);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return bound[a] > bound[b]; });
  const std::vector<Vec3> centres = random_sequential_positions(
      bound, spec.lower, spec.upper, rng, spec.attempts_per_body, "particle generator");

  const double density = materials[spec.material].density;
  const std::int64_t first_id = particles.num_bodies();
  for (int k = 0; k < spec.count; ++k) {
    const int n = order[k];
    if (clump[n]) {
      const ClumpTemplate t =
          scaled(*spec.clump_template, r[n] / spec.clump_template->equivalent_radius());
      particles.add_clump(t, centres[n], random_rotation(rng), spec.material, density,
                          first_id + k);
    } else {
      particles.add_ball(centres[n], r[n], spec.material, density, first_id + k);
    }
  }
}

}  // namespace trackbed::dem
