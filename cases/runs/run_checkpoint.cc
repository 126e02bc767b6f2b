#include "cases/runs/run_checkpoint.h"

#include <algorithm>
#include <cmath>

#include "common/input_error.h"
#include "common/number_text.h"
#include "dem/engine/value_checks.h"
#include "dem/io/hdf5_io.h"

namespace trackbed::cases {

namespace {

using dem::hdf5::Handle;
namespace hdf5 = dem::hdf5;

constexpr const char* kFormat = "trackbed checkpoint 1";
constexpr const char* kWhat = "a trackbed checkpoint (checkpoint.h5 of a results folder)";

std::vector<double> energy_numbers(const dem::EnergyBudget& e) {
  return {e.kinetic, e.strain,        e.friction,     e.rolling,
          e.dashpot, e.local_damping, e.gravity_work, e.wall_work};
}

dem::EnergyBudget energy_of(const std::vector<double>& v) {
  dem::EnergyBudget e;
  e.kinetic = v[0], e.strain = v[1], e.friction = v[2], e.rolling = v[3], e.dashpot = v[4];
  e.local_damping = v[5], e.gravity_work = v[6], e.wall_work = v[7];
  return e;
}

// A coupled run's group "coupling": the FE displacement, the scheme's memory, the run's sums.
void write_coupling(hid_t file, const SubgradeCoupling::Progress& p) {
  Handle g(hdf5::create_group(file, "coupling"), H5Gclose, "group coupling");
  const coupling::QuasiStaticState& s = p.scheme;
  hdf5::write_doubles(g, "fe_displacement", p.fe_displacement);
  hdf5::write_doubles(
      g, "counters",
      {double(s.exchanges), s.last_relaxation, s.converged ? 1.0 : 0.0, p.interface_work,
       p.strain_energy, p.fe_seconds, p.sleeper_z0, double(s.diverging)});
  hdf5::write_vectors(g, "interface_displacement", s.displacement);
  hdf5::write_vectors(g, "last_residual", s.last_residual);
  hdf5::write_vectors(g, "interval_origin", p.interval_origin);
  hdf5::write_integers(g, "history_bytes",
                       std::vector<std::int64_t>(p.history_bytes.begin(), p.history_bytes.end()));
}

SubgradeCoupling::Progress read_coupling(hid_t file, const std::string& path) {
  Handle g(hdf5::open_group(file, path, "coupling"), H5Gclose, "group coupling");
  SubgradeCoupling::Progress p;
  coupling::QuasiStaticState& s = p.scheme;
  p.fe_displacement = hdf5::read_doubles(g, path, "fe_displacement");
  const auto n = hdf5::read_doubles(g, path, "counters", 8);
  // Counts (exchanges, diverging exchanges) and a flag (converged) stored as reals, checked
  // before they are converted; the sums finite, the FE time not negative.
  auto count = [](double c) { return c >= 0 && c <= 1e12 && c == std::floor(c); };
  if (!count(n[0]) || !count(n[7]) || !(n[2] == 0 || n[2] == 1) || !dem::all_finite(n) || n[5] < 0)
    throw InputError(path +
                     ": coupling/counters hold a value out of range (a count not a whole number "
                     ">= 0, a flag not 0 or 1, a sum not finite); the file is damaged");
  s.exchanges = static_cast<int>(n[0]), s.last_relaxation = n[1], s.converged = n[2] != 0;
  p.interface_work = n[3], p.strain_energy = n[4], p.fe_seconds = n[5], p.sleeper_z0 = n[6];
  s.diverging = static_cast<int>(n[7]);
  s.displacement = hdf5::read_vectors(g, path, "interface_displacement");
  s.last_residual = hdf5::read_vectors(g, path, "last_residual");
  p.interval_origin = hdf5::read_vectors(g, path, "interval_origin");
  const auto bytes = hdf5::read_integers(g, path, "history_bytes", 2);
  p.history_bytes.assign(bytes.begin(), bytes.end());
  if (!dem::all_finite(p.fe_displacement) || !dem::all_finite(s.displacement) ||
      !dem::all_finite(s.last_residual) || !dem::all_finite(p.interval_origin) ||
      std::any_of(bytes.begin(), bytes.end(), [](std::int64_t b) { return b < 0; }))
    throw InputError(path +
                     ": the coupling's FE displacement, interface displacements or residuals "
                     "are not finite, or its history lengths negative; the file is damaged");
  return p;
}

// The run's own numbers (the engine state is checked where it is restored): finite where they
// must be; the next output times >= 0, infinite when no output is planned; history lengths >= 0.
void check_run_numbers(const RunCheckpoint& c, const std::string& path) {
  const bool times_ok = c.next_history >= 0 && c.next_frame >= 0 && c.next_snapshot >= 0 &&
                        c.loop_start_step >= 0 && std::isfinite(c.wall_seconds) &&
                        std::isfinite(c.loop_seconds);
  const bool bytes_ok = std::all_of(c.history_bytes.begin(), c.history_bytes.end(),
                                    [](std::int64_t b) { return b >= 0; });
  const auto& e = c.initial_energy;
  // The first frame is written at the start; frames follow in time, none after the state's.
  const bool frames_ok = !c.frame_times.empty() &&
                         std::is_sorted(c.frame_times.begin(), c.frame_times.end()) &&
                         c.frame_times.back() <= c.engine.time;
  const bool start_ok = frames_ok && dem::all_finite(c.frame_times) &&
                        dem::all_finite(energy_numbers(e)) &&
                        std::all_of(c.initial_positions.begin(), c.initial_positions.end(),
                                    [](const dem::Vec3& x) { return x.allFinite(); });
  if (!times_ok || !bytes_ok || !start_ok)
    throw InputError(path +
                     ": the run's counters, frame times, history lengths or starting "
                     "state hold a value out of range (not finite, negative, out of order); the "
                     "file is damaged");
}

// The push test's clock and counters (its hold ratio is NaN until the first hold is judged; its
// rows are the output's, NaN where a figure is not defined yet).
void check_push_numbers(const PushTest::Progress& p, const std::string& path) {
  if (!std::isfinite(p.start) || !std::isfinite(p.push_start) || std::isinf(p.hold_ratio) ||
      p.leg < 0 || p.confirmations < 0)
    throw InputError(path +
                     ": the push test's clock or counters hold a value out of range (not "
                     "finite, negative); the file is damaged");
}

}  // namespace

void write_run_checkpoint(const std::string& path, const RunCheckpoint& c) {
  hdf5::write_file(path, "checkpoint", [&](hid_t file) {
    hdf5::write_string_attribute(file, "format", kFormat);
    hdf5::write_string_attribute(file, "version", c.version);
    hdf5::write_string_attribute(file, "case_file", c.case_file);
    hdf5::write_string_attribute(file, "case_fingerprint", c.case_fingerprint);
    hdf5::write_string_attribute(file, "threads", std::to_string(c.threads));
    {
      Handle g(hdf5::create_group(file, "engine"), H5Gclose, "group engine");
      dem::write_engine_state(g, c.engine);
    }
    Handle run(hdf5::create_group(file, "run"), H5Gclose, "group run");
    hdf5::write_doubles(
        run, "counters",
        {c.next_history, c.next_frame, c.next_snapshot, c.warned_critical ? 1.0 : 0.0,
         double(c.loop_start_step), c.wall_seconds, c.loop_seconds});
    hdf5::write_doubles(run, "frame_times", c.frame_times);
    hdf5::write_integers(run, "history_bytes",
                         std::vector<std::int64_t>(c.history_bytes.begin(), c.history_bytes.end()));
    hdf5::write_doubles(run, "initial_energy", energy_numbers(c.initial_energy));
    hdf5::write_vectors(run, "initial_positions", c.initial_positions);
    if (c.has_push) {
      Handle g(hdf5::create_group(file, "push"), H5Gclose, "group push");
      const PushTest::Progress& p = c.push;
      hdf5::write_doubles(g, "progress",
                          {p.start, p.push_start, p.hold_ratio, double(p.leg),
                           double(p.confirmations), p.hold_converged ? 1.0 : 0.0});
      const std::size_t cols = p.rows.empty() ? 0 : p.rows.front().size();
      std::vector<double> flat;
      for (const auto& r : p.rows) flat.insert(flat.end(), r.begin(), r.end());
      hdf5::write_doubles(g, "rows", flat.data(), p.rows.size(), cols);  // cols >= 7
      hdf5::write_string_attribute(g, "columns", std::to_string(cols));
      if (!p.start_support.empty()) hdf5::write_doubles(g, "start_support", p.start_support);
    }
    if (c.coupled) write_coupling(file, c.coupling);
  });
}

RunCheckpoint read_run_checkpoint(const std::string& path) {
  Handle file(hdf5::open_for_reading(path, kWhat), H5Fclose, "open " + path);
  if (!hdf5::has_format(file, path, kFormat))
    throw InputError(path + ": not a trackbed checkpoint of this version; valid: " + kWhat + " (" +
                     kFormat + ")");
  RunCheckpoint c;
  c.version = hdf5::read_string_attribute(file, path, "version");
  c.case_file = hdf5::read_string_attribute(file, path, "case_file");
  c.case_fingerprint = hdf5::read_string_attribute(file, path, "case_fingerprint");
  c.threads = static_cast<int>(hdf5::read_integer_attribute(file, path, "threads", 1, 1024));
  {
    Handle g(hdf5::open_group(file, path, "engine"), H5Gclose, "group engine");
    c.engine = dem::read_engine_state(g, path);
  }
  Handle run(hdf5::open_group(file, path, "run"), H5Gclose, "group run");
  const auto n = hdf5::read_doubles(run, path, "counters", 7);
  // A flag (0 or 1) and a step of the run, stored as reals: checked before they are converted.
  if (!(n[3] == 0 || n[3] == 1) || !(n[4] >= 0 && n[4] <= static_cast<double>(c.engine.steps)))
    throw InputError(path + ": run/counters hold a warning flag of " + number_text(n[3]) +
                     " (valid: 0 or 1) or a first timed step of " + number_text(n[4]) +
                     " (valid: 0 to the state's step " + std::to_string(c.engine.steps) +
                     "); the file is damaged");
  c.next_history = n[0], c.next_frame = n[1], c.next_snapshot = n[2];
  c.warned_critical = n[3] != 0, c.loop_start_step = static_cast<long>(n[4]);
  c.wall_seconds = n[5], c.loop_seconds = n[6];
  c.frame_times = hdf5::read_doubles(run, path, "frame_times");
  const auto bytes = hdf5::read_integers(run, path, "history_bytes", 3);
  c.history_bytes.assign(bytes.begin(), bytes.end());
  c.initial_energy = energy_of(hdf5::read_doubles(run, path, "initial_energy", 8));
  c.initial_positions =
      hdf5::read_vectors(run, path, "initial_positions", c.engine.particles.num_elements());
  check_run_numbers(c, path);
  c.has_push = hdf5::exists(file, "push");
  if (c.has_push) {
    Handle g(hdf5::open_group(file, path, "push"), H5Gclose, "group push");
    const auto p = hdf5::read_doubles(g, path, "progress", 6);
    c.push.start = p[0], c.push.push_start = p[1], c.push.hold_ratio = p[2];
    c.push.leg = std::lround(p[3]), c.push.confirmations = static_cast<int>(p[4]);
    c.push.hold_converged = p[5] != 0;
    const long cols = hdf5::read_integer_attribute(g, path, "columns", 0, 1000);
    const auto flat = hdf5::read_doubles(g, path, "rows");
    if (cols <= 0 ? !flat.empty() : flat.size() % cols != 0)
      throw InputError(path + ": push/rows does not hold whole rows; the file is damaged");
    for (std::size_t k = 0; cols > 0 && k < flat.size(); k += cols)
      c.push.rows.emplace_back(flat.begin() + k, flat.begin() + k + cols);
    // Written once the push has started (absent from the checkpoints of trackbed before it).
    if (hdf5::exists(g, "start_support"))
      c.push.start_support = hdf5::read_doubles(g, path, "start_support");
    check_push_numbers(c.push, path);
  }
  c.coupled = hdf5::exists(file, "coupling");
  if (c.coupled) c.coupling = read_coupling(file, path);
  return c;
}

}  // namespace trackbed::cases
