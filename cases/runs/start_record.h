// What `trackbed resume DIR` needs to start a run or a sample build again from its beginning when
// it was stopped before its first checkpoint: the command, its parameter file and that file's
// fingerprint, the mode and the threads. Written to DIR/start.txt when a run or a build starts
// (durably, before any work), removed when it finishes. Format: docs/formats.md, "start.txt".
#pragma once

#include <optional>
#include <string>

namespace trackbed::cases {

struct StartRecord {
  std::string command;      // run | build-sample
  std::string file;         // the case or sample file, absolute
  std::string fingerprint;  // its parameters' fingerprint (prm_support.h)
  std::string mode;         // dem | coupled (a run), empty for a build
  int threads = 0;          // as asked (0: OMP_NUM_THREADS)
};

// The file name in a results folder.
constexpr const char* kStartFile = "start.txt";

// Prepares `folder` for a fresh run or build: creates it (InputError naming `where`, the file and
// parameter that gave it, when it cannot be), drops an earlier run's checkpoint (resume must not
// go back to it) and writes the start record. Returns whether the folder was created.
bool begin_fresh(const std::string& folder, const StartRecord& record, const std::string& where);
// Undoes begin_fresh for a run or build refused for bad input as it set up: removes the start
// record, and the folder if begin_fresh created it and nothing but empty folders is in it.
void abandon_fresh(const std::string& folder, bool created);
// The start record of `folder`; none when it has no start.txt; InputError naming the file when
// it is damaged.
std::optional<StartRecord> read_start_record(const std::string& folder);
// Removes the start record of a finished run or build.
void remove_start_record(const std::string& folder);

}  // namespace trackbed::cases
