// Particle size distribution of ballast: a sieve table (the grading curve), its validation and CSV
// input, stratified sampling of stones that reproduces the table by mass, and the measure of a
// sample's grading curve. Rules, the default table and its source: docs/grading.md.
#pragma once

#include <functional>
#include <random>
#include <string>
#include <vector>

namespace trackbed::dem {

// A grading curve: the percentage by mass passing each sieve. A stone's sieve size a is the
// smallest square aperture it passes: it passes every sieve of aperture s >= a.
struct SieveTable {
  std::vector<double> size;     // sieve apertures, m, strictly ascending
  std::vector<double> passing;  // % by mass passing, 0 at the smallest sieve, 100 at the largest
  std::string source;           // names the table in messages ("grading.csv", "EN 13450 ...")
};

// EN 13450 grading 31.5/63 (railway ballast): the middle of each category A band, with 0 % at
// 22.4 mm so that every stone lies in 22.4-63 mm (docs/grading.md has the table and the choice).
SieveTable en13450_ballast_grading();

// Throws InputError (naming table.source and the sieve) unless: at least two sieves; sizes
// finite, > 0, at most kMaxSieveSize and strictly increasing; passing finite, in [0, 100] and
// non-decreasing; 0 at the smallest sieve and 100 at the largest.
void validate_sieve_table(const SieveTable& table);

// The largest stone a table allows: the smallest sieve that passes 100 %.
double largest_stone_size(const SieveTable& table);

// Reads columns `size` (m) and `passing` (%) of a CSV file (dem/io/csv_table.h rules; '#' comments)
// and validates the table; errors name the file and line.
SieveTable read_sieve_table_csv(const std::string& path);

// Largest sieve aperture accepted, m. Standard test sieves for aggregates stop at 125 mm; the
// limit is there to catch a table given in millimetres (63 read as 63 m).
constexpr double kMaxSieveSize = 1.0;

// One stone of a sample: its sieve size and the shape it was given.
struct GradedStone {
  double size;    // sieve size a, m
  int shape;      // index into the shape factors given to sample_grading
  double volume;  // shape_factors[shape] * size^3, m^3
};

// Picks the shape of the next stone (an index into the shape factors) from its sieve size; called
// once per stone, as it is drawn; may draw from the generator (e.g. a random clump template).
using ShapeChooser = std::function<int(double size, std::mt19937_64& rng)>;

// Draws stones whose total solid volume is about `total_volume` (m^3) and whose mass passing
// every sieve reproduces the table: each sieve interval is filled to its share of the volume by
// stones of sizes drawn within it, the last stone kept only if it brings the interval's volume
// nearer its share. A stone of sieve size a and shape k has volume shape_factors[k] * a^3 (pi/6
// for a ball of diameter a; a clump template has its own factor). The stones come in a random
// order (a Fisher-Yates shuffle), so a caller placing them one by one does not layer them by size.
// Deterministic for the generator's state, on every platform (docs/grading.md#sampling).
// Throws InputError for an invalid table or a total volume that is not finite and > 0, and
// std::invalid_argument for a shape factor that is not finite and > 0 or a chooser that returns
// an index out of range.
std::vector<GradedStone> sample_grading(const SieveTable& table, double total_volume,
                                        const std::vector<double>& shape_factors,
                                        const ShapeChooser& choose_shape, std::mt19937_64& rng);
// The same with one shape for every stone (shape 0).
std::vector<GradedStone> sample_grading(const SieveTable& table, double total_volume,
                                        double shape_factor, std::mt19937_64& rng);

// Percentage of the total volume (= mass, for one density) of the stones that passes each sieve:
// 100 * sum(volumes[i] for sizes[i] <= sieve) / sum(volumes). Throws std::invalid_argument for
// vectors of different lengths, no stones, or a total volume that is not > 0.
std::vector<double> passing_by_mass(const std::vector<double>& sizes,
                                    const std::vector<double>& volumes,
                                    const std::vector<double>& sieves);

}  // namespace trackbed::dem
