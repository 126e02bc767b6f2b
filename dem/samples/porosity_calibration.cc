#include "dem/samples/porosity_calibration.h"

#include <algorithm>
#include <random>
#include <sstream>

#include "common/input_error.h"
#include "common/number_text.h"
#include "dem/samples/deposition.h"
#include "dem/samples/porosity.h"
#include "dem/samples/zone.h"

namespace trackbed::dem {

namespace {

constexpr double kPi = 3.14159265358979323846;

PlaneWall wall(const Vec3& point, const Vec3& normal, int material) {
  PlaneWall w;
  w.name = "calibration";
  w.point = point;
  w.normal = normal;
  w.material = material;
  return w;
}

}  // namespace

CalibrationResult calibrate_deposition_friction(const SieveTable& grading,
                                                const SectionMaterials& materials, double target,
                                                const CalibrationSettings& settings,
                                                StageRunner& runner) {
  std::vector<double> factors = settings.factors;
  std::sort(factors.begin(), factors.end());
  if (factors.size() < 2 || factors.front() < 0 || factors.back() > 1)
    throw InputError("build: calibration friction factors: give at least two in [0, 1]");
  const double largest = largest_stone_size(grading);
  const double side = settings.plan_size, h = settings.bed_height;
  // The stones to fill the box to the bed height at the target porosity.
  std::mt19937_64 rng(settings.seed);
  std::vector<double> sizes;
  for (const GradedStone& g : sample_grading(grading, side * side * h * (1 - target), kPi / 6, rng))
    sizes.push_back(g.size);
  SectionModel model(TrackSection(), materials, SimulationSettings(), settings.preparation_damping);

  CalibrationResult out;
  for (double f : factors) {
    SimulationSettings s;
    s.critical_fraction = settings.critical_fraction;
    s.skin = settings.skin;
    s.track_energy = false;
    Simulation sim(model.material_table({f, f, settings.deposition_damping}),
                   ball_cloud(sizes, Vec3::Zero(), Vec3(side, side, 0), 0.3, 0,
                              materials.ballast.density, settings.seed + 1),
                   s);
    sim.add_plane(wall(Vec3::Zero(), Vec3::UnitZ(), 0));
    for (int k = 0; k < 2; ++k) {
      sim.add_plane(wall(Vec3::Zero(), Vec3::Unit(k), 2));
      sim.add_plane(wall(side * Vec3::Unit(k), -Vec3::Unit(k), 2));
    }
    std::vector<StageReport> reports;
    DepositionStages stages{model.material_table({f, f, settings.deposition_damping}),
                            model.material_table({f, f, {}}), settings.stage_ratio,
                            settings.max_stage_time};
    deposit(sim, stages, runner, reports);
    StageReport both = reports.back();
    both.name = "calibration (friction x " + exact_number_text(f) + ")";
    both.steps = reports[0].steps + reports[1].steps;
    both.simulated_time = reports[0].simulated_time + reports[1].simulated_time;
    both.wall_time = reports[0].wall_time + reports[1].wall_time;
    // Away from the walls by one largest stone, below the bed's top by one.
    const Vec3 lo(largest, largest, largest), hi(side - largest, side - largest, h - largest);
    const double porosity =
        porosity_in_box(sim.particles(), lo, hi, 0.1 * grading.size.front()).porosity;
    out.points.push_back({f, porosity, both});
  }
  // Porosity grows with friction; interpolate between the bracketing points.
  const auto& p = out.points;
  out.target_in_range = target >= p.front().porosity && target <= p.back().porosity;
  out.friction_factor =
      target <= p.front().porosity ? p.front().friction_factor : p.back().friction_factor;
  for (std::size_t k = 0; k + 1 < p.size(); ++k) {
    const double n0 = p[k].porosity, n1 = p[k + 1].porosity;
    if (target >= std::min(n0, n1) && target <= std::max(n0, n1) && n1 != n0) {
      out.friction_factor =
          p[k].friction_factor +
          (target - n0) / (n1 - n0) * (p[k + 1].friction_factor - p[k].friction_factor);
      break;
    }
  }
  return out;
}

}  // namespace trackbed::dem
