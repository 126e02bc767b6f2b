// Random sequential addition: bodies placed one by one at random positions in a box, each kept
// only if its bounding sphere overlaps no earlier one. Gives loose clouds (solid fraction up to
// ~0.35-0.4) for deposition under gravity. Deterministic for a given seed.
#pragma once

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "dem/engine/clump_template.h"
#include "dem/engine/material.h"
#include "dem/engine/particles.h"

namespace trackbed::dem {

struct RandomPackingSpec {
  Vec3 lower = Vec3::Zero(), upper = Vec3::Ones();  // the bodies lie wholly inside this box
  int count = 0;
  double radius_min = 0.01, radius_max = 0.02;  // uniform by number; clumps: equivalent radius
  double clump_fraction = 0;                    // share of bodies that are clumps
  const ClumpTemplate* clump_template = nullptr;
  int material = 0;
  std::uint64_t seed = 1;
  int attempts_per_body = 2000;
};

// Appends the bodies to `particles`; throws InputError if the box cannot take them all.
void add_random_packing(const RandomPackingSpec& spec, const MaterialTable& materials,
                        Particles& particles);

// The placement itself: centres for spheres of the given (bounding) radii, each wholly inside
// the box and overlapping none placed before, placed largest first (ties in the given order)
// with up to `attempts_per_body` tries each. Returns the centres in the order of `radii`. Throws
// InputError, naming `what`, if some sphere finds no room.
std::vector<Vec3> random_sequential_positions(const std::vector<double>& radii, const Vec3& lower,
                                              const Vec3& upper, std::mt19937_64& rng,
                                              int attempts_per_body, const std::string& what);

// A uniformly random rotation (Shoemake 1992, "Uniform random rotations", Graphics Gems III).
Quat random_rotation(std::mt19937_64& rng);

}  // namespace trackbed::dem
