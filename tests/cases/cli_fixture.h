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

class Cli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("trackbed_cli_" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
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
  void expect_error(const Result& r, std::initializer_list<std::string> parts) {
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
