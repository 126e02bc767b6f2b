#include "cases/runs/sample_checkpoint.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>

#include "common/input_error.h"
#include "common/number_text.h"
#include "dem/io/hdf5_io.h"

namespace trackbed::cases {

namespace {

using dem::hdf5::Handle;
namespace hdf5 = dem::hdf5;

constexpr const char* kFormat = "trackbed sample build checkpoint 1";
// Its part (attribute `part`; a checkpoint without it was taken in a conversion).
constexpr const char* kBallBuild = "ball build";
constexpr const char* kConversion = "conversion";
constexpr const char* kWhat = "a checkpoint of trackbed build-sample (checkpoint.h5 of its folder)";
constexpr int kStageColumns = 9;
constexpr int kHistoryColumns = 7;

// Rows of numbers as one 2-D dataset, the texts beside them as an attribute.
void write_table(hid_t g, const char* name, const std::vector<std::string>& texts,
                 const std::vector<double>& flat, int cols) {
  hdf5::write_doubles(g, name, flat.data(), texts.size(), cols);
  hdf5::write_strings(g, (std::string(name) + "_names").c_str(), texts);
}

// The figures of a report or history, `cols` to a row: finite, whole numbers >= 0 in the
// `counts` columns, NaN allowed in the `undefined` ones (a sleeper's height before there is
// one). InputError naming the table otherwise, before anything is converted.
void require_report_numbers(const std::vector<double>& v, int cols, const std::vector<int>& counts,
                            const std::vector<int>& undefined, const std::string& file,
                            const char* name) {
  auto in = [](const std::vector<int>& columns, int c) {
    return std::find(columns.begin(), columns.end(), c) != columns.end();
  };
  for (std::size_t k = 0; k < v.size(); ++k) {
    const int c = static_cast<int>(k % cols);
    const bool ok = in(counts, c) ? v[k] >= 0 && v[k] <= 1e15 && v[k] == std::floor(v[k])
                                  : std::isfinite(v[k]) || (in(undefined, c) && std::isnan(v[k]));
    if (!ok)
      throw InputError(file + ": " + name + " holds " + number_text(v[k]) + " in column " +
                       std::to_string(c) +
                       "; valid: " + (in(counts, c) ? "a whole number >= 0" : "a finite number") +
                       "; the file is damaged");
  }
}

std::vector<double> read_table(hid_t g, const std::string& file, const char* name,
                               std::vector<std::string>& texts, int cols,
                               const std::vector<int>& counts, const std::vector<int>& undefined) {
  texts = hdf5::read_strings(g, file, (std::string(name) + "_names").c_str());
  auto v = hdf5::read_doubles(g, file, name, static_cast<long>(texts.size()) * cols);
  require_report_numbers(v, cols, counts, undefined, file, name);
  return v;
}

void write_stages(hid_t g, const char* name, const std::vector<dem::StageReport>& stages) {
  std::vector<std::string> names;
  std::vector<double> flat;
  for (const auto& s : stages) {
    names.push_back(s.name);
    flat.insert(flat.end(), {double(s.steps), s.simulated_time, s.wall_time, s.final_ratio,
                             s.converged ? 1.0 : 0.0, double(s.bodies), double(s.elements),
                             double(s.contacts), s.time_step});
  }
  write_table(g, name, names, flat, kStageColumns);
}

std::vector<dem::StageReport> read_stages(hid_t g, const std::string& file, const char* name) {
  std::vector<std::string> names;
  // steps, converged (0 or 1), bodies, elements, contacts
  const auto v = read_table(g, file, name, names, kStageColumns, {0, 4, 5, 6, 7}, {});
  std::vector<dem::StageReport> out;
  for (std::size_t k = 0; k < names.size(); ++k) {
    const double* r = v.data() + k * kStageColumns;
    dem::StageReport s;
    s.name = names[k];
    s.steps = std::lround(r[0]);
    s.simulated_time = r[1], s.wall_time = r[2], s.final_ratio = r[3];
    s.converged = r[4] != 0;
    s.bodies = static_cast<int>(r[5]), s.elements = static_cast<int>(r[6]);
    s.contacts = static_cast<int>(r[7]);
    s.time_step = r[8];
    out.push_back(s);
  }
  return out;
}

// The ball build's report (dem::BuildReport) less its stages.
void write_ball_build(hid_t file, const dem::BuildCheckpoint& b) {
  const dem::BuildReport& r = b.report;
  Handle g(hdf5::create_group(file, "ball_build"), H5Gclose, "group ball_build");
  hdf5::write_doubles(
      g, "report",
      {double(r.stones_drawn), r.deposition_friction_factor, r.porosity, b.sleeper_lift});
  std::vector<dem::StageReport> stages;
  std::vector<double> points;
  for (const auto& p : r.calibration) {
    stages.push_back(p.stage);
    points.insert(points.end(), {p.friction_factor, p.porosity});
  }
  write_stages(g, "calibration_stages", stages);
  hdf5::write_doubles(g, "calibration", points);
}

void read_ball_build(hid_t file, const std::string& path, dem::BuildCheckpoint& b) {
  dem::BuildReport& r = b.report;
  Handle g(hdf5::open_group(file, path, "ball_build"), H5Gclose, "group ball_build");
  const auto n = hdf5::read_doubles(g, path, "report", 4);
  // stones drawn; the sleeper's lift NaN before it is placed
  require_report_numbers(n, 4, {0}, {3}, path, "ball_build/report");
  r.stones_drawn = static_cast<int>(n[0]);
  r.deposition_friction_factor = n[1];
  r.porosity = n[2];
  b.sleeper_lift = n[3];
  const auto stages = read_stages(g, path, "calibration_stages");
  const auto points = hdf5::read_doubles(g, path, "calibration", 2 * long(stages.size()));
  require_report_numbers(points, 2, {}, {}, path, "ball_build/calibration");
  for (std::size_t k = 0; k < stages.size(); ++k)
    r.calibration.push_back({points[2 * k], points[2 * k + 1], stages[k]});
}

}  // namespace

std::string sample_digest(const dem::Sample& sample) {
  std::uint64_t h = 14695981039346656037ull;
  auto add = [&](const void* data, std::size_t bytes) {
    const auto* b = static_cast<const unsigned char*>(data);
    for (std::size_t k = 0; k < bytes; ++k) h = (h ^ b[k]) * 1099511628211ull;
  };
  const dem::Particles& p = sample.particles;
  const long n = p.num_bodies();
  add(&n, sizeof n);
  add(p.id.data(), p.id.size() * sizeof(p.id[0]));
  for (const dem::Vec3& x : p.x) add(x.data(), 3 * sizeof(double));
  add(p.radius.data(), p.radius.size() * sizeof(double));
  char text[32];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(h));
  return text;
}

std::string SampleCheckpoint::where() const {
  if (in_ball_build)
    return "ball build's " + dem::to_string(ball_build.stage) + " stage at step " +
           std::to_string(ball_build.point.steps);
  return dem::to_string(conversion.stage) + " stage at step " +
         std::to_string(conversion.point.steps);
}

void write_sample_checkpoint(const std::string& path, const SampleCheckpoint& c) {
  hdf5::write_file(path, "checkpoint", [&](hid_t file) {
    hdf5::write_string_attribute(file, "format", kFormat);
    hdf5::write_string_attribute(file, "version", c.version);
    hdf5::write_string_attribute(file, "sample_file", c.sample_file);
    hdf5::write_string_attribute(file, "fingerprint", c.fingerprint);
    hdf5::write_string_attribute(file, "base_digest", c.base_digest);
    hdf5::write_string_attribute(file, "threads", std::to_string(c.threads));
    hdf5::write_string_attribute(file, "part", c.in_ball_build ? kBallBuild : kConversion);
    const dem::BuildCheckpoint& b = c.ball_build;
    const dem::ConversionCheckpoint& v = c.conversion;
    {
      Handle g(hdf5::create_group(file, "engine"), H5Gclose, "group engine");
      dem::write_engine_state(g, c.in_ball_build ? b.engine : v.engine);
    }
    if (c.in_ball_build) write_ball_build(file, b);
    Handle build(hdf5::create_group(file, "build"), H5Gclose, "group build");
    const int stage = c.in_ball_build ? static_cast<int>(b.stage) : static_cast<int>(v.stage);
    const dem::StagePoint& at = c.in_ball_build ? b.point : v.point;
    const std::vector<double> counters = {double(stage), double(at.steps), double(at.below),
                                          at.wall_time, c.wall_seconds};
    hdf5::write_doubles(build, "counters", counters);
    hdf5::write_doubles(build, "criterion_memory",
                        c.in_ball_build ? b.criterion_memory : v.criterion_memory);
    // The stages the running part finished before.
    write_stages(build, "conversion_stages", c.in_ball_build ? b.report.stages : v.done);
    write_stages(build, "build_stages", c.stages);
    std::vector<std::string> keys, values;
    for (const auto& [k, x] : c.notes) keys.push_back(k), values.push_back(x);
    hdf5::write_strings(build, "note_keys", keys);
    hdf5::write_strings(build, "note_values", values);
    std::vector<std::string> stages;
    std::vector<double> flat;
    for (const auto& h : c.history) {
      stages.push_back(h.stage);
      flat.insert(flat.end(), {h.time, double(h.step), h.ratio, h.kinetic_energy,
                               double(h.contacts), h.sleeper_z, h.sleeper_load});
    }
    write_table(build, "history", stages, flat, kHistoryColumns);
  });
}

bool is_sample_checkpoint(const std::string& path) {
  Handle file(hdf5::open_for_reading(path, kWhat), H5Fclose, "open " + path);
  return hdf5::has_format(file, path, kFormat);
}

SampleCheckpoint read_sample_checkpoint(const std::string& path) {
  Handle file(hdf5::open_for_reading(path, kWhat), H5Fclose, "open " + path);
  if (!hdf5::has_format(file, path, kFormat))
    throw InputError(path + ": not a sample build checkpoint of this version; valid: " + kWhat +
                     " (" + kFormat + ")");
  SampleCheckpoint c;
  c.version = hdf5::read_string_attribute(file, path, "version");
  c.sample_file = hdf5::read_string_attribute(file, path, "sample_file");
  c.fingerprint = hdf5::read_string_attribute(file, path, "fingerprint");
  c.base_digest = hdf5::read_string_attribute(file, path, "base_digest");
  c.threads = static_cast<int>(hdf5::read_integer_attribute(file, path, "threads", 1, 1024));
  const std::string part = H5Aexists(file, "part") > 0
                               ? hdf5::read_string_attribute(file, path, "part")
                               : std::string(kConversion);
  if (part != kBallBuild && part != kConversion)
    throw InputError(path + ": part = '" + part + "'; valid: '" + kBallBuild + "' or '" +
                     kConversion + "'; the file is damaged");
  c.in_ball_build = part == kBallBuild;
  if (c.in_ball_build && !c.base_digest.empty())
    throw InputError(path + ": base_digest = '" + excerpt(c.base_digest) +
                     "' in a ball build's checkpoint, which has no base sample; valid: empty; "
                     "the file is damaged");
  dem::BuildCheckpoint& b = c.ball_build;
  dem::ConversionCheckpoint& v = c.conversion;
  {
    Handle g(hdf5::open_group(file, path, "engine"), H5Gclose, "group engine");
    (c.in_ball_build ? b.engine : v.engine) = dem::read_engine_state(g, path);
  }
  if (c.in_ball_build) read_ball_build(file, path, b);
  Handle build(hdf5::open_group(file, path, "build"), H5Gclose, "group build");
  const auto n = hdf5::read_doubles(build, path, "counters", 5);
  // stage, steps, checks below the criterion: counts
  require_report_numbers(n, 5, {0, 1, 2}, {}, path, "build/counters");
  const int last = (c.in_ball_build ? dem::kBuildStages : dem::kConversionStages) - 1;
  if (n[0] > last)
    throw InputError(path + ": build/counters names stage " + number_text(n[0]) + " of the " +
                     part + "; valid: 0 to " + std::to_string(last) + "; the file is damaged");
  const int stage = static_cast<int>(n[0]);
  dem::StagePoint& at = c.in_ball_build ? b.point : v.point;
  at.steps = std::lround(n[1]);
  at.below = static_cast<int>(n[2]);
  at.wall_time = n[3];
  c.wall_seconds = n[4];
  (c.in_ball_build ? b.criterion_memory : v.criterion_memory) =
      hdf5::read_doubles(build, path, "criterion_memory");
  (c.in_ball_build ? b.file : v.file) = path;
  auto& done = c.in_ball_build ? b.report.stages : v.done;
  done = read_stages(build, path, "conversion_stages");
  if (c.in_ball_build)
    b.stage = static_cast<dem::BuildStage>(stage);
  else
    v.stage = static_cast<dem::ConversionStage>(stage);
  c.stages = read_stages(build, path, "build_stages");
  const auto keys = hdf5::read_strings(build, path, "note_keys");
  const auto values = hdf5::read_strings(build, path, "note_values");
  if (keys.size() != values.size())
    throw InputError(path +
                     ": build/note_keys and note_values differ in length; the file "
                     "is damaged");
  for (std::size_t k = 0; k < keys.size(); ++k) c.notes.push_back({keys[k], values[k]});
  std::vector<std::string> stages;
  // steps and contacts; the sleeper's height and load NaN without one
  const auto flat = read_table(build, path, "history", stages, kHistoryColumns, {1, 4}, {5, 6});
  for (std::size_t k = 0; k < stages.size(); ++k) {
    const double* r = flat.data() + k * kHistoryColumns;
    if (std::isnan(r[5]) != std::isnan(r[6]))  // a sleeper has both a height and a load
      throw InputError(path + ": build/history row " + std::to_string(k) +
                       " has a sleeper height or load but not both; the file is damaged");
    c.history.push_back(
        {stages[k], r[0], std::lround(r[1]), r[2], r[3], static_cast<int>(r[4]), r[5], r[6]});
  }
  return c;
}

}  // namespace trackbed::cases
