// The trackbed executable as a user runs it: every kind of bad input stops with one line naming
// the file/line or parameter and exits non-zero, leaving no partial output; a good run writes
// its results folder and is reproducible bit for bit.
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

TEST_F(Cli, RunawayOverlapStopsTheRun) {
  // Forced past the critical step the bed explodes; the run must stop with a clear line, exit 1.
  const fs::path f = write("case.prm", small_case("subsection simulation\n  set time step = 2e-4\n"
                                                  "  set allow timestep above critical = true\n"
                                                  "  set number of steps = 20000\nend\n"));
  const Result r = run("run " + f.string());
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("runaway overlap"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("reduce the time step"), std::string::npos) << r.err;
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

TEST_F(Cli, GoodRunWritesResultsAndIsReproducible) {
  const fs::path f = write("case.prm", small_case());
  const Result a = run("run " + f.string() + " --threads 2");
  ASSERT_EQ(a.code, 0) << a.err;
  EXPECT_NE(a.out.find("sphere-steps/s"), std::string::npos);  // the progress line
  for (const char* name : {"summary.json", "summary.txt", "history/walls.csv", "history/energy.csv",
                           "particles.pvd", "contacts.pvd", "walls.pvd"})
    EXPECT_TRUE(fs::exists(dir_ / "out" / name)) << name;
  const std::string walls = slurp(dir_ / "out/history/walls.csv");
  const std::string snapshot = slurp(dir_ / "out/snapshots/state-000000200.h5");
  EXPECT_FALSE(snapshot.empty());
  fs::rename(dir_ / "out", dir_ / "first");
  const Result b = run("run " + f.string() + " --threads 2");
  ASSERT_EQ(b.code, 0) << b.err;
  EXPECT_EQ(slurp(dir_ / "out/history/walls.csv"), walls);
  EXPECT_EQ(slurp(dir_ / "out/history/energy.csv"), slurp(dir_ / "first/history/energy.csv"));
}

}  // namespace
