#include "dem/samples/pilot_zone.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numeric>
#include <tuple>
#include <unordered_map>

#include "common/input_error.h"
#include "common/number_text.h"
#include "dem/io/snapshot.h"

namespace trackbed::dem {

namespace fs = std::filesystem;

namespace {

// Shell-style match of a file name: '*' any run of characters, '?' one character.
bool name_matches(const std::string& name, const std::string& pattern) {
  std::size_t n = 0, p = 0, star = std::string::npos, resume = 0;
  while (n < name.size()) {
    if (p < pattern.size() && pattern[p] == '*') {
      star = p++, resume = n;
    } else if (p < pattern.size() && (pattern[p] == '?' || pattern[p] == name[n])) {
      ++n, ++p;
    } else if (star != std::string::npos) {
      p = star + 1, n = ++resume;
    } else {
      return false;
    }
  }
  while (p < pattern.size() && pattern[p] == '*') ++p;
  return p == pattern.size();
}

void check_parameters(double sleeper_displacement, double threshold, double dilation) {
  if (!(sleeper_displacement > 0) || !std::isfinite(sleeper_displacement))
    throw InputError("sleeper displacement " + exact_number_text(sleeper_displacement) +
                     " m; valid: a finite distance > 0 (m)");
  if (!(threshold >= 0) || !std::isfinite(threshold))
    throw InputError("threshold " + exact_number_text(threshold) +
                     " m; valid: a finite distance >= 0 (m)");
  if (!(dilation >= 0) || !std::isfinite(dilation))
    throw InputError("dilation " + exact_number_text(dilation) +
                     " m; valid: a finite distance >= 0 (m)");
}

// The reference snapshot's index of every body id.
std::unordered_map<std::int64_t, std::size_t> index_by_id(const SnapshotBodies& s,
                                                          const std::string& file) {
  std::unordered_map<std::int64_t, std::size_t> index;
  for (std::size_t b = 0; b < s.id.size(); ++b)
    if (!index.emplace(s.id[b], b).second)
      throw InputError(file + ": body id " + std::to_string(s.id[b]) +
                       " appears twice; valid: a trackbed snapshot (ids are unique)");
  return index;
}

const Vec3& sleeper_position(const SnapshotBodies& s, const std::string& file) {
  if (s.mesh_position.empty())
    throw InputError(file +
                     ": the snapshot has no mesh body; valid: a pilot run whose first "
                     "mesh body is the sleeper");
  return s.mesh_position[0];
}

std::pair<SphereUnion, PilotSummary> select_moved_bodies(const std::vector<std::string>& files,
                                                         double sleeper_displacement,
                                                         double threshold, double dilation) {
  check_parameters(sleeper_displacement, threshold, dilation);
  if (files.size() < 2)
    throw InputError(std::to_string(files.size()) +
                     " snapshot(s) found; valid: at least two (the first, in step order, is the "
                     "reference; a push test writes one where the push starts when its "
                     "output/snapshot interval is above 0)");
  std::vector<SnapshotClock> clocks;
  for (const auto& f : files) clocks.push_back(read_snapshot_clock(f));
  std::vector<std::size_t> order(files.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return std::tie(clocks[a].step, files[a]) < std::tie(clocks[b].step, files[b]);
  });

  const std::string& reference_file = files[order[0]];
  const SnapshotBodies reference = read_snapshot_bodies(reference_file);
  const Vec3 sleeper_start = sleeper_position(reference, reference_file);
  const auto index = index_by_id(reference, reference_file);

  double farthest = 0;
  std::string farthest_file = reference_file;
  for (std::size_t k = 1; k < order.size(); ++k) {
    const std::string& file = files[order[k]];
    const SnapshotBodies now = read_snapshot_bodies(file);
    const double moved = (sleeper_position(now, file) - sleeper_start).norm();
    if (moved > farthest) farthest = moved, farthest_file = file;
    if (moved < sleeper_displacement) continue;

    if (now.id.size() != reference.id.size())
      throw InputError(file + ": " + std::to_string(now.id.size()) + " bodies, the reference " +
                       reference_file + " has " + std::to_string(reference.id.size()) +
                       "; valid: snapshots of one run");
    std::vector<SphereUnion::Sphere> spheres;
    for (std::size_t b = 0; b < now.id.size(); ++b) {
      const auto found = index.find(now.id[b]);
      if (found == index.end())
        throw InputError(file + ": body id " + std::to_string(now.id[b]) +
                         " is not in the reference " + reference_file +
                         "; valid: snapshots of one run");
      const std::size_t r = found->second;
      if ((now.position[b] - reference.position[r]).norm() > threshold)
        spheres.push_back({reference.position[r], reference.bounding_radius[r] + dilation});
    }
    PilotSummary summary;
    summary.snapshot = file;
    summary.step = now.step;
    summary.time = now.time;
    summary.sleeper_displacement = moved;
    summary.selected_bodies = static_cast<int>(spheres.size());
    summary.total_bodies = static_cast<int>(now.id.size());
    return {SphereUnion(std::move(spheres)), summary};
  }
  throw InputError("the sleeper (first mesh body) moved at most " + exact_number_text(farthest) +
                   " m (in " + farthest_file + ") over the " + std::to_string(files.size()) +
                   " snapshots; valid: a sleeper displacement up to " +
                   exact_number_text(farthest) +
                   " m, or a pilot run that pushes the sleeper further");
}

}  // namespace

SphereUnion::SphereUnion(std::vector<Sphere> spheres) : spheres_(std::move(spheres)) {
  if (spheres_.empty()) return;
  double largest = 0;
  for (const auto& s : spheres_) {
    box_.extend(s.centre - Vec3::Constant(s.radius));
    box_.extend(s.centre + Vec3::Constant(s.radius));
    largest = std::max(largest, s.radius);
  }
  const Vec3 extent = box_.sizes();
  const double max_cells = static_cast<double>(kCellsPerSphere) * spheres_.size() + 1;
  cell_ = largest > 0 ? largest : 1.0;  // spheres of radius 0 are points: any cell will do
  auto cells_along = [&](int k) { return std::max(1.0, std::ceil(extent[k] / cell_)); };
  while (cells_along(0) * cells_along(1) * cells_along(2) > max_cells) cell_ *= 2;
  for (int k = 0; k < 3; ++k) dims_[k] = static_cast<long>(cells_along(k));

  auto cell_of = [&](const Vec3& x, int k) {
    const long c = static_cast<long>(std::floor((x[k] - box_.min()[k]) / cell_));
    return std::clamp(c, 0L, dims_[k] - 1);
  };
  // Two passes over the spheres' cell ranges: count, then fill (compressed sparse rows).
  offsets_.assign(dims_[0] * dims_[1] * dims_[2] + 1, 0);
  for (int pass = 0; pass < 2; ++pass) {
    std::vector<int> next;
    if (pass == 1) {
      std::partial_sum(offsets_.begin(), offsets_.end(), offsets_.begin());
      items_.resize(offsets_.back());
      next.assign(offsets_.begin(), offsets_.end() - 1);
    }
    for (int s = 0; s < static_cast<int>(spheres_.size()); ++s) {
      const Vec3 lo = spheres_[s].centre - Vec3::Constant(spheres_[s].radius);
      const Vec3 hi = spheres_[s].centre + Vec3::Constant(spheres_[s].radius);
      for (long i = cell_of(lo, 0); i <= cell_of(hi, 0); ++i)
        for (long j = cell_of(lo, 1); j <= cell_of(hi, 1); ++j)
          for (long k = cell_of(lo, 2); k <= cell_of(hi, 2); ++k) {
            const long c = (i * dims_[1] + j) * dims_[2] + k;
            if (pass == 0)
              ++offsets_[c + 1];
            else
              items_[next[c]++] = s;
          }
    }
  }
}

bool SphereUnion::contains(const Vec3& x) const {
  if (spheres_.empty() || !box_.contains(x)) return false;
  long c = 0;
  for (int k = 0; k < 3; ++k) {
    const long i = static_cast<long>(std::floor((x[k] - box_.min()[k]) / cell_));
    c = c * dims_[k] + std::clamp(i, 0L, dims_[k] - 1);
  }
  for (int i = offsets_[c]; i < offsets_[c + 1]; ++i) {
    const Sphere& s = spheres_[items_[i]];
    if ((x - s.centre).squaredNorm() <= s.radius * s.radius) return true;
  }
  return false;
}

std::vector<std::string> pilot_snapshot_files(const std::string& path) {
  const fs::path p(path);
  const std::string name = p.filename().string();
  fs::path folder;
  std::string pattern;
  if (fs::is_directory(p)) {
    folder = fs::is_directory(p / "snapshots") ? p / "snapshots" : p;
    pattern = "state-*.h5";
  } else if (name.find_first_of("*?") != std::string::npos) {
    folder = p.has_parent_path() ? p.parent_path() : fs::path(".");
    pattern = name;
    if (!fs::is_directory(folder))
      throw InputError(folder.string() +
                       ": no such folder; valid: a folder holding the pilot "
                       "run's snapshots");
  } else if (fs::is_regular_file(p)) {
    return {path};
  } else {
    throw InputError(path +
                     ": no such folder or file; valid: a pilot run's results folder, its "
                     "snapshots folder, or a pattern such as run/snapshots/state-*.h5");
  }
  std::vector<std::string> files;
  for (const auto& entry : fs::directory_iterator(folder))
    if (entry.is_regular_file() && name_matches(entry.path().filename().string(), pattern))
      files.push_back(entry.path().string());
  std::sort(files.begin(), files.end());
  if (files.empty())
    throw InputError(folder.string() + ": no snapshot files " + pattern +
                     "; valid: a pilot run's results folder, its snapshots folder, or a pattern "
                     "such as run/snapshots/state-*.h5");
  return files;
}

PilotZone::PilotZone(const std::string& path, const std::vector<std::string>& files,
                     double sleeper_displacement, double threshold, double dilation)
    : PilotZone(path, sleeper_displacement, threshold, dilation,
                select_moved_bodies(files, sleeper_displacement, threshold, dilation)) {}

PilotZone::PilotZone(const std::string& path, double sleeper_displacement, double threshold,
                     double dilation, std::pair<SphereUnion, PilotSummary> selection)
    : path_(path),
      sleeper_displacement_(sleeper_displacement),
      threshold_(threshold),
      dilation_(dilation),
      spheres_(std::move(selection.first)),
      summary_(std::move(selection.second)) {}

void PilotZone::print(std::string& out) const {
  out += "pilot(\"" + path_ + "\", " + exact_number_text(sleeper_displacement_) + ", " +
         exact_number_text(threshold_) + ", " + exact_number_text(dilation_) + ")";
}

}  // namespace trackbed::dem
