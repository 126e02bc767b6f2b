// Shares of a loop by work (dem/engine/work_split.h), the split of the pair loop and of the body
// update among threads.
#include <gtest/gtest.h>

#include <vector>

#include "dem/engine/work_split.h"

namespace trackbed::dem {
namespace {

std::vector<long long> cumulative(const std::vector<long long>& work) {
  std::vector<long long> c(work.size() + 1, 0);
  for (std::size_t i = 0; i < work.size(); ++i) c[i + 1] = c[i] + work[i];
  return c;
}

TEST(WorkSplit, SharesTheWorkNotTheItems) {
  // Three heavy items (clumps) and six light ones (balls): 27 + 6 units. Half the work (16.5) is
  // nearest done after the second heavy item, so two threads take 2 and 7 items (18 and 15
  // units), where equal shares of the items would give 4 and 5 (28 and 5 units); three threads
  // 9, 9 and 15 units.
  const auto c = cumulative({9, 9, 9, 1, 1, 1, 1, 1, 1});
  EXPECT_EQ(split_by_work(c, 1), (std::vector<int>{0, 9}));
  EXPECT_EQ(split_by_work(c, 2), (std::vector<int>{0, 2, 9}));
  EXPECT_EQ(split_by_work(c, 3), (std::vector<int>{0, 1, 2, 9}));
}

TEST(WorkSplit, MoreThreadsThanItemsLeaveSomeShareEmpty) {
  const std::vector<int> r = split_by_work(cumulative({5, 5, 5}), 5);
  ASSERT_EQ(r.size(), 6u);
  EXPECT_EQ(r.front(), 0);
  EXPECT_EQ(r.back(), 3);
  for (std::size_t t = 0; t + 1 < r.size(); ++t) EXPECT_LE(r[t], r[t + 1]);
  EXPECT_EQ(split_by_work(cumulative({}), 2), (std::vector<int>{0, 0, 0}));
}

}  // namespace
}  // namespace trackbed::dem
