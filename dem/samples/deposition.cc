#include "dem/samples/deposition.h"

#include <random>

#include "dem/samples/random_packing.h"

namespace trackbed::dem {

namespace {
constexpr double kPi = 3.14159265358979323846;
}

Particles ball_cloud(const std::vector<double>& sizes, const Vec3& lower, const Vec3& upper,
                     double solid_fraction, int material, double density, std::uint64_t seed) {
  double solid = 0;
  std::vector<double> radii;
  for (double a : sizes) {
    radii.push_back(0.5 * a);
    solid += kPi / 6 * a * a * a;
  }
  const double area = (upper.x() - lower.x()) * (upper.y() - lower.y());
  const Vec3 top(upper.x(), upper.y(), lower.z() + solid / (solid_fraction * area));
  std::mt19937_64 rng(seed);
  const auto centres = random_sequential_positions(radii, lower, top, rng, 2000, "loose cloud");
  Particles p;
  for (std::size_t k = 0; k < radii.size(); ++k)
    p.add_ball(centres[k], radii[k], material, density, static_cast<std::int64_t>(k));
  return p;
}

SettleCriterion deposition_criterion(double ratio, double max_stage_time, bool fall) {
  SettleCriterion c;
  c.max_time = max_stage_time;
  c.ratio = fall ? 10 * ratio : ratio;
  return c;
}

void deposit(Simulation& sim, const DepositionStages& stages, StageRunner& runner,
             std::vector<StageReport>& reports) {
  reports.push_back(runner.settle(sim, "deposition",
                                  deposition_criterion(stages.ratio, stages.max_stage_time, true)));
  sim.set_materials(stages.settle);
  reports.push_back(runner.settle(
      sim, "settling", deposition_criterion(stages.ratio, stages.max_stage_time, false)));
}

}  // namespace trackbed::dem
