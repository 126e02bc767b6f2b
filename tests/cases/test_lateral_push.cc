// The scaled-down lateral push (cases/lateral_push/small/) of the five models as a user runs it
// (study_fixture.h): each summary checked against the physics that holds at any size (the sleeper
// carries its weight, its parts carry its resistance, it moved 5 mm) and against stored reference
// figures (tests/cases/reference/lateral_push_small.csv), and the five peaks against one another.
#include <cmath>

#include "dem/io/csv_table.h"
#include "study_fixture.h"

namespace {

class LateralPush : public Study {
 protected:
  LateralPush()
      : Study("lateral_push", "small-section",
              {{"all-clump", "small-section-all-clump"},
               {"half-by-height", "small-section-half-by-height"},
               {"optimised", "small-section-optimised"},
               {"all-ball-rolling", "small-section"},
               {"all-ball", "small-section"}}) {}

  // Runs the shipped small case of `model` (drawing its pictures with `plot`) and checks what must
  // hold.
  void push(const std::string& model, bool plot = false) {
    const fs::path out = run_model(model, plot);
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
    // Where the sleeper rests when the push starts (after the case's hold), and no base contact
    // carries more than the base.
    expect_sleeper_on_its_base(out, "start_");
    EXPECT_LE(summary_number(out, "start_largest_base_contact_share"),
              summary_number(out, "start_base_load_share") + 1e-12);
    check_reference_of(model);
  }

  // A bed that does not flow under the sleeper passes the push on to its base: what local damping
  // and inertia take from the moving stones is a small part. Measured at 2 mm: balls with rolling
  // resistance 0.91, the clumps with it 0.87; the clumps without it (Table 2), which flow, 0.60
  // (docs/validation.md, "What makes the clump bed's resistance depend on the velocity").
  void expect_bed_carries_push(const fs::path& out) {
    EXPECT_GT(summary_number(out, "walls_lateral_force_at_2mm_n"),
              0.8 * summary_number(out, "lateral_force_at_2mm_n"));
  }
};

TEST_F(LateralPush, BallSample) {
  build_base_sample();
}
TEST_F(LateralPush, AllClumpSample) {
  build_converted_sample("small-section-all-clump");
}
// The optimised model's zone is where the reference push (all clumps) moved its stones.
TEST_F(LateralPush, OptimisedSample) {
  build_converted_sample("small-section-optimised", "all-clump");
}
TEST_F(LateralPush, HalfByHeightSample) {
  build_converted_sample("small-section-half-by-height");
}

TEST_F(LateralPush, AllClump) {
  push("all-clump");
  expect_bed_carries_push(results("all-clump"));
}
TEST_F(LateralPush, HalfByHeight) {
  push("half-by-height");
}
TEST_F(LateralPush, Optimised) {
  push("optimised");
}
// With it, the pictures a user opens first, drawn by the run as a user's run draws them (the other
// study runs skip them): the scripts read a real results folder (Debian's python3 with
// python3-matplotlib, scripts/install-deps).
TEST_F(LateralPush, AllBallRolling) {
  push("all-ball-rolling", true);
  const fs::path out = results("all-ball-rolling");
  for (const char* png : {"plot.png", "push.png", "force_chains.png", "displacement.png"})
    EXPECT_TRUE(fs::exists(out / png)) << png;
  expect_bed_carries_push(out);
}
TEST_F(LateralPush, AllBall) {
  push("all-ball");
}

// The resistance at zero displacement: push.csv's first row, the push's start.
double start_resistance(const fs::path& run) {
  return trackbed::dem::CsvTable((run / "push.csv").string()).number(0, "resistance_n");
}

// Held still along the push (as shipped), the sleeper starts the push under the net lateral load
// the seating left on it; free along it during the hold, it comes to rest where that load
// vanishes and the push starts from zero: at rest the load is its mass times an acceleration that
// the hold's equilibrium makes small. 1 % of its weight (2.4 N) separates the two by far (held:
// 27 N, 11 % of the weight; free: measured below 0.1 N).
TEST_F(LateralPush, FreeHold) {
  const fs::path free =
      run_model("all-ball-rolling", false,
                {"all-ball-rolling-free-hold",
                 "subsection push test\n  set hold along the push = free\nend\n"});
  const double weight = 24.32 * 9.81;  // N: the small sleeper (small/section.prm)
  EXPECT_GT(std::abs(start_resistance(results("all-ball-rolling"))), 0.05 * weight);
  EXPECT_LT(std::abs(start_resistance(free)), 0.01 * weight);
  EXPECT_NEAR(summary_number(free, "push_distance_m"), 0.005, 1e-6);
  EXPECT_NEAR(summary_number(free, "mean_vertical_load_over_weight"), 1.0, 0.02);
}

// The paper's ordering of the peaks (the paper, Table 3) where it holds on the small bed with a
// margin beyond the scatter between realisations of its samples (the reference's peak moved 11 %
// between two, docs/validation.md#scaled-down-variant). Measured with the clumps' rolling
// friction on samples whose conversions settled at the damped critical step (2026-12-07), as
// ratios to the reference: balls with rolling resistance 1.07 (the paper 1.33; 1.27 on the
// samples settled at the undamped step), the optimised model 0.68 (0.93; 0.89 before), balls
// without rolling resistance 0.26 (0.31); both multi-layer models above the balls without. And
// the costs (sphere-steps: deterministic, unlike wall time): the optimised model cheaper than
// half by height, cheaper than the reference. Not asserted: half by height below the reference
// (0.93 here, 1.10 before), the optimised model within 10 % of the reference (at full size 0.87,
// 0.94 and 0.98 in three realisations) and at under a quarter of its cost (0.25-0.26 of its
// sphere-steps at full size).
TEST_F(LateralPush, FiveModelsPeaks) {
  std::map<std::string, double> peak, cost;
  for (const auto& [model, unused] : sample_of()) {
    peak[model] = summary_number(results(model), "peak_lateral_force_n");
    cost[model] =
        summary_number(results(model), "elements") * summary_number(results(model), "steps");
  }
  const double reference = peak["all-clump"];
  EXPECT_GT(peak["all-ball-rolling"], reference);
  EXPECT_GT(reference, peak["optimised"]);
  EXPECT_GT(peak["optimised"], peak["all-ball"]);
  EXPECT_GT(peak["half-by-height"], peak["all-ball"]);
  EXPECT_LT(peak["all-ball"], 0.6 * reference);
  EXPECT_LT(cost["optimised"], cost["half-by-height"]);
  EXPECT_LT(cost["half-by-height"], cost["all-clump"]);
}

}  // namespace
