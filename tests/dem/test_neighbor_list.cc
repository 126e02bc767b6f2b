// The Verlet neighbour list (dem/engine/neighbor_list.h): the pairs it holds, and the split of its
// rows among threads by work (NeighborList::balanced_ranges).
#include <gtest/gtest.h>

#include <vector>

#include "dem/engine/neighbor_list.h"

namespace trackbed::dem {
namespace {

// A row of balls of radius r along x: the first `dense` spaced 1.9 r (each touching its
// neighbours), then `sparse` spaced 2.6 r (apart, yet within the skin of their neighbours).
Particles row_of_balls(int dense, int sparse, double r) {
  Particles p;
  double x = 0;
  for (int i = 0; i < dense + sparse; ++i) {
    p.add_ball(Vec3(x, 0, 0), r, 0, 2600, i);
    x += (i < dense ? 1.9 : 2.6) * r;
  }
  return p;
}

// Skin 0.8 r: each ball of the row is listed with its next neighbour only (2.6 r < 2 r + skin <
// 3.8 r), touching it in the dense part.
NeighborList list_of(const Particles& p, double r) {
  NeighborList list;
  list.build(p, 0.8 * r, false);
  return list;
}

TEST(NeighborList, HoldsExactlyThePairsWithinTheSkin) {
  const double r = 0.01, skin = 0.8 * r;
  const Particles p = row_of_balls(20, 20, r);
  const NeighborList list = list_of(p, r);
  const int n = p.num_elements();
  int expected = 0;
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j) {
      const bool near = (p.pos[j] - p.pos[i]).norm() < p.radius[i] + p.radius[j] + skin;
      expected += near;
      EXPECT_EQ(list.find(i, j) >= 0, near) << i << " " << j;
    }
  EXPECT_EQ(list.num_pairs(), expected);
}

// The rows split so that each thread has about the same work: a pair in contact counts
// kTouchingPairWork, a pair apart 1, a row 1 more; a range's work is within one row's of the
// mean, so the dense part of the row (rows of work 1 + 8, against 1 + 1) gets fewer rows.
TEST(NeighborList, BalancedRangesShareTheWorkNotTheRows) {
  const double r = 0.01;
  const Particles p = row_of_balls(60, 60, r);
  const NeighborList list = list_of(p, r);
  const int n = p.num_elements();
  std::vector<long long> row(n, 1);  // the work the split is to share, counted here by hand
  for (int i = 0; i < n; ++i)
    for (int k = list.offsets[i]; k < list.offsets[i + 1]; ++k) {
      const int j = list.partners[k];
      const bool touching = (p.pos[j] - p.pos[i]).norm() < p.radius[i] + p.radius[j];
      row[i] += touching ? NeighborList::kTouchingPairWork : 1;
    }
  long long total = 0, largest_row = 0;
  for (long long w : row) total += w, largest_row = std::max(largest_row, w);

  EXPECT_EQ(list.balanced_ranges(p.pos, p.radius, 1), (std::vector<int>{0, n}));
  for (int parts : {2, 3, 7}) {
    const std::vector<int> ranges = list.balanced_ranges(p.pos, p.radius, parts);
    ASSERT_EQ(static_cast<int>(ranges.size()), parts + 1);
    EXPECT_EQ(ranges.front(), 0);
    EXPECT_EQ(ranges.back(), n);
    for (int t = 0; t < parts; ++t) {
      ASSERT_LE(ranges[t], ranges[t + 1]);
      long long work = 0;
      for (int i = ranges[t]; i < ranges[t + 1]; ++i) work += row[i];
      EXPECT_NEAR(static_cast<double>(work), static_cast<double>(total) / parts, largest_row)
          << parts << " parts, range " << t;
    }
  }
  // Two threads: the dense first half (60 touching rows) is more than half the work.
  EXPECT_LT(list.balanced_ranges(p.pos, p.radius, 2)[1], 45);
}

}  // namespace
}  // namespace trackbed::dem
