// Checkpoints of a sample build (`trackbed build-sample`), in its ball build or in its conversion
// of balls to clumps: the running stage and the engine's state there (dem/samples/sample_builder.h,
// dem/samples/clump_conversion.h) with the build's own, so that `trackbed resume DIR` goes on from
// the last checkpoint and ends the build bit for bit as the uninterrupted one would have (same
// sample file, same threads):
//   - the sample file it builds: its path and the fingerprint of its parameters, and, in a
//     conversion, a digest of the base sample it converts (a base rebuilt since would convert to
//     another bed);
//   - what the build has gathered: the history rows, the reports of the finished stages, the
//     notes of its ball build (when the ball sample was built in the same run), its wall time.
// The stones of a ball build are drawn again from the seed, and the replacement of balls by clumps
// is made again from the base sample (the sample file's 'base sample', or base.h5 of the folder):
// both are deterministic. Written to DIR/checkpoint.h5 as a run's checkpoint is
// (run_checkpoint.h); format: docs/formats.md, "Checkpoints".
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "dem/io/sample.h"
#include "dem/samples/clump_conversion.h"
#include "dem/samples/sample_builder.h"

namespace trackbed::cases {

struct SampleCheckpoint {
  std::string sample_file;  // absolute path
  std::string fingerprint;  // SampleParameters::fingerprint
  std::string base_digest;  // sample_digest() of the base sample (a conversion's)
  std::string version;      // of the trackbed that wrote it
  int threads = 1;
  double wall_seconds = 0;                                 // of the build, up to the checkpoint
  std::vector<dem::StageReport> stages;                    // of the ball build made in the same run
  std::vector<std::pair<std::string, std::string>> notes;  // its summary items
  std::vector<dem::SettleSample> history;                  // rows of history/build.csv so far
  // Taken in the ball build (`ball_build`), or in the conversion (`conversion`).
  bool in_ball_build = false;
  dem::BuildCheckpoint ball_build;
  dem::ConversionCheckpoint conversion;
  // The stage it was taken in and its step there, for a reader.
  std::string where() const;
};

void write_sample_checkpoint(const std::string& path, const SampleCheckpoint& c);
// InputError naming the file for a foreign or damaged checkpoint.
SampleCheckpoint read_sample_checkpoint(const std::string& path);
// A digest of a sample's bodies (count, ids, positions, element radii; FNV-1a over their bytes):
// equal for the same file, different for a sample built again with any other outcome.
std::string sample_digest(const dem::Sample& sample);
// Whether a checkpoint file is a sample build's (else a run's, or not a checkpoint).
bool is_sample_checkpoint(const std::string& path);

}  // namespace trackbed::cases
