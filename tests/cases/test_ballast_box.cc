// The scaled-down ballast box test (cases/ballast_box/small/) of the three shapes as a user runs
// it (study_fixture.h): each summary checked against what holds at any size (the wedge travelled
// its path and came back to its start, the energy balance closes, compaction meets more
// resistance than lifting) and against stored reference figures
// (tests/cases/reference/ballast_box_small.csv), and the shapes' contacts against one another as
// the paper's Table 1 has them.
#include "study_fixture.h"

namespace {

class BallastBox : public Study {
 protected:
  BallastBox()
      : Study("ballast_box", "small-ballast-box",
              {{"ball", "small-ballast-box"},
               {"clump-D120R0.5", "small-ballast-box-D120R0.5"},
               {"clump-D130R0.4", "small-ballast-box-D130R0.4"}}) {}

  // Runs the shipped small case of `model` and checks what must hold.
  void test(const std::string& model) {
    const fs::path out = run_model(model);
    // The wedge travelled up 2.4 mm, down 4.8 mm, up 2.4 mm, and stands at its start: each leg
    // ends on its point exactly, up to the rounding of its position (1e-16 m).
    EXPECT_NEAR(summary_number(out, "push_path_m"), 0.0096, 1e-12);
    EXPECT_NEAR(summary_number(out, "push_distance_m"), 0.0, 1e-12);
    // Energy: the work of the driven wedge, of gravity and of the walls is what the bed stores
    // and dissipates; the tally's step error is measured at 4.8e-5 to 2.9e-4 on these runs.
    EXPECT_LT(std::abs(summary_number(out, "energy_balance_error")), 2e-3);
    // Pressing into the bed meets more resistance than lifting the stones beside the wedge.
    EXPECT_GT(summary_number(out, "peak_reverse_vertical_force_n"),
              summary_number(out, "peak_vertical_force_n"));
    check_reference_of(model);
  }
};

TEST_F(BallastBox, BallSample) {
  build_base_sample();
}
TEST_F(BallastBox, D120R05Sample) {
  build_converted_sample("small-ballast-box-D120R0.5");
}
TEST_F(BallastBox, D130R04Sample) {
  build_converted_sample("small-ballast-box-D130R0.4");
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
// the small bed has x1.27 and x1.28 (docs/validation.md). Its largest contact forces (particle-
// particle: the balls' 0.41 kN, the clumps' 0.25 and 0.91 kN) are checked against the references
// only: docs/validation.md says why they differ from the paper's.
TEST_F(BallastBox, ThreeShapes) {
  const double ball = summary_number(results("ball"), "contacts");
  for (const std::string clump : {"clump-D120R0.5", "clump-D130R0.4"})
    EXPECT_GT(summary_number(results(clump), "contacts"), 1.15 * ball) << clump;
}

}  // namespace
