// The pilot zone: the ballast a pilot run saw move. From the pilot's snapshots, the bodies that had
// moved more than a threshold when the sleeper (the run's first mesh body) had moved a given
// distance, each as a sphere at its start position holding the whole body, dilated
// (docs/zones.md#pilot-zones).
#pragma once

#include <array>
#include <string>
#include <utility>
#include <vector>

#include "dem/samples/zone.h"

namespace trackbed::dem {

// A union of spheres with point membership in a few sphere tests: a uniform grid of cells one
// largest radius wide over the spheres' box, each sphere listed in every cell its box overlaps.
class SphereUnion {
 public:
  struct Sphere {
    Vec3 centre;
    double radius;  // >= 0
  };
  explicit SphereUnion(std::vector<Sphere> spheres);
  bool contains(const Vec3& x) const;  // closed: |x - c| <= r for some sphere
  const std::vector<Sphere>& spheres() const { return spheres_; }
  const Bounds& bounds() const { return box_; }

  // A grid is never given more cells than this times the number of spheres (plus one): spheres
  // spread far apart get larger cells instead of an empty grid of millions of cells.
  static constexpr long kCellsPerSphere = 64;

 private:
  std::vector<Sphere> spheres_;
  Bounds box_;
  double cell_ = 1;
  std::array<long, 3> dims_{{0, 0, 0}};
  std::vector<int> offsets_;  // CSR: spheres of cell c are items_[offsets_[c], offsets_[c + 1])
  std::vector<int> items_;
};

// The snapshot files a pilot() path names: for a folder, its state-*.h5 files, or those of its
// snapshots/ subfolder when it has one; for a path whose last component has '*' or '?', the
// files of its folder that match. Sorted by name. Throws InputError when there are none.
std::vector<std::string> pilot_snapshot_files(const std::string& path);

class PilotZone final : public Zone {
 public:
  // Reads `files` (in any order; they are put in step order, the first is the reference) and
  // selects the bodies. `path` is what pilot() was given, resolved, for to_string(). Throws
  // InputError for fewer than two snapshots, no mesh body, bodies that do not match between
  // snapshots, a sleeper that never moves sleeper_displacement (naming the largest it reached),
  // or sleeper_displacement not > 0, threshold or dilation not >= 0.
  PilotZone(const std::string& path, const std::vector<std::string>& files,
            double sleeper_displacement, double threshold, double dilation);

  bool contains(const Vec3& x) const override { return spheres_.contains(x); }
  std::optional<Bounds> bounds() const override { return spheres_.bounds(); }
  void print(std::string& out) const override;
  void collect_pilot_summaries(std::vector<PilotSummary>& out) const override {
    out.push_back(summary_);
  }

  const PilotSummary& summary() const { return summary_; }
  const SphereUnion& spheres() const { return spheres_; }

 private:
  PilotZone(const std::string& path, double sleeper_displacement, double threshold, double dilation,
            std::pair<SphereUnion, PilotSummary> selection);

  std::string path_;
  double sleeper_displacement_, threshold_, dilation_;
  SphereUnion spheres_;
  PilotSummary summary_;
};

}  // namespace trackbed::dem
