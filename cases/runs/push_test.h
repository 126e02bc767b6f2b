// A push test of a mesh body (the single-sleeper lateral resistance test of the paper (Jia, Markine
// and Guo 2023)): the body is held until the bed is in equilibrium under the case's contact law (a
// sample built with other contacts, e.g. with rolling resistance that the case removes, first
// re-settles), then moves at the constant velocity of its push DOF until it has moved `distance`;
// its resistance is recorded against its displacement, split by the named parts of its mesh (a
// sleeper's base, sides facing the cribs, ends facing the shoulders).
//
//   equilibrium: mean unbalanced force ratio (Simulation::unbalanced_force_ratio) below
//                `equilibrium ratio` (and, on a coupled subgrade, the coupling converged) at 3
//                checks in a row, 200 steps apart, after `minimum hold`;
//                at `maximum hold` the push starts anyway and the summary says so
//
//   resistance R = -F . e     F: contact force the particles exert on the body, e: push direction
//   share of part p = R_p / R  at the peak of R
// R is reported as its running mean over a window of displacement (default 0.2 mm), since single
// stones slipping rattle the instantaneous value; push.csv keeps the raw rows.
//
// A `path` of displacements instead of one distance makes the body move to each in turn at the
// same speed (the ballast box test: up, down to compact, back to the start).
//
// Held still along the push, the body keeps whatever net load the bed leaves on it along the push
// (the sample seated it with that DOF fixed), and the push starts from that load; with
// `free_during_hold` the push DOF is free during the hold (moved by the bed's load on the body's
// mass), so the push starts from a body at rest under zero net load along it, as one that no
// actuator holds, and the displacement counts from where it then stands.
//
// Where the body gets its support when the push starts (dem/engine/sleeper_support.h: per part its
// contacts and its share of the vertical load, and the largest base contact's share) enters the
// summary: the case's hold re-settles the sample's bed under the case's contacts, and the push
// starts from the support the hold left, not the sample's.
//
// Outputs: push.csv (one row per history row of the push), summary items, push.png.
// Theory and definitions: docs/validation.md, "Lateral push test".
#pragma once

#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "cases/reports/report_support.h"
#include "dem/engine/simulation.h"

namespace trackbed::cases {

struct PushTestParameters {
  std::string mesh;                 // the pushed mesh body; empty: no push test
  int axis = 0;                     // 0 x, 1 y, 2 z
  double distance = 0.005;          // m: the run ends when the body has moved this far
  std::vector<double> path;         // m: displacements moved to in turn; empty: {distance}
  double min_hold = 0.02;           // s at rest at least before the push
  double max_hold = 1.0;            // s at rest at most
  double equilibrium_ratio = 1e-3;  // mean unbalanced force ratio that ends the hold
  bool free_during_hold = false;    // the push DOF free during the hold (else held still)
  double report_at = 0.002;         // m: the displacement at which the force is also reported
  double smoothing = 0.0002;        // m: window of the running mean of the resistance
};

class PushTest {
 public:
  // Checks that the mesh exists and that its push DOF is velocity-controlled with a non-zero
  // velocity; throws InputError naming `case_file` otherwise. Call after Simulation::setup.
  PushTest(PushTestParameters prm, dem::Simulation& sim, const std::string& case_file);

  // Simulated time at which the test will end: push start (or its earliest time while the body is
  // held) + path length / |velocity|.
  double expected_end(const dem::Simulation& sim) const;
  // Every leg of the path travelled.
  bool finished() const;
  // The hold is over and the push has started.
  bool pushing() const { return push_start_ >= 0; }
  // Before every step: holds (or frees) the push DOF until equilibrium, then moves it. The hold
  // also waits for `foundation_settled`: what the bed rests on is at rest too (a coupled
  // subgrade whose staggered scheme has converged).
  void control(dem::Simulation& sim, bool foundation_settled = true);
  // After a history row: one row of push.csv (during the push only).
  void record(const dem::Simulation& sim);

  void write_csv(const std::string& path) const;
  std::vector<SummaryItem> summary() const;

  // What the test has done so far, for checkpoints (run_checkpoint.h): where the push started,
  // the hold, the leg being travelled, and the rows recorded, each as the numbers of its push.csv
  // row. A test made for the same case and given it goes on as the saved one would have.
  struct Progress {
    double start = 0, push_start = -1, hold_ratio = NAN;
    long leg = 0;
    int confirmations = 0;
    bool hold_converged = false;
    std::vector<std::vector<double>> rows;
    std::vector<double> start_support;  // empty while held
  };
  Progress progress() const;
  // Throws InputError if the rows do not have this test's columns.
  void resume(const Progress& p);

 private:
  struct Row {
    double time, displacement, resistance, vertical_load;
    std::vector<double> part_resistance;
    double max_particle_force, max_body_force;
    double unbalance;  // sum of all wall and body loads along e, N: ~0 for a bed at rest
  };
  double displacement(const dem::Simulation& sim) const;
  double path_length() const;
  // The body's support at the push start, as start_support_ holds it: per part its contacts and
  // its share of the vertical load, then the largest base contact's share.
  std::vector<double> support_now(const dem::Simulation& sim) const;
  // The rows [first, last) about row k that stay within prm_.smoothing / 2 of its displacement,
  // contiguous in time (a path passes a displacement more than once).
  std::pair<std::size_t, std::size_t> window(std::size_t k) const;
  // value(row) averaged over that window, for every row: the curve a reading at one instant would
  // give is rattled by single stones slipping.
  template <class Value>
  std::vector<double> smoothed(Value value) const;
  // A curve over the rows interpolated at displacement d (NaN if the push did not get there).
  double interpolated_at(const std::vector<double>& curve, double d) const;
  // The summary items of the parts: each part's share of the resistance averaged over the window
  // of row `peak`, and its support at the push start (when recorded).
  std::vector<SummaryItem> part_items(std::size_t peak) const;

  PushTestParameters prm_;
  int mesh_ = 0;
  double velocity_ = 0, start_ = 0, weight_ = 0;
  std::size_t leg_ = 0;     // index in prm_.path of the displacement being moved to
  double push_start_ = -1;  // s; < 0 while held
  int confirmations_ = 0;
  double hold_ratio_ = NAN;  // unbalanced force ratio when the push started
  bool hold_converged_ = false;
  std::vector<std::string> parts_;
  std::vector<Row> rows_;
  std::vector<double> start_support_;  // support_now() at the push start
};

}  // namespace trackbed::cases
