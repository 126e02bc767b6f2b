#include "cases/runs/sample_run.h"

#include <omp.h>
#include <sys/resource.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <csignal>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "cases/app/stop_signal.h"
#include "cases/reports/report_support.h"
#include "cases/runs/run_checkpoint.h"
#include "cases/runs/start_record.h"
#include "common/absolute_path.h"
#include "common/input_error.h"
#include "common/number_text.h"
#include "common/output_folder.h"
#include "dem/engine/sleeper_support.h"
#include "dem/io/atomic_file.h"
#include "dem/io/vtu_writer.h"
#include "dem/samples/clump_conversion.h"
#include "dem/samples/porosity.h"
#include "dem/samples/sample_builder.h"
#include "dem/samples/section_model.h"
#include "dem/samples/template_library.h"
#include "dem/samples/zone.h"

namespace trackbed::cases {

namespace fs = std::filesystem;

namespace {

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

// Thrown at a check of the conversion when a signal asks the build to stop.
struct BuildInterrupted {};

// A JSON number with ten significant digits; null for a non-finite one (JSON has no NaN).
std::string number(double v) {
  return std::isfinite(v) ? number_text(v, 10) : "null";
}

template <class T, std::size_t N>
std::string json_array(const std::array<T, N>& values) {
  std::string s = "[";
  for (std::size_t k = 0; k < N; ++k) s += (k ? ", " : "") + number(values[k]);
  return s + "]";
}

}  // namespace

SampleRun::SampleRun(SampleParameters parameters)
    : prm_(std::move(parameters)), test_signal_(test_signal_from_environment()) {}

void SampleRun::connect(dem::StageRunner& runner) {
  runner.progress_seconds = prm_.progress_interval;
  runner.on_progress = [](const std::string& line) { std::cout << line << std::endl; };
  runner.on_sample = [this](const dem::SettleSample& s) { history_.push_back(s); };
}

void SampleRun::stop_at_checks() {
  catch_stop_signals();
  last_checkpoint_ = std::chrono::steady_clock::now();
}

dem::Sample SampleRun::build_ball_sample(dem::BuildCheckpoint* from) {
  dem::SampleBuilder builder(prm_.build);
  connect(builder.runner());
  builder.runner().at_check = [&](const dem::StagePoint& at) {
    // Not in the calibration: its depositions of a small box are made again on resume.
    if (!builder.in_stage()) return;
    long step = at.steps;  // of the build, calibration included
    for (const auto& s : builder.report().stages) step += s.steps;
    at_check(step, [&](SampleCheckpoint& c) {
      c.in_ball_build = true;
      c.ball_build = builder.checkpoint(at);
    });
  };
  if (!from) std::cout << "trackbed: building the ball sample of the section" << std::endl;
  stop_at_checks();
  dem::Sample sample = builder.run(from);
  const dem::BuildReport& r = builder.report();
  stages_.insert(stages_.end(), r.stages.begin(), r.stages.end());
  notes_.push_back({"stones_drawn", number(r.stones_drawn)});
  notes_.push_back({"deposition_friction_factor", number(r.deposition_friction_factor)});
  notes_.push_back({"porosity_after_deposition", number(r.porosity)});
  for (const auto& c : r.calibration)
    notes_.push_back(
        {"calibration_porosity_at_friction_x" + number(c.friction_factor), number(c.porosity)});
  if (prm_.preset == "all-ball") write_outputs(sample, builder.simulation(), nullptr);
  return sample;
}

dem::Sample SampleRun::convert(const dem::Sample& base, dem::ConversionCheckpoint* from) {
  // A preset's zone is that of the base sample's own section.
  const std::string text =
      prm_.preset == "custom" ? prm_.zone_text : preset_zone(prm_.preset, dem::section_of(base));
  const dem::ZonePtr zone =
      dem::parse_zone(text, prm_.file + ": zone/clump zone", prm_.zone_folder);
  auto templates =
      dem::read_template_library(prm_.templates, prm_.template_setting, prm_.mass_from);
  const std::size_t template_count = templates.size();
  dem::ClumpConversion conversion(base, zone, std::move(templates), prm_.conversion);
  std::cout << "trackbed: converting the " << conversion.balls_in_zone() << " balls (of "
            << base.particles.num_bodies() << " bodies) in zone " << zone->to_string()
            << " to clumps of " << template_count << " templates " << prm_.template_setting
            << std::endl;
  report_pilots(*zone, from != nullptr);
  connect(conversion.runner());
  conversion.runner().at_check = [&](const dem::StagePoint& at) {
    at_check(conversion.simulation().step_count(),
             [&](SampleCheckpoint& c) { c.conversion = conversion.checkpoint(at); });
  };
  stop_at_checks();
  base_digest_ = sample_digest(base);
  if (from && from_digest_ != base_digest_)
    throw InputError(prm_.file +
                     ": the base sample has changed since the build started "
                     "(another file, or built again); valid: the base sample it started "
                     "from, or a new build");
  dem::Sample sample = conversion.run(from);
  const dem::ConversionReport& r = conversion.report();
  stages_.insert(stages_.end(), r.stages.begin(), r.stages.end());
  notes_.push_back({"converted_balls", number(r.converted)});
  notes_.push_back({"growth_start_scale_min", number(r.start_scale_min)});
  notes_.push_back({"growth_start_scale_mean", number(r.start_scale_mean)});
  write_outputs(sample, conversion.simulation(), &base);
  return sample;
}

// What each pilot term of the zone selected, on the terminal and in the summary, so a user can
// tune its threshold to the zone size wanted (docs/zones.md#pilot-zones). A resumed build has the
// notes in its checkpoint already.
void SampleRun::report_pilots(const dem::Zone& zone, bool resumed) {
  const auto pilots = zone.pilot_summaries();
  for (std::size_t k = 0; k < pilots.size(); ++k) {
    const dem::PilotSummary& s = pilots[k];
    std::cout << "trackbed: pilot zone " << k + 1 << ": " << s.selected_bodies << " of "
              << s.total_bodies << " bodies moved more than the threshold by "
              << fs::path(s.snapshot).filename().string() << " (step " << s.step
              << ", t = " << s.time << " s, sleeper displacement " << s.sleeper_displacement
              << " m)" << std::endl;
    if (resumed) continue;
    const std::string key = "pilot" + std::to_string(k + 1) + "_";
    notes_.push_back({key + "selected_bodies", number(s.selected_bodies)});
    notes_.push_back({key + "total_bodies", number(s.total_bodies)});
    notes_.push_back({key + "sleeper_displacement", number(s.sleeper_displacement)});
  }
}

void SampleRun::at_check(long step, const PartState& part) {
  if (test_signal_.first >= 0 && step >= test_signal_.first) {
    test_signal_.first = -1;
    std::raise(test_signal_.second);
  }
  const bool stop = stop_signal() != 0;
  const bool checkpoints = prm_.checkpoint_interval > 0;
  if (checkpoints && (stop || seconds_since(last_checkpoint_) >= prm_.checkpoint_interval))
    write_checkpoint(part);
  if (stop) throw BuildInterrupted{};
}

void SampleRun::write_checkpoint(const PartState& part) {
  SampleCheckpoint c;
  c.sample_file = absolute_path(prm_.file);
  c.fingerprint = prm_.fingerprint;
  c.base_digest = base_digest_;
  c.version = TRACKBED_VERSION;
  c.threads = omp_get_max_threads();
  c.wall_seconds = earlier_wall_seconds_ + seconds_since(start_);
  c.stages = stages_;
  c.notes = notes_;
  c.history = history_;
  part(c);
  write_sample_checkpoint(out_ + "/" + kCheckpointFile, c);
  last_checkpoint_ = std::chrono::steady_clock::now();
}

int SampleRun::run() {
  return build(nullptr);
}

int SampleRun::resume(SampleCheckpoint checkpoint) {
  history_ = std::move(checkpoint.history);
  stages_ = std::move(checkpoint.stages);
  notes_ = std::move(checkpoint.notes);
  earlier_wall_seconds_ = checkpoint.wall_seconds;
  from_digest_ = checkpoint.base_digest;
  const double t = (checkpoint.in_ball_build ? checkpoint.ball_build.engine.time
                                             : checkpoint.conversion.engine.time);
  std::cout << "trackbed: resuming " << prm_.file << " in " << prm_.output_folder << " in its "
            << checkpoint.where() << " (t = " << t << " s)" << std::endl;
  return build(&checkpoint);
}

int SampleRun::build(SampleCheckpoint* from) {
  start_ = std::chrono::steady_clock::now();
  if (prm_.threads > 0) omp_set_num_threads(prm_.threads);
  out_ = prm_.output_folder;
  create_output_folders(out_, {"history"}, output_folder_parameter(prm_.file, out_));
  dem::BuildCheckpoint* in_ball_build = from && from->in_ball_build ? &from->ball_build : nullptr;
  dem::ConversionCheckpoint* in_conversion =
      from && !from->in_ball_build ? &from->conversion : nullptr;
  try {
    if (prm_.preset == "all-ball") {
      build_ball_sample(in_ball_build);
    } else if (!prm_.base_sample.empty()) {
      const dem::Sample base = dem::read_sample(prm_.base_sample);
      if (base.particles.num_clumps() > 0 && base.num_balls() == 0)
        throw InputError(prm_.base_sample +
                         ": the base sample has no balls to convert; "
                         "valid: a ball sample (zone preset all-ball)");
      convert(base, in_conversion);
    } else if (in_conversion) {
      convert(dem::read_sample(out_ + "/base.h5"), in_conversion);  // built by the interrupted run
    } else {
      const dem::Sample base = build_ball_sample(in_ball_build);
      dem::write_sample(out_ + "/base.h5", base);
      convert(base, nullptr);
    }
  } catch (const BuildInterrupted&) {
    std::cout << "trackbed: interrupted; "
              << (prm_.checkpoint_interval > 0
                      ? "continue with: trackbed resume " + out_
                      : std::string("no checkpoint written (output/checkpoint interval = 0)"))
              << std::endl;
    return 130;
  }
  // A finished build needs no checkpoint (and it is the largest file of the folder).
  fs::remove(fs::path(out_) / kCheckpointFile);
  remove_start_record(out_);
  std::cout << "trackbed: results in " << out_ << std::endl;
  return 0;
}

void SampleRun::write_outputs(const dem::Sample& sample, const dem::Simulation& sim,
                              const dem::Sample* base) {
  dem::write_sample(out_ + "/sample.h5", sample);
  write_grading(sample, base);
  write_history();
  if (prm_.vtu) {
    dem::particles_grid(sim).write(out_ + "/particles.vtu");
    dem::contacts_grid(sim).write(out_ + "/contacts.vtu");
    dem::walls_grid(sim).write(out_ + "/walls.vtu");
    dem::PvdCollection pvd(out_ + "/sample.pvd");
    for (const char* f : {"particles.vtu", "contacts.vtu", "walls.vtu"}) pvd.add(0, f);
  }
  write_summary(sample, sim);
  if (prm_.plot) make_plots();
}

void SampleRun::write_grading(const dem::Sample& sample, const dem::Sample* base) {
  // The sample's own records: a converted sample comes from a base built by another file.
  const dem::SieveTable t = dem::grading_of(sample);
  const double density = dem::materials_of(sample).ballast.density;
  // By sieve size, and by the diameter of the sphere of the same volume, which the conversion
  // to clumps keeps for every stone (for balls the two are the same).
  auto passing = [&](const dem::Sample& s, bool equivalent) {
    std::vector<double> size = s.sieve_size;
    if (equivalent)
      for (int b = 0; b < s.particles.num_bodies(); ++b)
        size[b] = std::cbrt(6 * s.particles.mass[b] / (density * M_PI));
    return dem::passing_by_mass(size, s.particles.mass, t.size);
  };
  const auto now = passing(sample, false), now_eq = passing(sample, true);
  std::vector<double> before;
  if (base) before = passing(*base, false);
  dem::AtomicFile csv(out_ + "/grading.csv");
  csv.stream() << "# " << t.source
               << "; percent by mass passing, by sieve size and by equivalent diameter\n"
               << "size,target,sample,sample_equivalent_diameter" << (base ? ",base" : "") << "\n";
  max_grading_error_ = 0;
  for (std::size_t k = 0; k < t.size.size(); ++k) {
    csv.stream() << t.size[k] << "," << t.passing[k] << "," << now[k] << "," << now_eq[k];
    if (base) csv.stream() << "," << before[k];
    csv.stream() << "\n";
    max_grading_error_ = std::max(max_grading_error_, std::abs(now[k] - t.passing[k]));
    max_grading_error_equivalent_ =
        std::max(max_grading_error_equivalent_, std::abs(now_eq[k] - t.passing[k]));
  }
  csv.commit();
}

void SampleRun::write_history() {
  dem::AtomicFile csv(out_ + "/history/build.csv");
  csv.stream() << std::setprecision(10)
               << "stage,time,step,ratio,kinetic_energy,contacts,sleeper_z,sleeper_load\n";
  for (const auto& h : history_)
    csv.stream() << '"' << h.stage << "\"," << h.time << "," << h.step << "," << h.ratio << ","
                 << h.kinetic_energy << "," << h.contacts << "," << h.sleeper_z << ","
                 << h.sleeper_load << "\n";
  csv.commit();
}

void SampleRun::write_summary(const dem::Sample& sample, const dem::Simulation& sim) {
  const dem::Particles& p = sample.particles;
  const TrackSection section = dem::section_of(sample);
  const dem::SieveTable grading = dem::grading_of(sample);
  const double largest = dem::largest_stone_size(grading);
  const double spacing = 0.1 * grading.size.front();
  dem::Vec3 lo, hi;
  dem::porosity_box(section, largest, lo, hi);
  const double core = dem::porosity_in_box(p, lo, hi, spacing).porosity;
  const dem::Vec3 plo(-section.half_base_width(), -0.5 * section.length, 0);
  const dem::Vec3 phi(section.half_base_width(), 0.5 * section.length, section.crest_z());
  const double profile = dem::porosity_in_region(p, plo, phi, spacing, [&](const dem::Vec3& x) {
                           return section.in_profile(x);
                         }).porosity;
  long steps = 0;
  double simulated = 0;
  for (const auto& s : stages_) steps += s.steps, simulated += s.simulated_time;
  struct rusage usage;
  getrusage(RUSAGE_SELF, &usage);
  double sleeper_load = NAN, sleeper_bottom = NAN;
  if (const int k = sim.mesh_index(dem::SectionModel::kSleeperName); k >= 0) {
    const dem::MeshBody& m = sim.meshes()[k];
    sleeper_load = m.contact_force.z();
    sleeper_bottom = m.x.z() - 0.5 * section.sleeper_height;
  }
  // (key, label, unit, JSON value)
  std::vector<std::tuple<std::string, std::string, std::string, std::string>> items = {
      {"preset", "zone preset", "", '"' + prm_.preset + '"'},
      {"zone", "clump zone", "", '"' + json_escape(sample.info_value("zone")) + '"'},
      {"template_setting", "template setting", "",
       prm_.preset == "all-ball" ? "null" : '"' + prm_.template_setting + '"'},
      {"bodies", "bodies", "", number(p.num_bodies())},
      {"balls", "balls", "", number(sample.num_balls())},
      {"clumps", "clumps", "", number(p.num_clumps())},
      {"elements", "sphere elements", "", number(p.num_elements())},
      {"pebbles_per_clump", "pebbles per clump", "",
       number(p.num_clumps() > 0 ? double(p.num_elements() - sample.num_balls()) / p.num_clumps()
                                 : 0.0)},
      {"contacts", "contacts", "", number(sim.num_contacts())},
      {"porosity_under_sleeper", "porosity under the sleeper", "", number(core)},
      {"porosity_profile", "porosity of the whole profile", "", number(profile)},
      {"target_porosity", "target porosity", "",
       sample.info_value("build/target porosity").empty()
           ? "null"
           : sample.info_value("build/target porosity")},
      {"max_grading_error_percent", "largest sieve error of the grading", "% of mass",
       number(max_grading_error_)},
      {"max_grading_error_equivalent_percent", "the same by equivalent diameter", "% of mass",
       number(max_grading_error_equivalent_)},
      {"mass_kg", "ballast mass", "kg", number([&] {
         double m = 0;
         for (double x : p.mass) m += x;
         return m;
       }())},
      {"sleeper_load_n", "sleeper contact force z", "N", number(sleeper_load)},
      {"sleeper_weight_n", "sleeper weight", "N", number(section.sleeper_mass * 9.81)},
      {"sleeper_bottom_z_m", "sleeper bottom z", "m", number(sleeper_bottom)},
      {"unbalanced_force_ratio", "mean unbalanced force ratio", "",
       number(sim.unbalanced_force_ratio())},
      {"time_step_s", "time step (last stage)", "s", number(sim.time_step())},
      {"steps", "steps (all stages)", "", number(steps)},
      {"simulated_time_s", "simulated time (all stages)", "s", number(simulated)},
      {"wall_time_s", "wall time", "s", number(earlier_wall_seconds_ + seconds_since(start_))},
      {"threads", "threads", "", number(sim.team_size())},
      {"peak_memory_mb", "peak resident memory", "MB", number(usage.ru_maxrss / 1024.0)},
  };
  if (const int k = sim.mesh_index(dem::SectionModel::kSleeperName); k >= 0) {
    // Where the seated sleeper gets its support (dem/engine/sleeper_support.h): a sleeper balanced
    // on a few stones pushes differently from one carried along its length.
    const dem::SleeperSupport support = dem::sleeper_support(sim, k);
    for (const auto& part : support.parts) {
      items.push_back({"sleeper_" + part.name + "_contacts", "sleeper contacts, " + part.name, "",
                       number(part.contacts)});
      items.push_back({"sleeper_" + part.name + "_load_share",
                       "share of the sleeper's load on its " + part.name, "",
                       number(part.force.z() / sleeper_load)});
    }
    items.push_back({"sleeper_largest_base_contact_share",
                     "largest base contact's share of the load", "",
                     number(support.largest_base_contact / sleeper_load)});
    items.push_back({"sleeper_base_contacts_by_fifth", "base contacts by fifths of the length", "",
                     json_array(support.base_contacts)});
    items.push_back({"sleeper_base_load_by_fifth_n", "base load by fifths of the length", "N",
                     json_array(support.base_load)});
  }
  for (const auto& [k, v] : notes_) items.push_back({k, k, "", v});

  dem::AtomicFile json(out_ + "/summary.json");
  json.stream() << "{\n  \"sample_file\": \"" << json_escape(absolute_path(prm_.file)) << "\"";
  for (const auto& [key, label, unit, value] : items)
    json.stream() << ",\n  \"" << key << "\": " << value;
  json.stream() << ",\n  \"stages\": [";
  for (std::size_t k = 0; k < stages_.size(); ++k) {
    const auto& s = stages_[k];
    json.stream() << (k ? ",\n" : "\n") << "    {\"name\": \"" << json_escape(s.name)
                  << "\", \"steps\": " << s.steps
                  << ", \"simulated_time_s\": " << number(s.simulated_time)
                  << ", \"wall_time_s\": " << number(s.wall_time)
                  << ", \"time_step_s\": " << number(s.time_step)
                  << ", \"final_ratio\": " << number(s.final_ratio)
                  << ", \"converged\": " << (s.converged ? "true" : "false")
                  << ", \"bodies\": " << s.bodies << ", \"elements\": " << s.elements << "}";
  }
  json.stream() << "\n  ]\n}\n";
  json.commit();

  dem::AtomicFile txt(out_ + "/summary.txt");
  auto& t = txt.stream();
  t << "trackbed sample: " << absolute_path(prm_.file) << "\n";
  for (const auto& [key, label, unit, value] : items) {
    std::string v = value;
    if (!v.empty() && v.front() == '"') v = v.substr(1, v.size() - 2);
    t << "  " << std::left << std::setw(44) << label << " " << v << (unit.empty() ? "" : " ")
      << unit << "\n";
  }
  t << "\n  " << std::left << std::setw(34) << "stage" << std::right << std::setw(9) << "steps"
    << std::setw(11) << "time (s)" << std::setw(11) << "wall (s)" << std::setw(11) << "ratio"
    << "  converged\n";
  for (const auto& s : stages_)
    t << "  " << std::left << std::setw(34) << s.name << std::right << std::setw(9) << s.steps
      << std::setw(11) << std::setprecision(4) << s.simulated_time << std::setw(11)
      << std::setprecision(4) << s.wall_time << std::setw(11) << std::setprecision(3)
      << s.final_ratio << "  " << (s.converged ? "yes" : "NO") << "\n";
  txt.commit();
}

void SampleRun::make_plots() {
  run_plot_script("plot_sample.py", out_);
}

}  // namespace trackbed::cases
