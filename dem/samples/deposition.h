// Deposition of ballast under gravity, shared by the section build and the porosity calibration:
// a loose cloud of balls placed by random sequential addition, which falls with little damping
// (so it comes down at nearly g) and then settles with the ballast's own damping.
#pragma once

#include <cstdint>
#include <vector>

#include "dem/samples/settling.h"

namespace trackbed::dem {

// Balls of the given sieve sizes (diameters, m; ids in this order) in a loose cloud over the plan
// area [lower.x, upper.x] x [lower.y, upper.y] from z = lower.z up, at the given solid fraction.
Particles ball_cloud(const std::vector<double>& sizes, const Vec3& lower, const Vec3& upper,
                     double solid_fraction, int material, double density, std::uint64_t seed);

struct DepositionStages {
  MaterialTable fall, settle;  // the materials of the fall and of the settling
  double ratio = 1e-3;         // the settling stage's ratio; the fall ends at ten times it
  double max_stage_time = 4;
};

// The criterion of the fall (`fall`) or of the settling: the settling ends at `ratio`, the fall
// at ten times it (the bed still slides into place; the settling judges it).
SettleCriterion deposition_criterion(double ratio, double max_stage_time, bool fall);

// Runs the fall and the settling of `sim` (built by the caller with `stages.fall`), appending a
// report per stage.
void deposit(Simulation& sim, const DepositionStages& stages, StageRunner& runner,
             std::vector<StageReport>& reports);

}  // namespace trackbed::dem
