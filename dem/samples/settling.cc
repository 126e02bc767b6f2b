#include "dem/samples/settling.h"

#include <cmath>
#include <cstdio>

namespace trackbed::dem {

namespace {

StageReport report_of(const Simulation& sim, const std::string& stage, long steps, double time,
                      double wall, double ratio, bool converged) {
  StageReport r;
  r.name = stage;
  r.steps = steps;
  r.simulated_time = time;
  r.wall_time = wall;
  r.final_ratio = ratio;
  r.converged = converged;
  r.bodies = sim.particles().num_bodies();
  r.elements = sim.particles().num_elements();
  r.contacts = sim.num_contacts();
  r.time_step = sim.time_step();
  return r;
}

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

}  // namespace

void StageRunner::check(const Simulation& sim, const std::string& stage, long steps, long first,
                        double t, double ratio, Clock::time_point start, double max_time) {
  const double ke = sim.particles().kinetic_energy();
  const bool sleeper = !sim.meshes().empty();
  if (on_sample)
    on_sample({stage, t, steps, ratio, ke, sim.num_contacts(),
               sleeper ? sim.meshes().front().x.z() : NAN,
               sleeper ? sim.meshes().front().contact_force.z() : NAN});
  if (!on_progress || seconds_since(last_progress_) < progress_seconds) return;
  last_progress_ = Clock::now();
  const double wall = seconds_since(start);
  const double rate = wall > 0 ? (steps - first) / wall : 0;
  char line[256];
  std::snprintf(line, sizeof line,
                "%s: t = %.4f s | step %ld | %.0f steps/s | %.2e sphere-steps/s | ratio %.2e | "
                "KE %.2e J | contacts %d | at most %.0f s left",
                stage.c_str(), t, steps, rate, rate * sim.particles().num_elements(), ratio, ke,
                sim.num_contacts(), rate > 0 ? (max_time - t) / sim.time_step() / rate : NAN);
  on_progress(line);
}

StageReport StageRunner::settle(Simulation& sim, const std::string& stage, const SettleCriterion& c,
                                const StagePoint& from) {
  const auto start = Clock::now();
  if (!sim.is_set_up()) sim.setup();
  const long max_steps = static_cast<long>(std::ceil(c.max_time / sim.time_step()));
  const long min_steps = static_cast<long>(std::ceil(c.min_time / sim.time_step()));
  StagePoint at = from;
  auto wall = [&] { return from.wall_time + seconds_since(start); };
  double ratio = NAN;
  while (at.steps < max_steps) {
    for (int k = 0; k < c.check_interval && at.steps < max_steps; ++k, ++at.steps) {
      sim.step();
      if (c.each_step) c.each_step(sim);
    }
    sim.check_finite();
    ratio = sim.unbalanced_force_ratio();
    if (at.steps >= min_steps)
      at.below = ratio <= c.ratio && (!c.also || c.also(sim)) ? at.below + 1 : 0;
    const double t = at.steps * sim.time_step();
    check(sim, stage, at.steps, from.steps, t, ratio, start, c.max_time);
    if (at.below >= c.confirmations) return report_of(sim, stage, at.steps, t, wall(), ratio, true);
    at.wall_time = wall();
    if (at_check) at_check(at);
  }
  return report_of(sim, stage, at.steps, at.steps * sim.time_step(), wall(), ratio, false);
}

StageReport StageRunner::run_for(Simulation& sim, const std::string& stage, double duration,
                                 const std::function<void(long)>& each_step, const StagePoint& from,
                                 int check_interval, const StepRenewal& renewal) {
  const auto start = Clock::now();
  if (!sim.is_set_up()) sim.setup();
  long n = static_cast<long>(std::ceil(duration / sim.time_step()));
  StagePoint at = from;
  // The stage's time: its steps at a fixed step; the clock's advance when the step changes.
  auto time = [&] {
    return renewal.renew ? sim.time() - renewal.began : at.steps * sim.time_step();
  };
  auto renew = [&] {
    if (!renewal.renew) return;
    renewal.renew(sim);
    n = at.steps + static_cast<long>(std::ceil((duration - time()) / sim.time_step()));
  };
  auto wall = [&] { return from.wall_time + seconds_since(start); };
  double ratio = NAN;
  renew();
  while (at.steps < n) {
    for (int k = 0; k < check_interval && at.steps < n; ++k, ++at.steps) {
      if (each_step) each_step(at.steps);
      sim.step();
    }
    sim.check_finite();
    ratio = sim.unbalanced_force_ratio();
    check(sim, stage, at.steps, from.steps, time(), ratio, start, duration);
    at.wall_time = wall();
    if (at.steps < n) {
      if (at_check) at_check(at);
      renew();
    }
  }
  return report_of(sim, stage, at.steps, time(), wall(), ratio, true);
}

}  // namespace trackbed::dem
