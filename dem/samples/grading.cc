#include "dem/samples/grading.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <sstream>
#include <stdexcept>

#include "common/input_error.h"
#include "common/number_text.h"
#include "dem/io/csv_table.h"

namespace trackbed::dem {

namespace {

// Where a table's sieves come from, for messages: "SOURCE: sieve N" or "FILE:LINE".
struct TableLocation {
  std::function<std::string(int sieve)> sieve;  // the prefix of a message about one sieve
  std::string table;                            // the prefix of a message about the whole table
};

TableLocation location_of(const SieveTable& t) {
  return {[source = t.source](int i) { return source + ": sieve " + std::to_string(i + 1); },
          t.source};
}

void validate(const SieveTable& t, const TableLocation& at) {
  if (t.size.size() != t.passing.size())
    throw InputError(at.table + ": " + std::to_string(t.size.size()) + " sizes but " +
                     std::to_string(t.passing.size()) +
                     " passing values; valid: one passing value per sieve");
  const int n = static_cast<int>(t.size.size());
  if (n < 2)
    throw InputError(at.table + ": sieve table has " + std::to_string(n) +
                     " sieve(s); valid: at least two sieves, 0 % passing the smallest and 100 % "
                     "the largest");
  for (int i = 0; i < n; ++i) {
    const double a = t.size[i], p = t.passing[i];
    if (!std::isfinite(a) || a <= 0 || a > kMaxSieveSize)
      throw InputError(at.sieve(i) + ": size " + number_text(a, 12) +
                       " m is not valid; valid: a finite aperture > 0 and at most " +
                       number_text(kMaxSieveSize, 12) + " m (sizes are in metres: 63 mm is 0.063)");
    if (i > 0 && a <= t.size[i - 1])
      throw InputError(at.sieve(i) + ": size " + number_text(a, 12) + " m is not above the " +
                       number_text(t.size[i - 1], 12) +
                       " m of the sieve before; valid: sizes strictly increasing");
    if (!std::isfinite(p) || p < 0 || p > 100)
      throw InputError(at.sieve(i) + ": passing " + number_text(p, 12) +
                       " % is not valid; valid: a percentage by mass in [0, 100]");
    if (i > 0 && p < t.passing[i - 1])
      throw InputError(at.sieve(i) + ": passing " + number_text(p, 12) + " % is below the " +
                       number_text(t.passing[i - 1], 12) +
                       " % of the smaller sieve before; valid: passing non-decreasing with size");
  }
  if (t.passing.front() != 0)
    throw InputError(at.sieve(0) + ": the smallest sieve passes " + number_text(t.passing[0], 12) +
                     " %; valid: 0 % (add a smaller sieve with 0 % passing: stones are sampled "
                     "between the smallest and the largest sieve)");
  if (t.passing.back() != 100)
    throw InputError(at.sieve(n - 1) + ": the largest sieve passes " +
                     number_text(t.passing.back(), 12) +
                     " %; valid: 100 % (add a larger sieve with 100 % passing)");
}

// Uniform in (0, 1] from the top 53 bits: the same numbers on every standard library, which
// std::uniform_real_distribution does not promise.
double unit_interval(std::mt19937_64& rng) {
  return static_cast<double>((rng() >> 11) + 1) * 0x1.0p-53;
}

// Uniform in [0, n), without modulo bias (the rare draws below 2^64 mod n are rejected).
std::uint64_t below(std::uint64_t n, std::mt19937_64& rng) {
  const std::uint64_t reject_below = (0 - n) % n;  // 2^64 mod n
  while (true) {
    const std::uint64_t r = rng();
    if (r >= reject_below) return r % n;
  }
}

// A size in (a0, a1] with the mass spread uniformly in log(a) (the passing curve a straight line
// on the usual semi-log grading chart): by number the density is proportional to a^-4, whose
// inverse cumulative distribution is a = (a0^-3 - t (a0^-3 - a1^-3))^(-1/3).
double draw_size(double a0, double a1, std::mt19937_64& rng) {
  const double t = unit_interval(rng);
  const double c0 = 1 / (a0 * a0 * a0), c1 = 1 / (a1 * a1 * a1);
  const double a = std::cbrt(1 / (c0 - t * (c0 - c1)));
  // Rounding may land on a0 or just past a1; the interval is (a0, a1].
  return std::clamp(a, std::nextafter(a0, a1), a1);
}

}  // namespace

SieveTable en13450_ballast_grading() {
  SieveTable t;
  t.size = {0.0224, 0.0315, 0.040, 0.050, 0.063, 0.080};
  t.passing = {0, 13, 47.5, 84.5, 100, 100};
  t.source = "EN 13450 grading 31.5/63 (middle of category A, 0 % at 22.4 mm)";
  return t;
}

void validate_sieve_table(const SieveTable& table) {
  validate(table, location_of(table));
}

double largest_stone_size(const SieveTable& table) {
  for (std::size_t k = 0; k < table.size.size(); ++k)
    if (table.passing[k] >= 100) return table.size[k];
  return table.size.back();
}

SieveTable read_sieve_table_csv(const std::string& path) {
  const CsvTable csv(path, "sieve table");
  csv.require("size");
  csv.require("passing");
  SieveTable t;
  t.source = path;
  for (int row = 0; row < csv.num_rows(); ++row) {
    t.size.push_back(csv.number(row, "size"));
    t.passing.push_back(csv.number(row, "passing"));
  }
  const TableLocation at{[&](int i) { return path + ":" + std::to_string(csv.line_of(i)); },
                         path + ":" + std::to_string(csv.header_line())};
  validate(t, at);
  return t;
}

std::vector<GradedStone> sample_grading(const SieveTable& table, double total_volume,
                                        const std::vector<double>& shape_factors,
                                        const ShapeChooser& choose_shape, std::mt19937_64& rng) {
  validate_sieve_table(table);
  if (!std::isfinite(total_volume) || total_volume <= 0)
    throw InputError(table.source + ": sample of total solid volume " +
                     number_text(total_volume, 12) + " m^3; valid: a finite volume > 0");
  if (shape_factors.empty()) throw std::invalid_argument("sample_grading: no shape factors given");
  for (double f : shape_factors)
    if (!std::isfinite(f) || f <= 0)
      throw std::invalid_argument("sample_grading: shape factor " + number_text(f, 12) +
                                  " is not finite and > 0");
  std::vector<GradedStone> stones;
  for (std::size_t i = 0; i + 1 < table.size.size(); ++i) {
    const double share = (table.passing[i + 1] - table.passing[i]) / 100 * total_volume;
    double filled = 0;
    while (share > 0) {
      const double a = draw_size(table.size[i], table.size[i + 1], rng);
      const int k = choose_shape(a, rng);
      if (k < 0 || k >= static_cast<int>(shape_factors.size()))
        throw std::invalid_argument("sample_grading: the shape chooser returned " +
                                    std::to_string(k) + "; valid: 0 to " +
                                    std::to_string(shape_factors.size() - 1));
      const double v = shape_factors[k] * a * a * a;
      if (filled + v <= share) {
        stones.push_back({a, k, v});
        filled += v;
        continue;
      }
      // The stone that overfills the share: kept only if that leaves the total nearer to it, so
      // the interval's error is at most half a stone.
      if (filled + v - share < share - filled) stones.push_back({a, k, v});
      break;
    }
  }
  for (std::size_t i = stones.size(); i > 1; --i) std::swap(stones[i - 1], stones[below(i, rng)]);
  return stones;
}

std::vector<GradedStone> sample_grading(const SieveTable& table, double total_volume,
                                        double shape_factor, std::mt19937_64& rng) {
  return sample_grading(
      table, total_volume, {shape_factor}, [](double, std::mt19937_64&) { return 0; }, rng);
}

std::vector<double> passing_by_mass(const std::vector<double>& sizes,
                                    const std::vector<double>& volumes,
                                    const std::vector<double>& sieves) {
  if (sizes.size() != volumes.size())
    throw std::invalid_argument("passing_by_mass: " + std::to_string(sizes.size()) + " sizes but " +
                                std::to_string(volumes.size()) + " volumes");
  double total = 0;
  for (double v : volumes) total += v;
  if (sizes.empty() || !(total > 0))
    throw std::invalid_argument("passing_by_mass: no stones, or a total volume that is not > 0");
  std::vector<double> passing(sieves.size(), 0.0);
  for (std::size_t s = 0; s < sieves.size(); ++s) {
    double below = 0;
    for (std::size_t i = 0; i < sizes.size(); ++i)
      if (sizes[i] <= sieves[s]) below += volumes[i];
    passing[s] = 100 * below / total;
  }
  return passing;
}

}  // namespace trackbed::dem
