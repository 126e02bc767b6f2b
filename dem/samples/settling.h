// Running a model to static equilibrium, the building block of every stage of a sample build.
//
// Equilibrium is judged by PFC's mean unbalanced force ratio (Simulation::
// unbalanced_force_ratio): the stage ends once the ratio has stayed at or below `ratio` for
// `confirmations` checks in a row, `check_interval` steps apart, and any extra condition of the
// stage holds (e.g. a sleeper's load balanced). A stage that reaches `max_time` first ends
// unconverged; the report says so and the caller decides (docs/samples.md, "Equilibrium").
#pragma once

#include <chrono>
#include <functional>
#include <string>
#include <vector>

#include "dem/engine/simulation.h"

namespace trackbed::dem {

struct SettleCriterion {
  double ratio = 1e-4;  // mean unbalanced force ratio to reach
  int confirmations = 3;
  double min_time = 0;       // s simulated before the ratio is looked at
  double max_time = 5;       // s simulated at most
  int check_interval = 500;  // steps
  // Further condition, judged at a check where the ratio meets `ratio` (empty: none), and what is
  // done after every step (empty: nothing), e.g. recording the means it judges, or changing a
  // wall's control.
  std::function<bool(const Simulation&)> also;
  std::function<void(Simulation&)> each_step;
  // What `also` and `each_step` remember from one check to the next, as numbers, and its
  // restoring (empty: nothing), for checkpoints: a resumed stage judges as the uninterrupted one.
  std::function<std::vector<double>()> memory;
  std::function<void(const std::vector<double>&)> restore_memory;
};

// Where a stage stands at one of its checks: what it needs to go on from there (checkpoints).
struct StagePoint {
  long steps = 0;        // done in the stage
  int below = 0;         // checks in a row that met the criterion (settle)
  double wall_time = 0;  // s spent in the stage up to here
};

struct StageReport {
  std::string name;
  long steps = 0;
  double simulated_time = 0;  // s
  double wall_time = 0;       // s
  double final_ratio = 0;
  bool converged = false;
  int bodies = 0, elements = 0, contacts = 0;
  double time_step = 0;
};

// One row of a build's history, written at every check.
struct SettleSample {
  std::string stage;
  double time;  // s, simulated since the stage began
  long step;
  double ratio, kinetic_energy;
  int contacts;
  // The first mesh body (a section's sleeper): its height and the vertical force of its
  // contacts; NaN without one.
  double sleeper_z, sleeper_load;
};

// A timed stage whose step changes as it goes (StageRunner::run_for).
struct StepRenewal {
  // Called at the start of the stage and at every check (after at_check): may set another step.
  std::function<void(Simulation&)> renew;
  double began = 0;  // the model's clock when the stage began, s
};

class StageRunner {
 public:
  // Called at every check (history) and, at most every `progress_seconds` of wall time, with a
  // printable progress line.
  std::function<void(const SettleSample&)> on_sample;
  std::function<void(const std::string&)> on_progress;
  double progress_seconds = 5;
  // Called at every check that does not end the stage, after the history row, with the stage's
  // point there: where a caller writes checkpoints, and stops the stage by throwing (an
  // interrupted build).
  std::function<void(const StagePoint&)> at_check;

  // Steps `sim` (set up by the caller or here) until the criterion holds or max_time passes;
  // from a point of an earlier, interrupted run of the same stage when given.
  StageReport settle(Simulation& sim, const std::string& stage, const SettleCriterion& c,
                     const StagePoint& from = {});
  // Steps `sim` for a fixed simulated time, calling `each_step(step index)` before every step
  // (a growth schedule, a moving boundary), with the same history and progress. At a fixed step
  // the stage takes ceil(duration / step) steps; with a renewal, the steps left are counted again
  // from the time left, the model's clock less `renewal.began`, whenever it renews the step.
  StageReport run_for(Simulation& sim, const std::string& stage, double duration,
                      const std::function<void(long)>& each_step, const StagePoint& from = {},
                      int check_interval = 500, const StepRenewal& renewal = {});

 private:
  using Clock = std::chrono::steady_clock;
  // The history row and the progress line (its rate over the steps of this process, from
  // `first`).
  void check(const Simulation& sim, const std::string& stage, long steps, long first, double time,
             double ratio, Clock::time_point start, double max_time);
  Clock::time_point last_progress_{};
};

}  // namespace trackbed::dem
