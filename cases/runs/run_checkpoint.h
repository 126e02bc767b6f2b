// Checkpoints of a run (`trackbed run`): the engine's complete state (dem/io/engine_state.h) with
// the run's own, so that `trackbed resume DIR` continues an interrupted run from its last
// checkpoint and ends it bit for bit as the uninterrupted run would have (same case, same threads):
//   - the case it runs: its file and the fingerprint of its parameters (case_parameters.h);
//   - what the run has written: the bytes of each CSV history, the times of the ParaView frames;
//   - its clocks and counters: next history row, frame and snapshot, the start's energy and
//     element positions (for displacements), the wall and loop seconds spent;
//   - the push test's progress (push_test.h);
//   - a coupled run's FE displacement and staggered scheme (subgrade_coupling.h).
// Written to DIR/checkpoint.h5 under a temporary name and renamed, so a run killed while writing
// keeps its previous checkpoint. Format: docs/formats.md, "Checkpoints".
#pragma once

#include <string>
#include <vector>

#include "cases/runs/push_test.h"
#include "cases/runs/subgrade_coupling.h"
#include "dem/io/engine_state.h"

namespace trackbed::cases {

struct RunCheckpoint {
  std::string case_file;         // absolute path
  std::string case_fingerprint;  // CaseParameters::fingerprint
  std::string version;           // of the trackbed that wrote it
  int threads = 1;               // OpenMP threads of the run
  dem::EngineState engine;

  double next_history = 0, next_frame = 0, next_snapshot = 0;
  std::vector<double> frame_times;  // one per ParaView frame written (particles, contacts, walls)
  std::vector<long> history_bytes;  // walls.csv, energy.csv, bodies.csv
  bool warned_critical = false;
  long loop_start_step = 0;                   // the first step of the timed loop (after warm-up)
  double wall_seconds = 0, loop_seconds = 0;  // spent up to the checkpoint
  dem::EnergyBudget initial_energy;
  std::vector<dem::Vec3> initial_positions;  // of the elements at the start

  bool has_push = false;
  PushTest::Progress push;

  bool coupled = false;  // mode = coupled: the subgrade's FE state and the scheme's
  SubgradeCoupling::Progress coupling;
};

// The file name in a results folder.
constexpr const char* kCheckpointFile = "checkpoint.h5";

void write_run_checkpoint(const std::string& path, const RunCheckpoint& c);
// InputError naming the file for a missing, foreign or damaged checkpoint.
RunCheckpoint read_run_checkpoint(const std::string& path);

}  // namespace trackbed::cases
