// Random sequential addition: bodies placed one by one at random positions in a box, each kept
// only if its bounding sphere overlaps no earlier one. Gives loose clouds (solid fraction up to
// ~0.35-0.4) for deposition under gravity. Deterministic for a given seed.
#pragma once

#include <cstdint>

#include "dem/clump_template.h"
#include "dem/material.h"
#include "dem/particles.h"

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

}  // namespace trackbed::dem
