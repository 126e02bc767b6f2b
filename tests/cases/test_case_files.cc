// Every case and sample file shipped under cases/ is read as trackbed reads it, without running
// it: a parameter misspelt, a value out of range or an include that does not resolve in a file
// that only a full-size study runs (hours, never in CI) fails here instead of in a user's run.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <vector>

#include "cases/parameters/case_parameters.h"
#include "cases/parameters/sample_parameters.h"
#include "common/input_error.h"

namespace fs = std::filesystem;

namespace {

// The shipped .prm files: cases/ without the benchmark's work folder (its generated inputs).
std::vector<fs::path> shipped_files() {
  const fs::path root = fs::path(TRACKBED_SOURCE_DIR) / "cases";
  std::vector<fs::path> files;
  for (auto it = fs::recursive_directory_iterator(root); it != fs::recursive_directory_iterator();
       ++it) {
    if (it->is_directory() && it->path() == root / "bench" / "work") {
      it.disable_recursion_pending();
      continue;
    }
    if (it->path().extension() == ".prm") files.push_back(it->path());
  }
  return files;
}

bool is_sample_file(const fs::path& p) {
  return p.parent_path().filename() == "samples";
}

// The files that others include (the parts a study's models share): read through those.
std::set<fs::path> included_files(const std::vector<fs::path>& files) {
  std::set<fs::path> included;
  for (const fs::path& f : files) {
    std::ifstream in(f);
    for (std::string line; std::getline(in, line);)
      if (line.rfind("include ", 0) == 0)
        included.insert(fs::weakly_canonical(f.parent_path() / line.substr(8)));
  }
  return included;
}

// A zone taken from a pilot run's snapshots cannot be read before that run has been made (the
// reference push, hours at full size): its error names the pilot.
bool waits_for_pilot_run(const std::string& message) {
  return message.find("zone/clump zone") != std::string::npos &&
         message.find("pilot: ") != std::string::npos;
}

}  // namespace

using trackbed::cases::read_case_file;
using trackbed::cases::read_sample_file;

TEST(CaseFiles, EveryShippedFileIsRead) {
  const std::vector<fs::path> files = shipped_files();
  const std::set<fs::path> included = included_files(files);
  int samples = 0, cases = 0, pilots = 0;
  for (const fs::path& f : files) {
    if (included.count(fs::weakly_canonical(f))) continue;
    try {
      if (is_sample_file(f)) {
        read_sample_file(f.string());
        ++samples;
      } else {
        read_case_file(f.string());
        ++cases;
      }
    } catch (const trackbed::InputError& e) {
      if (is_sample_file(f) && waits_for_pilot_run(e.what()))
        ++pilots;
      else
        ADD_FAILURE() << f << ": " << e.what();
    }
  }
  // The shipped set at the time of writing: 17 samples (3 on pilot zones), 23 cases besides the
  // 4 shared parts (bounds, not counts to keep in step: they guard against the walk finding
  // nothing, and against every sample file waiting for a pilot).
  EXPECT_GE(samples, 12);
  EXPECT_LE(pilots, 4);
  EXPECT_GE(cases, 20);
}
