// Which deposition friction gives a target porosity: the porosity a bed settles to under gravity
// falls as the friction during deposition is lowered (frictionless spheres pack densest). A
// small box of the same stones is deposited at a few friction factors, its porosity measured away
// from the walls, and the factor for the target interpolated linearly between the two
// bracketing points (docs/samples.md, "Compaction to a target porosity").
#pragma once

#include <cstdint>
#include <vector>

#include "dem/samples/grading.h"
#include "dem/samples/section_model.h"
#include "dem/samples/settling.h"

namespace trackbed::dem {

struct CalibrationPoint {
  double friction_factor;
  double porosity;
  StageReport stage;
};

struct CalibrationResult {
  std::vector<CalibrationPoint> points;  // ascending friction factor
  double friction_factor;                // for the target (clamped to the points' range)
  bool target_in_range;                  // the target lies between the extreme porosities
};

struct CalibrationSettings {
  std::vector<double> factors = {0.25, 0.5, 1.0};
  double bed_height = 0.5;  // m of settled bed (the section's crest height)
  double plan_size = 0.5;   // m, square box (at least 8 largest stones)
  double stage_ratio = 1e-3;
  double max_stage_time = 4;
  double deposition_damping = 0.3;
  double preparation_damping = 0.3;
  double critical_fraction = 0.35;
  double skin = 0.004;
  std::uint64_t seed = 1;
};

// Deposits the calibration box once per factor with the materials of `model` (walls: its
// frictionless wall material, base: ballast) and returns the factor for `target`. Throws
// InputError for factors outside [0, 1] or fewer than two of them.
CalibrationResult calibrate_deposition_friction(const SieveTable& grading,
                                                const SectionMaterials& materials, double target,
                                                const CalibrationSettings& settings,
                                                StageRunner& runner);

}  // namespace trackbed::dem
