// Contiguous shares of a loop for the threads of a team, of about equal work rather than of
// equal length: the pair loop's rows (NeighborList::balanced_ranges) and the bodies of the body
// update (Simulation::integrate_bodies). A share depends only on the work counts, so it is the
// same from run to run and in a resumed run, and with it the order of every sum.
#pragma once

#include <algorithm>
#include <vector>

namespace trackbed::dem {

// `cumulative[i]`: the work of items 0 .. i-1 (size n + 1, cumulative[0] = 0, non-decreasing).
// Returns parts + 1 boundaries: share t is [r[t], r[t+1]), each inner boundary the item boundary
// nearest to where t / parts of the whole work is done.
inline std::vector<int> split_by_work(const std::vector<long long>& cumulative, int parts) {
  const int n = static_cast<int>(cumulative.size()) - 1;
  std::vector<int> ranges(parts + 1, n);
  ranges[0] = 0;
  for (int t = 1; t < parts; ++t) {
    const long long share = cumulative[n] * t / parts;
    auto at = std::lower_bound(cumulative.begin(), cumulative.end(), share);
    if (at != cumulative.begin() && share - *(at - 1) < *at - share) --at;
    ranges[t] = static_cast<int>(at - cumulative.begin());
  }
  return ranges;
}

}  // namespace trackbed::dem
