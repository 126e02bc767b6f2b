// `trackbed build-sample`: builds a track-bed sample as a sample file describes it and writes
// its results folder (docs/samples.md):
//   sample.h5                       the sample, for any case to load (particles/sample file)
//   base.h5                         the ball sample a conversion started from (if built here)
//   summary.json, summary.txt       counts, porosity, grading errors, stages, wall time, memory
//   grading.csv, grading.png        the grading curve: target and sample
//   history/build.csv               unbalanced force ratio, kinetic energy, contacts, the
//                                   sleeper's height and load per check
//   particles.vtu, contacts.vtu, walls.vtu, sample.pvd   ParaView
//   sample.png                      a cross-section and a plan view drawn from particles.vtu
//   checkpoint.h5                   while the build runs: the state to resume from
//                                   (sample_checkpoint.h), every `output/checkpoint interval` of
//                                   wall time and on Ctrl-C or SIGTERM; removed when done
#pragma once

#include <chrono>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "cases/parameters/sample_parameters.h"
#include "cases/runs/sample_checkpoint.h"
#include "dem/io/sample.h"
#include "dem/samples/settling.h"
#include "dem/samples/zone.h"

namespace trackbed::cases {

class SampleRun {
 public:
  explicit SampleRun(SampleParameters parameters);
  // Returns the process exit status: 0 done, 130 interrupted by a signal.
  int run();
  // Continues an interrupted build from its checkpoint, in its results folder.
  int resume(SampleCheckpoint checkpoint);

 private:
  // What a checkpoint holds of the part of the build that runs (ball build or conversion).
  using PartState = std::function<void(SampleCheckpoint&)>;

  int build(SampleCheckpoint* from);
  dem::Sample build_ball_sample(dem::BuildCheckpoint* from);
  dem::Sample convert(const dem::Sample& base, dem::ConversionCheckpoint* from);
  void report_pilots(const dem::Zone& zone, bool resumed);
  // From here on Ctrl-C and SIGTERM end the build at the next check of a stage, with a
  // checkpoint.
  void stop_at_checks();
  // At every check of a stage: a checkpoint when one is due or a signal came, and the build's
  // end on a signal. `step`: where the tests' signal (TRACKBED_TEST_SIGNAL) is due.
  void at_check(long step, const PartState& part);
  void write_checkpoint(const PartState& part);
  void connect(dem::StageRunner& runner);
  void write_outputs(const dem::Sample& sample, const dem::Simulation& sim,
                     const dem::Sample* base);
  void write_grading(const dem::Sample& sample, const dem::Sample* base);
  void write_summary(const dem::Sample& sample, const dem::Simulation& sim);
  void write_history();
  void make_plots();

  SampleParameters prm_;
  std::string out_;
  std::vector<dem::SettleSample> history_;
  std::vector<dem::StageReport> stages_;
  // Items of the summary that only the build or the conversion knows.
  std::vector<std::pair<std::string, std::string>> notes_;
  double max_grading_error_ = 0, max_grading_error_equivalent_ = 0;
  std::chrono::steady_clock::time_point start_, last_checkpoint_;
  double earlier_wall_seconds_ = 0;          // a resumed build's, up to its checkpoint
  std::string base_digest_;                  // of the base sample converted (sample_digest)
  std::string from_digest_;                  // that of the checkpoint resumed from
  std::pair<long, int> test_signal_{-1, 0};  // step, signal (TRACKBED_TEST_SIGNAL)
};

}  // namespace trackbed::cases
