// Verlet neighbour list of sphere elements, built with a cell list.
//
// Holds every pair (i, j), i < j, of elements of different bodies whose surfaces are closer than
// the skin: |x_i - x_j| < r_i + r_j + skin. Stored as CSR by i with partners sorted ascending, so
// the list (and the contact history that is aligned with it) is the same whatever the number of
// threads. Rebuilt when some element has moved more than skin/2 since the last build; then no
// pair can have come into contact unseen (two elements close at most 2 * skin/2 = skin).
#pragma once

#include <vector>

#include "dem/engine/particles.h"

namespace trackbed::dem {

class NeighborList {
 public:
  // With `parallel` false the build runs on the calling thread only.
  void build(const Particles& p, double skin, bool parallel = true);

  int num_pairs() const { return static_cast<int>(partners.size()); }
  // The index of pair (i, j) in `partners`, or -1. Binary search; for tests and remapping.
  int find(int i, int j) const;
  // Splits the rows (elements i) into `parts` contiguous ranges of about equal force work:
  // returns parts + 1 boundaries, range t = [r[t], r[t+1]). A row's work is 1 and 1 for each of
  // its pairs, kTouchingPairWork for a pair in contact at `pos`/`radius` (docs/theory.md, "The
  // loops are shared by work"). A function of the list and the positions only, so the
  // partition, and the order of every force sum, is the same in a resumed run.
  std::vector<int> balanced_ranges(const std::vector<Vec3>& pos, const std::vector<double>& radius,
                                   int parts) const;
  static constexpr int kTouchingPairWork = 8;

  std::vector<int> offsets;   // size num_elements + 1
  std::vector<int> partners;  // j of each pair
};

// Uniform grid of cells over the elements' bounding box (counting sort), shared by the pair search
// and the wall candidate search.
class CellGrid {
 public:
  // Cells are at least `min_cell` wide; the number of cells is capped near the element count.
  void build(const std::vector<Vec3>& points, double min_cell);
  // Cell coordinates of a point, clamped to the grid.
  void cell_of(const Vec3& x, int& ix, int& iy, int& iz) const;
  int index(int ix, int iy, int iz) const { return (iz * ny_ + iy) * nx_ + ix; }
  int nx() const { return nx_; }
  int ny() const { return ny_; }
  int nz() const { return nz_; }
  // Points of cell c: sorted_[start_[c] .. start_[c+1]).
  const int* begin(int c) const { return sorted_.data() + start_[c]; }
  const int* end(int c) const { return sorted_.data() + start_[c + 1]; }

 private:
  Vec3 lower_ = Vec3::Zero();
  double inv_cell_ = 1;
  int nx_ = 1, ny_ = 1, nz_ = 1;
  std::vector<int> start_, sorted_;
};

}  // namespace trackbed::dem
