// The scaled-down ballast box test (cases/ballast_box/small/) of the three shapes as a user runs
// it: the samples built by build-sample from the shipped sample files, the three shipped cases run
// on them, each summary checked against what holds at any size (the wedge travelled its path and
// came back to its start, the energy balance closes, compaction meets more resistance than
// lifting) and against stored reference figures (tests/cases/reference/ballast_box_small.csv), and
// the shapes' contacts against one another as the paper's Table 1 has them.
// ctest runs each test alone, in the order its fixtures give (tests/cases/CMakeLists.txt): the
// samples and runs are kept in TRACKBED_STUDY_WORK for the tests that follow.
#include <map>

#include "cli_fixture.h"

namespace {

const fs::path kWork = TRACKBED_STUDY_WORK;
const std::string kSource = TRACKBED_SOURCE_DIR;

// model -> sample it runs on
const std::map<std::string, std::string> kSampleOf = {
    {"ball", "small-ballast-box"},
    {"clump-D120R0.5", "small-ballast-box-D120R0.5"},
    {"clump-D130R0.4", "small-ballast-box-D130R0.4"},
};

class BallastBox : public Cli {
 protected:
  fs::path sample(const std::string& name) { return kWork / "samples" / name; }
  fs::path results(const std::string& model) { return kWork / "runs" / model; }

  // The shipped clump sample file on the ball sample of kWork (file values are relative to the
  // case that is run, so the included file's base sample and templates are given again).
  void build_clump_sample(const std::string& setting) {
    const std::string name = "small-ballast-box-" + setting;
    const Result r =
        run_including("build-sample", kSource + "/cases/samples/" + name + ".prm",
                      "subsection zone\n  set base sample = " +
                          (sample("small-ballast-box") / "sample.h5").string() +
                          "\n  set templates = " + kSource +
                          "/cases/templates/ballast/library.csv\nend\n"
                          "subsection output\n  set plot = false\n  set vtu = false\nend\n",
                      sample(name));
    ASSERT_EQ(r.code, 0) << r.out << r.err;
  }

  // Runs the shipped small case of `model` on the samples of kWork and checks what must hold.
  void test(const std::string& model) {
    const Result r = run_including("run", kSource + "/cases/ballast_box/small/" + model + ".prm",
                                   "subsection particles\n  set sample file = " +
                                       (sample(kSampleOf.at(model)) / "sample.h5").string() +
                                       "\nend\nsubsection output\n  set plot = false\nend\n",
                                   results(model));
    ASSERT_EQ(r.code, 0) << r.out << r.err;
    const fs::path out = results(model);
    ASSERT_TRUE(fs::exists(out / "push.csv"));
    EXPECT_NE(slurp(out / "summary.json").find("\"status\": \"finished\""), std::string::npos);

    // The wedge travelled up 2.4 mm, down 4.8 mm, up 2.4 mm, and stands at its start: each leg
    // ends on its point exactly, up to the rounding of its position (1e-16 m).
    EXPECT_NEAR(summary_number(out, "push_path_m"), 0.0096, 1e-12);
    EXPECT_NEAR(summary_number(out, "push_distance_m"), 0.0, 1e-12);
    // Energy: the work of the driven wedge, of gravity and of the walls is what the bed stores
    // and dissipates; the tally's step error is measured at 8e-5 to 3.2e-4 on these runs.
    EXPECT_LT(std::abs(summary_number(out, "energy_balance_error")), 2e-3);
    // Pressing into the bed meets more resistance than lifting the stones beside the wedge.
    EXPECT_GT(summary_number(out, "peak_reverse_vertical_force_n"),
              summary_number(out, "peak_vertical_force_n"));

    check_reference(kSource + "/tests/cases/reference/ballast_box_small.csv", model, out);
  }
};

TEST_F(BallastBox, BallSample) {
  const Result r =
      run("build-sample " + kSource + "/cases/samples/small-ballast-box.prm --threads 1 --output " +
          sample("small-ballast-box").string());
  ASSERT_EQ(r.code, 0) << r.out << r.err;
}
TEST_F(BallastBox, D120R05Sample) {
  build_clump_sample("D120R0.5");
}
TEST_F(BallastBox, D130R04Sample) {
  build_clump_sample("D130R0.4");
}

TEST_F(BallastBox, Ball) {
  test("ball");
}
TEST_F(BallastBox, ClumpD120R05) {
  test("clump-D120R0.5");
}
TEST_F(BallastBox, ClumpD130R04) {
  test("clump-D130R0.4");
}

// Table 1's finding on contacts: the clumps' bed has more contacts than the balls' (the paper:
// 11,573 and 10,536 against 5,991, x1.9), since a clump touches a neighbour at several pebbles;
// the small bed has x1.26 and x1.29 (docs/validation.md). Its largest contact forces are the
// other way round (the balls' 0.4 kN against the clumps' 0.09-0.18 kN) and are checked against the
// references only: docs/validation.md says why they differ from the paper's.
TEST_F(BallastBox, ThreeShapes) {
  const double ball = summary_number(results("ball"), "contacts");
  for (const std::string clump : {"clump-D120R0.5", "clump-D130R0.4"})
    EXPECT_GT(summary_number(results(clump), "contacts"), 1.15 * ball) << clump;
}

}  // namespace
