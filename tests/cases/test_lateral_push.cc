// The scaled-down lateral push (cases/lateral_push/small/) of the five models as a user runs it:
// the samples built by build-sample from the shipped sample files, the five shipped cases run on
// them, each summary checked against the physics that holds at any size (the sleeper carries its
// weight, its parts carry its resistance, it moved 5 mm) and against stored reference figures
// (tests/cases/reference/lateral_push_small.csv), and the five peaks against one another.
// ctest runs each test alone, in the order its fixtures give (tests/cases/CMakeLists.txt): the
// samples and runs are kept in TRACKBED_STUDY_WORK for the tests that follow.
#include <map>

#include "cli_fixture.h"

namespace {

const fs::path kWork = TRACKBED_STUDY_WORK;
const std::string kSource = TRACKBED_SOURCE_DIR;

// model -> sample it runs on
const std::map<std::string, std::string> kSampleOf = {
    {"all-clump", "small-section-all-clump"},
    {"half-by-height", "small-section-half-by-height"},
    {"optimised", "small-section-optimised"},
    {"all-ball-rolling", "small-section"},
    {"all-ball", "small-section"},
};

class LateralPush : public Cli {
 protected:
  fs::path sample(const std::string& name) { return kWork / "samples" / name; }
  fs::path results(const std::string& model) { return kWork / "runs" / model; }

  // The shipped zone sample file on the ball sample of kWork (file values are relative to the
  // case that is run, so the included file's base sample and templates are given again).
  void build_zone_sample(const std::string& zone) {
    const std::string name = "small-section-" + zone;
    const Result r = run_including(
        "build-sample", kSource + "/cases/samples/" + name + ".prm",
        "subsection zone\n  set base sample = " + (sample("small-section") / "sample.h5").string() +
            "\n  set templates = " + kSource +
            "/cases/templates/ballast/library.csv\nend\n"
            "subsection output\n  set plot = false\n  set vtu = false\nend\n",
        sample(name));
    ASSERT_EQ(r.code, 0) << r.out << r.err;
  }

  // Runs the shipped small case of `model` on the samples of kWork and checks what must hold.
  void push(const std::string& model) {
    const Result r = run_including("run", kSource + "/cases/lateral_push/small/" + model + ".prm",
                                   "subsection particles\n  set sample file = " +
                                       (sample(kSampleOf.at(model)) / "sample.h5").string() +
                                       "\nend\nsubsection output\n  set plot = false\nend\n",
                                   results(model));
    ASSERT_EQ(r.code, 0) << r.out << r.err;
    const fs::path out = results(model);
    ASSERT_TRUE(fs::exists(out / "push.csv"));
    EXPECT_NE(slurp(out / "summary.json").find("\"status\": \"finished\""), std::string::npos);

    // The sleeper moved the full 5 mm (to within a step's travel, v dt = 6e-8 m).
    EXPECT_NEAR(summary_number(out, "push_distance_m"), 0.005, 1e-6);
    // The sleeper, free vertically, carried its weight: over the push the mean vertical contact
    // load is the weight up to the change of its vertical momentum (measured 1.0001 on the ball
    // model); 2 % allows for a sleeper still sinking into a creeping bed.
    EXPECT_NEAR(summary_number(out, "mean_vertical_load_over_weight"), 1.0, 0.02);
    // The sleeper's parts carry all of its resistance (the top touches no stone).
    const double shares = summary_number(out, "share_base") + summary_number(out, "share_sides") +
                          summary_number(out, "share_ends") + summary_number(out, "share_top");
    EXPECT_NEAR(shares, 1.0, 1e-9);
    EXPECT_GT(summary_number(out, "share_base"), 0.0);
    EXPECT_GT(summary_number(out, "peak_lateral_force_n"), 0.0);

    check_reference(kSource + "/tests/cases/reference/lateral_push_small.csv", model, out);
  }
};

TEST_F(LateralPush, BallSample) {
  const Result r = run("build-sample " + kSource +
                       "/cases/samples/small-section.prm --threads 1 "
                       "--output " +
                       sample("small-section").string());
  ASSERT_EQ(r.code, 0) << r.out << r.err;
}
TEST_F(LateralPush, AllClumpSample) {
  build_zone_sample("all-clump");
}
TEST_F(LateralPush, OptimisedSample) {
  build_zone_sample("optimised");
}
TEST_F(LateralPush, HalfByHeightSample) {
  build_zone_sample("half-by-height");
}

TEST_F(LateralPush, AllClump) {
  push("all-clump");
}
TEST_F(LateralPush, HalfByHeight) {
  push("half-by-height");
}
TEST_F(LateralPush, Optimised) {
  push("optimised");
}
TEST_F(LateralPush, AllBallRolling) {
  push("all-ball-rolling");
}
TEST_F(LateralPush, AllBall) {
  push("all-ball");
}

// The paper's findings (seed-facts.md, Table 3) as they hold on the small bed (docs/validation.md):
// balls without rolling resistance far below the all-clump reference, balls with it above, the
// optimised model near it at a fraction of its cost (sphere-steps: deterministic, unlike wall
// time). "Near" is 20 %, not the paper's 10 %: this bed's peak scatters by about 13 % between
// equivalent runs. The half-by-height model is left out: at this scale its clump layer under the
// sleeper (80 mm x 0.4) is one stone thick.
TEST_F(LateralPush, FiveModelsPeaks) {
  std::map<std::string, double> peak, cost;
  for (const auto& [model, unused] : kSampleOf) {
    peak[model] = summary_number(results(model), "peak_lateral_force_n");
    cost[model] =
        summary_number(results(model), "elements") * summary_number(results(model), "steps");
  }
  const double reference = peak["all-clump"];
  EXPECT_LT(peak["all-ball"], 0.6 * reference);
  EXPECT_GT(peak["all-ball-rolling"], reference);
  EXPECT_NEAR(peak["optimised"] / reference, 1.0, 0.2);
  EXPECT_LT(cost["optimised"], 0.25 * cost["all-clump"]);
}

}  // namespace
