// The fixture of the tests that run the trackbed executable as a user does: a temporary folder,
// files written into it, a run with its exit code and output, and the check of a one-line
// input error that leaves nothing half-written.
#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

struct Result {
  int code;
  std::string out, err;
};

inline std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// A number of FOLDER/summary.json ("key": value); NaN and a test failure if it is not there.
inline double summary_number(const fs::path& folder, const std::string& key) {
  const std::string json = slurp(folder / "summary.json");
  const std::regex re("\"" + key + "\": ([-0-9.eE+]+)");
  std::smatch m;
  if (!std::regex_search(json, m, re)) ADD_FAILURE() << key << " not in " << folder;
  return m.size() > 1 ? std::stod(m[1]) : NAN;
}

// Checks FOLDER/summary.json against the stored figures of `model` in a reference CSV (model,
// quantity, value, relative tolerance; written by tests/cases/reference/update-case-reference).
inline void check_reference(const std::string& csv, const std::string& model,
                            const fs::path& folder) {
  std::ifstream in(csv);
  ASSERT_TRUE(in) << "reference file missing: " << csv;
  std::string line;
  int checked = 0;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#' || line.rfind("model,", 0) == 0) continue;
    std::stringstream s(line);
    std::string m, key, value, tol;
    std::getline(s, m, ',');
    std::getline(s, key, ',');
    std::getline(s, value, ',');
    std::getline(s, tol, ',');
    if (m != model) continue;
    const double expected = std::stod(value), rel = std::stod(tol);
    EXPECT_NEAR(summary_number(folder, key), expected, rel * std::abs(expected))
        << model << ": " << key;
    ++checked;
  }
  EXPECT_GT(checked, 0) << "no reference figures for " << model << " in " << csv;
}

// The seated sleeper's support in FOLDER/summary.json, its keys starting with PREFIX (sleeper_ in
// a sample's summary, start_ in a push's at the push start): the parts' shares of its vertical
// load sum to one (the load is their sum; dashpots at rest carry nothing), and it stands on its
// base, which carries most of it (the crib stones against its sides 0.1-0.2 in the samples,
// docs/samples.md).
inline void expect_sleeper_on_its_base(const fs::path& folder, const std::string& prefix) {
  double shares = 0;
  for (const char* part : {"base", "top", "sides", "ends"})
    shares += summary_number(folder, prefix + part + "_load_share");
  EXPECT_NEAR(shares, 1, 1e-6) << prefix;
  EXPECT_GE(summary_number(folder, prefix + "base_contacts"), 1) << prefix;
  EXPECT_GT(summary_number(folder, prefix + "base_load_share"), 0.5) << prefix;
}

class Cli : public ::testing::Test {
 protected:
  void SetUp() override {
    // Suite and test name: ctest runs tests of different suites with the same name (the
    // BallSample of the lateral push and of the ballast box) at the same time.
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("trackbed_cli_" + std::string(info->test_suite_name()) + "." + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path write(const std::string& name, const std::string& text) {
    const fs::path p = dir_ / name;
    std::ofstream(p) << text;
    return p;
  }
  Result run(const std::string& args) {
    const std::string cmd = std::string(TRACKBED_BIN) + " " + args + " > '" +
                            (dir_ / "stdout").string() + "' 2> '" + (dir_ / "stderr").string() +
                            "'";
    const int status = std::system(cmd.c_str());
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(dir_ / "stdout"),
            slurp(dir_ / "stderr")};
  }
  // Writes a file that includes `included` (a shipped sample or case file) followed by `extra`,
  // and runs `command` (build-sample or run) on it with one thread into `out`.
  Result run_including(const std::string& command, const fs::path& included,
                       const std::string& extra, const fs::path& out) {
    const fs::path prm =
        write(included.filename().string(), "include " + included.string() + "\n" + extra);
    return run(command + " " + prm.string() + " --threads 1 --output " + out.string());
  }
  // A small valid case: 40 balls dropped on a floor, 200 steps. `extra` is appended.
  std::string small_case(const std::string& extra = "", const std::string& particles = "") {
    std::string text =
        "set mode = dem\n"
        "subsection simulation\n  set time step = 1e-5\n  set number of steps = 200\nend\n"
        "subsection plane walls\n  set number of walls = 1\nend\n"
        "subsection output\n  set folder = " +
        (dir_ / "out").string() + "\n  set history interval = 5e-4\n  set plot = false\nend\n";
    if (particles.empty())
      text +=
          "subsection particles\n  subsection generator\n    set number = 40\n"
          "    set region = 0, 0, 0, 0.3, 0.3, 0.3\n  end\nend\n";
    else
      text += "subsection particles\n  set file = " + particles + "\nend\n";
    return text + extra;
  }
  // Checks the one-line error: exit code 2, a single line on stderr containing every `parts`.
  void expect_error(const Result& r, const std::vector<std::string>& parts) {
    EXPECT_EQ(r.code, 2) << r.err;
    std::string line = r.err;
    while (!line.empty() && line.back() == '\n') line.pop_back();
    EXPECT_EQ(line.find('\n'), std::string::npos) << "one line expected: " << r.err;
    for (const auto& p : parts)
      EXPECT_NE(r.err.find(p), std::string::npos) << p << " in: " << r.err;
    // Nothing half-written under a final name.
    if (fs::exists(dir_ / "out"))
      for (const auto& e : fs::recursive_directory_iterator(dir_ / "out"))
        EXPECT_EQ(e.path().string().find(".part"), std::string::npos) << e.path();
  }

  fs::path dir_;
};
