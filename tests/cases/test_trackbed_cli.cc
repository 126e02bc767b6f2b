// The trackbed executable as a user runs it: every kind of bad input stops with one line naming
// the file/line or parameter and exits non-zero, leaving no partial output; a good run writes
// its results folder and is reproducible bit for bit.
#include <algorithm>
#include <cctype>
#include <csignal>
#include <cstdlib>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "cli_fixture.h"

namespace {

TEST_F(Cli, HelpVersionAndParameters) {
  EXPECT_EQ(run("--help").code, 0);
  const Result v = run("--version");
  EXPECT_EQ(v.code, 0);
  EXPECT_NE(v.out.find("trackbed "), std::string::npos);
  const Result p = run("--print-parameters");
  EXPECT_EQ(p.code, 0);
  EXPECT_NE(p.out.find("subsection materials"), std::string::npos);
  expect_error(run("frobnicate"), {"unknown command 'frobnicate'", "valid:"});
}

TEST_F(Cli, UnknownParameterNamesFileAndLine) {
  const fs::path f =
      write("case.prm", small_case("subsection simulation\n  set tme step = 1\nend\n"));
  // The misspelled entry is on line 2 of the appended block, after the small case's lines.
  expect_error(run("run " + f.string()), {f.string(), "tme step", "Line <"});
}

// 'include FILE' is relative to the including file, nests, and later lines override; an error
// in an included file names that file and its line; a missing include is one line too.
TEST_F(Cli, IncludedFilesNestAndNameTheirLines) {
  fs::create_directories(dir_ / "shared" / "deeper");
  write("shared/deeper/steps.prm", "subsection simulation\n  set number of steps = 7\nend\n");
  write("shared/base.prm", small_case() + "include deeper/steps.prm\n");
  const fs::path good = write("good.prm",
                              "include shared/base.prm\nsubsection simulation\n"
                              "  set number of steps = 9\nend\n");
  const Result r = run("run " + good.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find(" 9 steps"), std::string::npos) << r.out;

  write("shared/deeper/steps.prm", "subsection simulation\n  set numbr of steps = 7\nend\n");
  expect_error(run("run " + good.string()),
               {"Line <2> of file <" + (dir_ / "shared/deeper/steps.prm").string(), "numbr"});
  const fs::path missing = write("missing.prm", "include nowhere.prm\n");
  expect_error(run("run " + missing.string()), {missing.string() + ":1", "nowhere.prm"});
}

// A relative file name resolves against the folder of the file that set it: an included file's
// particle file is found beside it, a later top-level value beside the top-level file.
TEST_F(Cli, IncludedFilesKeepTheirRelativePaths) {
  fs::create_directories(dir_ / "shared");
  const std::string balls = "x,y,z,radius\n0.1,0.1,0.1,0.01\n0.2,0.1,0.1,0.01\n";
  write("shared/balls.csv", balls);
  write("shared/base.prm", small_case("", "balls.csv"));
  const Result r = run("run " + write("good.prm", "include shared/base.prm\n").string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("2 bodies"), std::string::npos) << r.out;

  write("shared/other.csv", balls);
  const fs::path top = write("top.prm",
                             "include shared/base.prm\nsubsection particles\n"
                             "  set file = other.csv\nend\n");
  expect_error(run("run " + top.string()), {(dir_ / "other.csv").string(), "cannot open"});
}

TEST_F(Cli, OutOfRangeValueNamesParameterAndRange) {
  const fs::path f = write("case.prm", small_case("subsection materials\n  subsection material 0\n"
                                                  "    set normal stiffness = -5\n  end\nend\n"));
  expect_error(run("run " + f.string()), {"normal stiffness", "-5"});
}

TEST_F(Cli, MissingCaseAndParticleFiles) {
  expect_error(run("run " + (dir_ / "nope.prm").string()), {"nope.prm", "not found"});
  const fs::path f = write("case.prm", small_case("", (dir_ / "missing.csv").string()));
  expect_error(run("run " + f.string()), {"missing.csv", "cannot open"});
}

TEST_F(Cli, MalformedParticleFileNamesLine) {
  const fs::path csv = write("p.csv", "x,y,z,radius\n0.1,0.1,0.1,0.01\n0.2,abc,0.1,0.01\n");
  const fs::path f = write("case.prm", small_case("", csv.string()));
  expect_error(run("run " + f.string()), {csv.string() + ":3:", "'abc'"});
  const fs::path neg = write("n.csv", "x,y,z,radius\n0.1,0.1,0.1,-0.01\n");
  expect_error(run("run " + write("c2.prm", small_case("", neg.string())).string()),
               {neg.string() + ":2:", "radius must be > 0"});
}

// A tracked body's mass properties are in the summary: a ball of radius r has I = 2/5 m r^2
// about every axis and mass rho 4/3 pi r^3 (the first material's density), to the summary's ten
// significant digits.
TEST_F(Cli, TrackedBodiesMassPropertiesInTheSummary) {
  const fs::path csv = write("p.csv", "x,y,z,radius\n0.1,0.1,0.1,0.02\n");
  const fs::path f =
      write("case.prm", small_case("subsection output\n  set tracked bodies = 0\nend\n"
                                   "subsection materials\n  subsection material 0\n"
                                   "    set density = 2650\n  end\nend\n",
                                   csv.string()));
  ASSERT_EQ(run("run " + f.string()).code, 0);
  const double mass = summary_number(dir_ / "out", "body_0_mass_kg"), r = 0.02;
  EXPECT_NEAR(mass, 2650 * 4.0 / 3.0 * M_PI * r * r * r, 1e-9 * mass);
  EXPECT_EQ(summary_number(dir_ / "out", "body_0_elements"), 1);
  for (const char* k : {"1", "2", "3"})
    EXPECT_NEAR(
        summary_number(dir_ / "out", std::string("body_0_principal_inertia_") + k + "_kg_m2"),
        0.4 * mass * r * r, 1e-9 * mass * r * r);
}

TEST_F(Cli, OverlapAtStartIsRefused) {
  const fs::path csv = write("p.csv", "x,y,z,radius\n0.1,0.1,0.1,0.02\n0.13,0.1,0.1,0.02\n");
  expect_error(run("run " + write("c.prm", small_case("", csv.string())).string()),
               {"particles 0 and 1 overlap", "valid:"});
  const fs::path wall = write("w.csv", "x,y,z,radius\n0.1,0.1,0.01,0.02\n");
  expect_error(run("run " + write("c2.prm", small_case("", wall.string())).string()),
               {"particle 0 overlaps wall", "valid:"});
}

TEST_F(Cli, TimestepAboveCriticalIsRefused) {
  const fs::path f =
      write("case.prm", small_case("subsection simulation\n  set time step = 1e-3\nend\n"));
  expect_error(run("run " + f.string()),
               {"time step = 0.001", "critical", "allow timestep above critical"});
}

TEST_F(Cli, ExplodingBedStopsTheRun) {
  // Forced past the critical step the bed explodes; the run must stop with a clear line, exit 1.
  // The energy check sees it first (at step 153 of 20,000, a history row), before any overlap
  // passes half a radius.
  const fs::path f = write("case.prm", small_case("subsection simulation\n  set time step = 2e-4\n"
                                                  "  set allow timestep above critical = true\n"
                                                  "  set number of steps = 20000\nend\n"));
  const Result r = run("run " + f.string());
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("the model blew up at t = "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("energy from nowhere"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("reduce the time step"), std::string::npos) << r.err;
}

// A blow-up below the runaway overlap: a 4 x 4 x 4 block of balls with normal and shear dashpots
// of 0.5, in a box, at 0.96 of the critical step at its start. The side walls' contacts bring
// the estimate below the step and the block blows up: its energy balance error, 3e-3 at step 58,
// passes 0.1 at step 64 and is 0.64 at step 67 (at 0.48 and 0.72 of the estimate it stays below
// 3e-3 over the same time). With a checkpoint at every step, checked before it is written, the
// run stops as failed and keeps its last checkpoint; resumed, it fails the same way.
TEST_F(Cli, BlowUpStopsAsFailedKeepingItsCheckpoint) {
  std::string csv = "x,y,z,radius\n";
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      for (int k = 0; k < 4; ++k)
        csv += std::to_string(0.01 * (2 * i + 1)) + "," + std::to_string(0.01 * (2 * j + 1)) + "," +
               std::to_string(0.01 * (2 * k + 1) - 1e-6 * (k + 1)) + ",0.01\n";
  std::string walls = "subsection plane walls\n  set number of walls = 5\n";
  const char* planes[5][2] = {{"0, 0, 0", "0, 0, 1"},
                              {"0, 0, 0", "1, 0, 0"},
                              {"0.08, 0, 0", "-1, 0, 0"},
                              {"0, 0, 0", "0, 1, 0"},
                              {"0, 0.08, 0", "0, -1, 0"}};
  for (int w = 0; w < 5; ++w)
    walls += "  subsection wall " + std::to_string(w) + "\n    set point = " + planes[w][0] +
             "\n    set normal = " + planes[w][1] + "\n  end\n";
  const fs::path f = write(
      "case.prm",
      "subsection simulation\n  set time step = 1.2e-5\n  set allow timestep above critical = "
      "true\n  set number of steps = 3000\nend\n"
      "subsection materials\n  set number of materials = 1\n  subsection material 0\n"
      "    set normal stiffness = 2e6\n    set shear stiffness = 2e6\n"
      "    set rolling friction = 0.3\n    set local damping = 0.7\n"
      "    set normal damping ratio = 0.5\n    set shear damping ratio = 0.5\n  end\nend\n" +
          walls + "end\nsubsection particles\n  set file = " + write("block.csv", csv).string() +
          "\nend\nsubsection output\n  set folder = " + (dir_ / "out").string() +
          "\n  set history interval = 1e-3\n  set checkpoint interval = 1e-9\nend\n");
  const Result r = run("run " + f.string());
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("the model blew up at t = "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("energy from nowhere"), std::string::npos) << r.err;
  EXPECT_NE(slurp(dir_ / "out" / "summary.json").find("\"status\": \"failed: the model blew up"),
            std::string::npos);
  EXPECT_FALSE(fs::exists(dir_ / "out" / "plot.png"));
  ASSERT_TRUE(fs::exists(dir_ / "out" / "checkpoint.h5"));
  const Result resumed = run("resume " + (dir_ / "out").string());
  EXPECT_EQ(resumed.code, 1);
  EXPECT_EQ(resumed.err, r.err);
}

TEST_F(Cli, BadDofAndMeshFile) {
  const fs::path f = write("case.prm", small_case("subsection meshes\n  set number of meshes = 1\n"
                                                  "  subsection mesh 0\n    set dof z = servoo 3\n"
                                                  "  end\nend\n"));
  expect_error(run("run " + f.string()), {"meshes/mesh 0/dof z", "servoo", "valid: fixed"});
  const fs::path g = write("c2.prm", small_case("subsection meshes\n  set number of meshes = 1\n"
                                                "  subsection mesh 0\n    set file = none.stl\n"
                                                "  end\nend\n"));
  expect_error(run("run " + g.string()), {"none.stl"});
}

// A push test needs a mesh of that name whose push DOF has a velocity, and a hold that ends.
TEST_F(Cli, BadPushTest) {
  const std::string mesh =
      "subsection meshes\n  set number of meshes = 1\n  subsection mesh 0\n    set name = plate\n"
      "    set box = 0, 0, 0.5, 0.3, 0.3, 0.6\n    set dof x = %s\n  end\nend\n";
  auto case_with = [&](const std::string& dof, const std::string& push) {
    std::string m = mesh;
    m.replace(m.find("%s"), 2, dof);
    return small_case(m + "subsection push test\n" + push + "end\n");
  };
  const fs::path a = write("a.prm", case_with("velocity 0.01", "  set mesh = sleeper\n"));
  expect_error(run("run " + a.string()), {"push test/mesh = sleeper", "valid: plate"});
  const fs::path b = write("b.prm", case_with("fixed", "  set mesh = plate\n"));
  expect_error(run("run " + b.string()), {"push test/mesh = plate", "'dof x' must be"});
  const fs::path c = write("c.prm", case_with("velocity 0.01",
                                              "  set mesh = plate\n"
                                              "  set maximum hold = 0.01\n"));
  expect_error(run("run " + c.string()), {"maximum hold = 0.01", "minimum hold"});
  const fs::path d = write("d.prm", case_with("velocity 0.01",
                                              "  set mesh = plate\n"
                                              "  set path = 0.002, 0.002, 0\n"));
  expect_error(run("run " + d.string()), {"push test/path = 0.002, 0.002, 0", "point 2",
                                          "each point differs from the one before"});
}

TEST_F(Cli, EmptyOutputFolderIsRefused) {
  const fs::path f = write("case.prm", small_case());
  expect_error(run("run " + f.string() + " --output ''"), {"--output ''", "valid: a folder"});
  const fs::path g = write("g.prm", small_case("subsection output\n  set folder =\nend\n"));
  expect_error(run("run " + g.string()), {"output/folder is empty", "valid: a folder"});
}

// Inputs that once crashed, hung, ended with a stack trace or ran as if all were well: each is
// refused with one line naming the file and the parameter.
TEST_F(Cli, HostileCaseFilesAreRefused) {
  write("block.stl",
        "solid b\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 0 0\n"
        "   vertex 0 1 0\n  endloop\n endfacet\nendsolid b\n");
  write("afile", "not a folder\n");
  fs::create_directories(dir_ / "afolder");
  const std::string mesh = "subsection meshes\n  set number of meshes = 1\n  subsection mesh 0\n";
  const std::pair<std::string, std::vector<std::string>> cases[] = {
      {mesh + "    set file = block.stl\n    set scale = 1e300\n  end\nend\n",
       {"meshes/mesh0", "after scale and translation", "within 1e6 m"}},
      {"include afolder\n", {"include afolder", "not a regular file"}},
      {"include /dev/zero\n", {"include /dev/zero", "not a regular file"}},
      {"subsection output\n  set folder = " + (dir_ / "afile").string() + "\nend\n",
       {"output/folder", "cannot be created", "valid: a folder"}},
      {"subsection particles\n  subsection generator\n    set number = 1000000000\n  end\nend\n",
       {"number = 1000000000", "valid: at most"}},
      {"subsection materials\n  subsection material 0\n    set rolling friction = 5e-324\n"
       "  end\nend\n",
       {"case.prm", "rolling friction", "valid: a number of normal size"}},
      {"subsection simulation\n  set number of steps = 0\n  set end time = 1e30\nend\n",
       {"simulation/end time = 1e+30", "at most 1e12 steps"}},
      {mesh + "    set name = a,\"b\n  end\nend\n", {"meshes/mesh 0/name", "valid: 1 to 64"}},
      {"subsection simulation\n  set end time = " + std::string(100000, '1') + "x\nend\n",
       {"end time", "(100001 characters)"}},
  };
  for (const auto& [extra, parts] : cases) {
    const fs::path f = write("case.prm", small_case(extra));
    SCOPED_TRACE(extra.substr(0, 120));
    const Result r = run("run " + f.string());
    expect_error(r, parts);
    EXPECT_LT(r.err.size(), 1000u);
  }
}

// A full disk (a file size limit of 40 KB, with SIGXFSZ ignored as a disk gives no signal):
// the write that fails stops the run as failed in one line, its files whole or absent, none
// half-written; the HDF5 library's state stays sound (it once crashed at exit).
TEST_F(Cli, FullDiskStopsTheRunAsFailed) {
  const fs::path f =
      write("case.prm", small_case("subsection simulation\n  set number of steps = 3000\nend\n"
                                   "subsection output\n  set vtu interval = 5e-4\n"
                                   "  set checkpoint interval = 0.0001\nend\n"));
  const std::string command = "bash -c \"trap '' XFSZ; ulimit -f 40; " + std::string(TRACKBED_BIN) +
                              " run " + f.string() + "\" > /dev/null 2> '" +
                              (dir_ / "stderr").string() + "'";
  const int status = std::system(command.c_str());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 1);
  const std::string err = slurp(dir_ / "stderr");
  EXPECT_EQ(err.find('\n'), err.size() - 1) << err;
  EXPECT_NE(err.find("failed (disk full, or a file system read-only?)"), std::string::npos) << err;
  for (const auto& e : fs::recursive_directory_iterator(dir_ / "out"))
    EXPECT_EQ(e.path().string().find(".part"), std::string::npos) << e.path();
  EXPECT_NE(slurp(dir_ / "out/summary.json").find("\"status\": \"failed: "), std::string::npos);
}

// A file system turned read-only during the run, as the kernel does on a disk error (Linux refuses
// to remount one read-only while files are open for writing, so strace stands in: every write to
// the walls history fails with EROFS): the run stops at the row whose write failed, not at its
// end, as failed in one line naming the file; the summary says so, the other histories are kept
// and the failed one leaves no .part behind.
TEST_F(Cli, ReadOnlyFileSystemStopsTheRunAtTheFailedWrite) {
  if (std::system("strace -f -o /dev/null true > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "strace cannot trace processes here";
  const long steps = 200000;
  const fs::path f =
      write("case.prm",
            small_case("subsection simulation\n  set number of steps = " + std::to_string(steps) +
                       "\nend\nsubsection output\n  set history interval = 1e-5\nend\n"));
  const fs::path walls = fs::absolute(dir_ / "out/history/walls.csv.part");
  const std::string command = "strace -f -o /dev/null -P '" + walls.string() +
                              "' -e trace=write,writev -e inject=write,writev:error=EROFS " +
                              std::string(TRACKBED_BIN) + " run " + f.string() +
                              " > /dev/null 2> '" + (dir_ / "stderr").string() + "'";
  const int status = std::system(command.c_str());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 1);
  const std::string err = slurp(dir_ / "stderr");
  EXPECT_EQ(err.find('\n'), err.size() - 1) << err;
  EXPECT_NE(err.find("history/walls.csv: writing failed (disk full, or a file system read-only?)"),
            std::string::npos)
      << err;
  // Rows of 20-200 bytes, one a step: the stream's first full buffer (8 KiB) fails within a few
  // hundred steps, not at the end.
  EXPECT_LT(summary_number(dir_ / "out", "steps"), steps / 100);
  EXPECT_NE(slurp(dir_ / "out/summary.json").find("\"status\": \"failed: "), std::string::npos);
  EXPECT_TRUE(fs::exists(dir_ / "out/history/energy.csv"));
  EXPECT_FALSE(fs::exists(dir_ / "out/history/walls.csv"));
  for (const auto& e : fs::recursive_directory_iterator(dir_ / "out"))
    EXPECT_EQ(e.path().string().find(".part"), std::string::npos) << e.path();
}

// A coupled run's bad input: one line naming the parameter and what is valid, nothing written.
TEST_F(Cli, BadCoupledRun) {
  const fs::path a = write("a.prm", small_case());
  expect_error(run("run " + a.string() + " --mode coupled"),
               {"mode = coupled needs particles/sample file", "valid:"});
  EXPECT_FALSE(fs::exists(dir_ / "out"));
  const fs::path b = write("b.prm", small_case("subsection coupling\n  set relaxation = 0\nend\n"));
  expect_error(run("run " + b.string()), {"relaxation = 0", "valid: (0, 1]"});
  const fs::path c = write("c.prm", small_case("subsection coupling\n  set interval = 0\nend\n"));
  expect_error(run("run " + c.string()), {"interval", "0"});
  const fs::path d = write("d.prm", small_case("subsection fem\n  subsection layers\n"
                                               "    set ground depth = 0\n  end\nend\n"));
  expect_error(run("run " + d.string()), {"fem/layers/ground depth = 0", "valid: > 0"});
  const fs::path e = write("e.prm", small_case("subsection fem\n  subsection subgrade\n"
                                               "    set poisson ratio = 0.5\n  end\nend\n"));
  expect_error(run("run " + e.string()), {"fem/subgrade", "Poisson ratio = 0.5", "-1 < nu < 0.5"});
}

// The times of a history file's rows (its first column) or of a ParaView collection's frames.
std::vector<double> output_times(const fs::path& file) {
  std::istringstream in(slurp(file));
  const bool pvd = file.extension() == ".pvd";
  std::vector<double> times;
  for (std::string line; std::getline(in, line);) {
    if (pvd) {
      const auto at = line.find("timestep=\"");
      if (at != std::string::npos) times.push_back(std::stod(line.substr(at + 10)));
    } else if (!line.empty() && std::isdigit(static_cast<unsigned char>(line[0]))) {
      times.push_back(std::stod(line));
    }
  }
  return times;
}

TEST_F(Cli, GoodRunWritesResultsAndIsReproducible) {
  // 200 steps of 1e-5 s: the end, 2 ms, is a history time (every 0.5 ms) and a frame time.
  const fs::path f =
      write("case.prm", small_case("subsection output\n  set vtu interval = 1e-3\nend\n"));
  const Result a = run("run " + f.string() + " --threads 2");
  ASSERT_EQ(a.code, 0) << a.err;
  EXPECT_NE(a.out.find("sphere-steps/s"), std::string::npos);  // the progress line
  for (const char* name : {"summary.json", "summary.txt", "history/walls.csv", "history/energy.csv",
                           "particles.pvd", "contacts.pvd", "walls.pvd"})
    EXPECT_TRUE(fs::exists(dir_ / "out" / name)) << name;
  // Each output time once: the last state, which the loop wrote, is not written again at the end.
  EXPECT_EQ(output_times(dir_ / "out/history/walls.csv"),
            (std::vector<double>{0, 5e-4, 1e-3, 1.5e-3, 2e-3}));
  EXPECT_EQ(output_times(dir_ / "out/particles.pvd"), (std::vector<double>{0, 1e-3, 2e-3}));
  const std::string walls = slurp(dir_ / "out/history/walls.csv");
  const std::string snapshot = slurp(dir_ / "out/snapshots/state-000000200.h5");
  EXPECT_FALSE(snapshot.empty());
  fs::rename(dir_ / "out", dir_ / "first");
  const Result b = run("run " + f.string() + " --threads 2");
  ASSERT_EQ(b.code, 0) << b.err;
  EXPECT_EQ(slurp(dir_ / "out/history/walls.csv"), walls);
  EXPECT_EQ(slurp(dir_ / "out/history/energy.csv"), slurp(dir_ / "first/history/energy.csv"));
}

// A run interrupted and resumed from its checkpoint ends as the uninterrupted run: the same
// histories, push rows and summary figures, digit for digit. A plate pushes 150 dropped balls (a
// push test, with its hold) on two threads; two bodies are tracked.
class Resume : public Cli {
 protected:
  std::string pushing_case(const std::string& extra = "") {
    return small_case(
        "subsection particles\n  subsection generator\n    set number = 150\n"
        "    set region = 0, 0, 0, 0.3, 0.3, 0.3\n  end\nend\n"
        "subsection simulation\n  set number of steps = 0\nend\n"
        "subsection materials\n  subsection material 0\n    set local damping = 0.7\n  end\nend\n"
        "subsection plane walls\n  set number of walls = 4\n"
        "  subsection wall 1\n    set normal = 0, 1, 0\n  end\n"
        "  subsection wall 2\n    set point = 0, 0.3, 0\n    set normal = 0, -1, 0\n  end\n"
        "  subsection wall 3\n    set point = 0.3, 0, 0\n    set normal = -1, 0, 0\n  end\nend\n"
        "subsection meshes\n  set number of meshes = 1\n  subsection mesh 0\n"
        "    set name = plate\n    set box = -0.1, 0, 0, -0.001, 0.3, 0.12\n"
        "    set dof x = velocity 0.05\n  end\nend\n"
        "subsection push test\n  set mesh = plate\n  set distance = 0.01\n"
        "  set minimum hold = 0.3\n  set maximum hold = 0.33\nend\n"
        "subsection output\n  set tracked bodies = 0, 7\n  set progress interval = 0.05\n"
        "end\n" +
        extra);
  }
  // Runs the case with TRACKBED_TEST_SIGNAL="STEP SIGNAL" into out/.
  Result run_signalled(const fs::path& prm, long step, int signal) {
    setenv("TRACKBED_TEST_SIGNAL", (std::to_string(step) + " " + std::to_string(signal)).c_str(),
           1);
    Result r = run("run " + prm.string() + " --threads 2");
    unsetenv("TRACKBED_TEST_SIGNAL");
    return r;
  }
  void expect_same_results(const fs::path& a, const fs::path& b) {
    for (const char* f : {"push.csv", "history/walls.csv", "history/energy.csv",
                          "history/bodies.csv", "particles.pvd", "contacts.pvd"})
      EXPECT_TRUE(slurp(a / f) == slurp(b / f)) << f << " differs";
    // The plate's support at the push start is taken once, in the uninterrupted run after the
    // stop in the hold, and carried by the checkpoint of the stop in the push.
    for (const char* key :
         {"steps", "contacts", "kinetic_energy", "energy_balance_error", "peak_lateral_force_n",
          "max_particle_contact_force_push_n", "start_ends_contacts", "start_sides_contacts"})
      EXPECT_EQ(summary_number(a, key), summary_number(b, key)) << key;
    EXPECT_NE(slurp(b / "summary.json").find("\"status\": \"finished\""), std::string::npos);
    EXPECT_FALSE(fs::exists(b / "checkpoint.h5"));  // a finished run needs none
    // The same files: no snapshot or frame of the interruption left behind.
    auto names = [](const fs::path& folder) {
      std::set<std::string> all;
      for (const auto& e : fs::recursive_directory_iterator(folder))
        all.insert(fs::relative(e.path(), folder).string());
      return all;
    };
    EXPECT_EQ(names(a), names(b));
    for (const auto& e : fs::recursive_directory_iterator(b))
      EXPECT_EQ(e.path().string().find(".part"), std::string::npos) << e.path();
  }
};

TEST_F(Resume, InterruptedOrKilledRunEndsAsTheUninterruptedOne) {
  const fs::path f = write("case.prm", pushing_case());
  const Result whole = run("run " + f.string() + " --threads 2");
  ASSERT_EQ(whole.code, 0) << whole.err;
  const long steps = std::lround(summary_number(dir_ / "out", "steps"));
  ASSERT_GT(steps, 50000);  // hold 0.3-0.33 s, then 0.2 s of push at 1e-5 s
  fs::rename(dir_ / "out", dir_ / "whole");

  // SIGTERM in the push: a checkpoint is written, the run ends "interrupted" with code 130 and
  // says how to go on.
  const Result stopped = run_signalled(f, 45000, SIGTERM);
  EXPECT_EQ(stopped.code, 130) << stopped.err;
  EXPECT_NE(stopped.out.find("trackbed resume " + (dir_ / "out").string()), std::string::npos)
      << stopped.out;
  EXPECT_TRUE(fs::exists(dir_ / "out/checkpoint.h5"));
  EXPECT_NE(slurp(dir_ / "out/summary.json").find("interrupted"), std::string::npos);
  const Result resumed = run("resume " + (dir_ / "out").string());
  ASSERT_EQ(resumed.code, 0) << resumed.err;
  EXPECT_NE(resumed.out.find("resuming"), std::string::npos);
  expect_same_results(dir_ / "whole", dir_ / "out");
  fs::remove_all(dir_ / "out");

  // SIGKILL (a power loss) in the hold, with a checkpoint every millisecond of wall time: the run
  // goes on from the last one, its histories cut back to what that one counted.
  fs::remove(f);
  const fs::path g = write(
      "case.prm", pushing_case("subsection output\n  set checkpoint interval = 0.001\nend\n"));
  const Result killed = run_signalled(g, 20000, SIGKILL);
  EXPECT_TRUE(killed.code == -1 || killed.code == 128 + SIGKILL) << killed.code;  // by the shell
  ASSERT_TRUE(fs::exists(dir_ / "out/checkpoint.h5"));
  EXPECT_TRUE(fs::exists(dir_ / "out/history/walls.csv.part"));
  const Result revived = run("resume " + (dir_ / "out").string());
  ASSERT_EQ(revived.code, 0) << revived.err;
  expect_same_results(dir_ / "whole", dir_ / "out");
  fs::remove_all(dir_ / "out");

  // SIGKILL before the first checkpoint (every 600 s of wall time by default): resume starts the
  // run again from its beginning, on the threads it was started with.
  fs::remove(g);
  write("case.prm", pushing_case());
  const Result early = run_signalled(f, 3000, SIGKILL);
  EXPECT_TRUE(early.code == -1 || early.code == 128 + SIGKILL) << early.code;
  ASSERT_FALSE(fs::exists(dir_ / "out/checkpoint.h5"));
  const Result anew = run("resume " + (dir_ / "out").string());
  ASSERT_EQ(anew.code, 0) << anew.err;
  expect_same_results(dir_ / "whole", dir_ / "out");
}

// With snapshots on, a push test writes none in the hold, one where the push starts (the bed at
// rest: a pilot zone's reference, docs/zones.md#pilot-zones), one every interval after it and one
// at the end; a resumed run keeps that schedule. A fresh run first clears what an earlier run left
// in its folder's snapshots and frames.
TEST_F(Resume, PushSnapshotsStartWithThePush) {
  const fs::path f =
      write("case.prm", pushing_case("subsection output\n  set snapshot interval = 0.03\nend\n"));
  const fs::path stale_snapshot = dir_ / "out/snapshots/state-000000001.h5";
  const fs::path stale_frame = dir_ / "out/vtu/particles-000099.vtu";
  fs::create_directories(dir_ / "out/snapshots");
  fs::create_directories(dir_ / "out/vtu");
  std::ofstream(stale_snapshot) << "an earlier run's";
  std::ofstream(stale_frame) << "an earlier run's";
  auto snapshot_steps = [&](const fs::path& out) {
    std::vector<long> steps;
    for (const auto& e : fs::directory_iterator(out / "snapshots"))
      steps.push_back(std::atol(e.path().filename().string().c_str() + 6));  // state-NNNNNNNNN
    std::sort(steps.begin(), steps.end());
    return steps;
  };
  ASSERT_EQ(run("run " + f.string() + " --threads 2").code, 0);
  EXPECT_FALSE(fs::exists(stale_snapshot));
  EXPECT_FALSE(fs::exists(stale_frame));
  const double dt = summary_number(dir_ / "out", "time_step_s");
  const long start = std::lround(summary_number(dir_ / "out", "hold_time_s") / dt);
  const long end = std::lround(summary_number(dir_ / "out", "steps"));
  std::vector<long> expected;
  for (long s = start, k = 1; s < end; s = start + std::lround(k++ * 0.03 / dt))
    expected.push_back(s);
  expected.push_back(end);
  // A step or so either way: the clocks compare with half a step's tolerance.
  const std::vector<long> whole = snapshot_steps(dir_ / "out");
  ASSERT_EQ(whole.size(), expected.size());
  for (std::size_t k = 0; k < whole.size(); ++k) EXPECT_NEAR(whole[k], expected[k], 1) << k;
  fs::rename(dir_ / "out", dir_ / "whole");

  // Stopped in the hold and resumed: the same snapshots.
  ASSERT_EQ(run_signalled(f, 20000, SIGTERM).code, 130);
  ASSERT_EQ(run("resume " + (dir_ / "out").string()).code, 0);
  std::vector<long> resumed = snapshot_steps(dir_ / "out");
  resumed.erase(std::remove(resumed.begin(), resumed.end(), 20000L), resumed.end());
  EXPECT_EQ(resumed, whole);
}

// A fresh run in the folder of an interrupted one drops that one's checkpoint: killed before its
// own first (every 600 s of wall time by default), it is started anew by resume, not continued
// from the earlier run's state under the new run's outputs.
TEST_F(Resume, FreshRunDropsAnEarlierRunsCheckpoint) {
  const fs::path f = write("case.prm", pushing_case());
  ASSERT_EQ(run_signalled(f, 20000, SIGTERM).code, 130);
  ASSERT_TRUE(fs::exists(dir_ / "out/checkpoint.h5"));
  const Result killed = run_signalled(f, 10000, SIGKILL);
  EXPECT_TRUE(killed.code == -1 || killed.code == 128 + SIGKILL) << killed.code;
  EXPECT_FALSE(fs::exists(dir_ / "out/checkpoint.h5"));
  const Result resumed = run("resume " + (dir_ / "out").string());
  EXPECT_EQ(resumed.code, 0) << resumed.err;
  EXPECT_NE(resumed.out.find("stopped before its first checkpoint: starting"), std::string::npos)
      << resumed.out;
  EXPECT_NE(slurp(dir_ / "out/summary.json").find("\"status\": \"finished\""), std::string::npos);
  EXPECT_FALSE(fs::exists(dir_ / "out/start.txt"));  // a finished run needs none
}

// A run with the automatic time step (0 until the model is set up or restored) and an end time:
// resumed, it counts its steps with the restored step and ends where the uninterrupted one does.
TEST_F(Resume, AutomaticTimeStepRunEndsAsTheUninterruptedOne) {
  const fs::path f = write("case.prm", small_case("subsection simulation\n  set time step = 0\n"
                                                  "  set number of steps = 0\n"
                                                  "  set end time = 0.01\nend\n"));
  ASSERT_EQ(run("run " + f.string() + " --threads 1").code, 0);
  fs::rename(dir_ / "out", dir_ / "whole");
  setenv("TRACKBED_TEST_SIGNAL", ("100 " + std::to_string(SIGTERM)).c_str(), 1);
  const Result stopped = run("run " + f.string() + " --threads 1");
  unsetenv("TRACKBED_TEST_SIGNAL");
  ASSERT_EQ(stopped.code, 130) << stopped.err;
  ASSERT_EQ(run("resume " + (dir_ / "out").string()).code, 0);
  EXPECT_EQ(summary_number(dir_ / "out", "steps"), summary_number(dir_ / "whole", "steps"));
  EXPECT_TRUE(slurp(dir_ / "out/history/walls.csv") == slurp(dir_ / "whole/history/walls.csv"));
}

TEST_F(Resume, WhatCannotBeResumedIsSaidInOneLine) {
  const fs::path f = write("case.prm", pushing_case());
  expect_error(run("resume " + (dir_ / "nothing").string()), {"checkpoint.h5", "no such file"});
  ASSERT_EQ(run_signalled(f, 3000, SIGTERM).code, 130);
  expect_error(run("resume " + (dir_ / "out").string() + " --threads x"), {"--threads x"});
  // The case changed since: the parameter that differs, then and now.
  const std::string original = slurp(f);
  std::ofstream(f) << original << "subsection push test\n  set maximum hold = 0.34\nend\n";
  expect_error(run("resume " + (dir_ / "out").string()),
               {"case.prm has changed", "push test/maximum hold = 0.33", "= 0.34"});
  std::ofstream(f) << original;
  ASSERT_EQ(run("resume " + (dir_ / "out").string()).code, 0);
  expect_error(run("resume " + (dir_ / "out").string()), {"the run finished"});
}

}  // namespace
