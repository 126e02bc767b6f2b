#include "cases/runs/dem_run.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "cases/app/stop_signal.h"
#include "cases/reports/report_support.h"
#include "cases/runs/start_record.h"
#include "common/absolute_path.h"
#include "common/input_error.h"
#include "common/number_text.h"
#include "common/output_folder.h"
#include "dem/io/atomic_file.h"
#include "dem/io/snapshot.h"

namespace trackbed::cases {

namespace fs = std::filesystem;
using dem::Vec3;

namespace {

std::string hms(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0) return "--:--:--";
  const long s = std::lround(seconds);
  char buf[32];
  std::snprintf(buf, sizeof buf, "%ld:%02ld:%02ld", s / 3600, (s / 60) % 60, s % 60);
  return buf;
}

// Whether an output due every `interval` (the next at `next`) was written at the present step, at
// `time` with step `dt`. The loop writes one at the first step whose time reaches `next` (within
// half a step) and moves `next` on by `interval`: the last went at the present step iff
// `next - interval` lies less than half a step before `time`; with an interval shorter than the
// step, one goes every step. Worked out from the schedule alone, it holds for resumed runs too.
bool written_this_step(double next, double interval, double time, double dt) {
  if (!(interval > 0)) return false;
  return interval < dt || next - interval > time - 0.5 * dt;
}

}  // namespace

// The time-series files, written under temporary names and renamed when the run ends.
struct DemRun::Series {
  std::unique_ptr<dem::AtomicFile> walls, energy, bodies;
};

DemRun::DemRun(CaseParameters parameters)
    : prm_(std::move(parameters)), test_signal_(test_signal_from_environment()) {}
DemRun::~DemRun() = default;

void DemRun::open_outputs(const RunCheckpoint* c) {
  out_ = prm_.output_folder;
  create_output_folders(out_, {"history", "vtu", "snapshots"},
                        output_folder_parameter(prm_.file, out_));
  series_ = std::make_unique<Series>();
  const std::string h = out_ + "/history/";
  auto open = [&](const char* name, int k) {
    return c ? std::make_unique<dem::AtomicFile>(h + name, c->history_bytes[k])
             : std::make_unique<dem::AtomicFile>(h + name);
  };
  series_->walls = open("walls.csv", 0);
  series_->energy = open("energy.csv", 1);
  series_->bodies = open("bodies.csv", 2);
  for (auto* f : {series_->walls.get(), series_->energy.get(), series_->bodies.get()})
    f->stream() << std::setprecision(12);

  auto collection = [&](const char* kind) {
    std::vector<std::pair<double, std::string>> frames;
    if (c)
      for (std::size_t k = 0; k < c->frame_times.size(); ++k)
        frames.emplace_back(c->frame_times[k], frame_file(kind, static_cast<int>(k)));
    return std::make_unique<dem::PvdCollection>(out_ + "/" + kind + ".pvd", std::move(frames));
  };
  pvd_particles_ = collection("particles");
  pvd_contacts_ = collection("contacts");
  pvd_walls_ = collection("walls");
  if (c) return;

  auto& w = series_->walls->stream();
  w << "time";
  for (const auto& p : sim_->planes())
    for (const char* col : {"fx", "fy", "fz", "mx", "my", "mz"}) w << "," << p.name << "_" << col;
  for (const auto& m : sim_->meshes()) {
    for (const char* col : {"x", "y", "z", "fx", "fy", "fz", "mx", "my", "mz"})
      w << "," << m.name << "_" << col;
    for (const auto& part : m.local.part_names)
      for (const char* col : {"fx", "fy", "fz", "mx", "my", "mz"})
        w << "," << m.name << "." << part << "_" << col;
  }
  w << "\n";
  series_->energy->stream() << "time,kinetic,strain,friction,rolling,dashpot,local_damping,"
                               "gravity_work,wall_work,balance_error\n";
  series_->bodies->stream() << "time,id,x,y,z,vx,vy,vz,wx,wy,wz\n";
}

dem::EnergyBudget DemRun::write_history() {
  const double t = sim_->time();
  auto& w = series_->walls->stream();
  w << t;
  for (const auto& p : sim_->planes())
    for (const dem::Vec3* v : {&p.force, &p.moment})
      w << "," << v->x() << "," << v->y() << "," << v->z();
  for (const auto& m : sim_->meshes()) {
    for (const Vec3* v : {&m.x, &m.contact_force, &m.contact_moment})
      w << "," << v->x() << "," << v->y() << "," << v->z();
    for (std::size_t k = 0; k < m.part_force.size(); ++k)
      for (const dem::Vec3* v : {&m.part_force[k], &m.part_moment[k]})
        w << "," << v->x() << "," << v->y() << "," << v->z();
  }
  w << "\n";

  const dem::EnergyBudget e = sim_->energy();
  if (prm_.track_energy) {
    series_->energy->stream() << t << "," << e.kinetic << "," << e.strain << "," << e.friction
                              << "," << e.rolling << "," << e.dashpot << "," << e.local_damping
                              << "," << e.gravity_work << "," << e.wall_work << ","
                              << e.balance_error(initial_energy_) << "\n";
  }
  const auto& p = sim_->particles();
  for (const int b : tracked_) {
    series_->bodies->stream() << t << "," << p.id[b] << "," << p.x[b].x() << "," << p.x[b].y()
                              << "," << p.x[b].z() << "," << p.v[b].x() << "," << p.v[b].y() << ","
                              << p.v[b].z() << "," << p.w[b].x() << "," << p.w[b].y() << ","
                              << p.w[b].z() << "\n";
  }
  if (push_) push_->record(*sim_);
  return e;
}

std::string DemRun::frame_file(const char* kind, int k) {
  char name[64];
  std::snprintf(name, sizeof name, "vtu/%s-%06d.vtu", kind, k);
  return name;
}

void DemRun::write_frame() {
  const int k = frame_++;
  dem::particles_grid(*sim_, &initial_positions_).write(out_ + "/" + frame_file("particles", k));
  dem::contacts_grid(*sim_).write(out_ + "/" + frame_file("contacts", k));
  dem::walls_grid(*sim_).write(out_ + "/" + frame_file("walls", k));
  pvd_particles_->add(sim_->time(), frame_file("particles", k));
  pvd_contacts_->add(sim_->time(), frame_file("contacts", k));
  pvd_walls_->add(sim_->time(), frame_file("walls", k));
  if (subgrade_) subgrade_->write_frame(k, sim_->time());
}

void DemRun::write_snapshot() {
  char name[64];
  std::snprintf(name, sizeof name, "/snapshots/state-%09ld.h5", sim_->step_count());
  dem::write_snapshot(out_ + name, *sim_);
}

void DemRun::report_progress(bool last) {
  const auto now = Clock::now();
  const double wall = earlier_wall_seconds_ + std::chrono::duration<double>(now - start_).count();
  const double loop = std::chrono::duration<double>(now - loop_start_).count();
  const long done = sim_->step_count() - std::max(loop_start_step_, part_first_step_);
  const double rate = loop > 0 ? done / loop : 0;
  const double eta = rate > 0 ? (total_steps_ - sim_->step_count()) / rate : NAN;
  const double t_end = total_steps_ * sim_->time_step();
  std::ostringstream s;
  s << std::fixed << std::setprecision(4) << "t = " << sim_->time() << " s of " << t_end << " s ("
    << std::setprecision(1) << 100.0 * sim_->step_count() / std::max(total_steps_, 1L)
    << " %) | step " << sim_->step_count() << " | " << std::setprecision(0) << rate << " steps/s | "
    << std::scientific << std::setprecision(2) << rate * sim_->particles().num_elements()
    << " sphere-steps/s | contacts " << sim_->num_contacts() << " | KE "
    << sim_->particles().kinetic_energy() << " J | "
    << (last ? "wall " + hms(wall) : "ETA " + hms(eta));
  std::cout << s.str() << std::endl;
  // PFC's estimate follows the contacts; a bed that densifies can pass under the step chosen at
  // the start. Said once: the estimate carries a safety factor of about 2 (docs/theory.md).
  const double critical = sim_->critical_timestep();
  if (!warned_critical_ && sim_->time_step() > critical) {
    std::cout << "trackbed: warning: at t = " << sim_->time() << " s the time step "
              << sim_->time_step() << " s is above the critical timestep " << critical
              << " s of the current contacts; watch for instability or lower 'time step'"
              << std::endl;
    warned_critical_ = true;
  }
  last_progress_ = now;
}

int DemRun::run() {
  start_ = Clock::now();
  if (prm_.threads > 0) omp_set_num_threads(prm_.threads);
  build_model();
  start_fresh();
  return loop_and_finish();
}

int DemRun::resume(RunCheckpoint checkpoint) {
  start_ = Clock::now();
  if (prm_.threads > 0) omp_set_num_threads(prm_.threads);
  build_model();
  start_from(checkpoint);
  return loop_and_finish();
}

void DemRun::make_push_test() {
  if (!prm_.push.mesh.empty()) push_ = std::make_unique<PushTest>(prm_.push, *sim_, prm_.file);
}

void DemRun::count_steps() {
  // A push test ends when the push does; the step count is its estimate, updated as it goes.
  const double end_time = push_ ? push_->expected_end(*sim_) : prm_.end_time;
  const double steps = std::ceil(end_time / sim_->time_step() - 1e-9);
  constexpr double kMaxSteps = 1e12;  // beyond any run's wall time, and exact in a long
  if (prm_.number_of_steps == 0 && !(steps <= kMaxSteps))
    throw InputError(prm_.file +
                     (push_ ? ": the push test's end at " : ": simulation/end time = ") +
                     number_text(end_time) + " s is " + number_text(steps) + " steps of " +
                     number_text(sim_->time_step()) + " s; valid: at most 1e12 steps");
  total_steps_ = prm_.number_of_steps > 0 ? prm_.number_of_steps : static_cast<long>(steps);
}

void DemRun::find_tracked_bodies() {
  // Bodies are reordered at setup; the case file names them by id (row of the particle file).
  for (long id : prm_.tracked_bodies) {
    const auto& ids = sim_->particles().id;
    const auto it = std::find(ids.begin(), ids.end(), id);
    if (it == ids.end())
      throw InputError(prm_.file + ": output/tracked bodies: no body with id " +
                       std::to_string(id) + "; valid: 0 to " + std::to_string(ids.size() - 1));
    tracked_.push_back(static_cast<int>(it - ids.begin()));
  }
}

void DemRun::start_fresh() {
  sim_->setup();
  if (!prm_.sample_file.empty()) {
    const int restored = sim_->restore_contact_state(sample_contacts_);
    std::cout << "trackbed: sample " << prm_.sample_file << ": " << restored << " of "
              << sample_contacts_.pairs.size() + sample_contacts_.walls.size()
              << " contact springs restored" << std::endl;
  }
  initial_energy_ = sim_->energy();
  initial_positions_ = sim_->particles().pos;
  find_tracked_bodies();
  make_push_test();
  count_steps();
  open_outputs();
  remove_outputs_after(-1);  // an earlier run's frames and snapshots in this folder
  if (subgrade_) subgrade_->start(*sim_, formation_mesh_, sleeper_mesh(), out_);

  const auto& p = sim_->particles();
  std::cout << "trackbed: " << p.num_bodies() << " bodies (" << p.num_clumps() << " clumps), "
            << p.num_elements() << " sphere elements, " << sim_->planes().size() << " plane walls, "
            << sim_->meshes().size() << " meshes; time step " << sim_->time_step()
            << " s (critical " << sim_->critical_timestep() << " s), " << total_steps_ << " steps, "
            << sim_->team_size() << " threads" << std::endl;
  write_history();
  write_frame();
  // An output that is not written at intervals is never due.
  next_history_ = prm_.history_interval > 0 ? prm_.history_interval : INFINITY;
  next_frame_ = prm_.vtu_interval > 0 ? prm_.vtu_interval : INFINITY;
  // A push test's snapshots start with the push (advance()).
  next_snapshot_ = prm_.snapshot_interval > 0 && !push_ ? prm_.snapshot_interval : INFINITY;
  loop_start_step_ = 0;
}

void DemRun::start_from(RunCheckpoint& c) {
  // The push test checks the case's push DOF before the checkpoint's controls replace it.
  make_push_test();
  if (c.has_push != (push_ != nullptr))
    throw InputError(prm_.file + ": the checkpoint " + std::string(c.has_push ? "has" : "has no") +
                     " push test and the case " + (push_ ? "has" : "has none") +
                     "; valid: the case the run started from");
  const long step = c.engine.steps;
  const std::string checkpoint = (fs::path(prm_.output_folder) / kCheckpointFile).string();
  try {
    sim_->restore_engine_state(std::move(c.engine));
  } catch (const InputError& e) {
    throw InputError(checkpoint + ": " + e.what());
  }
  // The next output times follow the case's intervals: each at most one interval ahead, finite
  // where the case writes at intervals (a push run's snapshots wait for the push: infinite),
  // infinite where it does not.
  const double t = sim_->time();
  auto fits = [t](double next, double interval, bool may_wait) {
    if (interval <= 0) return next == INFINITY;
    return (may_wait && next == INFINITY) ||
           (std::isfinite(next) && next <= t + interval * (1 + 1e-9));
  };
  if (!fits(c.next_history, prm_.history_interval, false) ||
      !fits(c.next_frame, prm_.vtu_interval, false) ||
      !fits(c.next_snapshot, prm_.snapshot_interval, push_ != nullptr))
    throw InputError(checkpoint +
                     ": its next history row, frame or snapshot time does not fit "
                     "the case's intervals at t = " +
                     number_text(t) + " s; the file is damaged");
  if (push_) push_->resume(c.push);
  count_steps();  // with the restored time step
  initial_energy_ = c.initial_energy;
  initial_positions_ = std::move(c.initial_positions);
  find_tracked_bodies();
  next_history_ = c.next_history;
  next_frame_ = c.next_frame;
  next_snapshot_ = c.next_snapshot;
  warned_critical_ = c.warned_critical;
  frame_ = static_cast<int>(c.frame_times.size());
  loop_start_step_ = c.loop_start_step;
  earlier_wall_seconds_ = c.wall_seconds;
  earlier_loop_seconds_ = c.loop_seconds;
  part_first_step_ = step;
  try {
    open_outputs(&c);  // the histories cut back to the lengths the checkpoint counted
  } catch (const InputError& e) {
    throw InputError(checkpoint + ": " + e.what());
  }
  remove_outputs_after(step);
  if (c.coupled != (subgrade_ != nullptr))
    throw InputError(prm_.file + ": the checkpoint is of a " + (c.coupled ? "coupled" : "DEM") +
                     " run and the case's mode is " + prm_.mode +
                     "; valid: the mode the run started with");
  if (subgrade_) {
    try {  // its state fitted to the FE interface, its histories cut back
      subgrade_->start(*sim_, formation_mesh_, sleeper_mesh(), out_, &c.coupling, c.frame_times);
    } catch (const InputError& e) {
      throw InputError(checkpoint + ": " + e.what());
    }
  }
  std::cout << "trackbed: resuming " << prm_.file << " in " << out_ << " at t = " << sim_->time()
            << " s (step " << step << " of about " << total_steps_ << "), "
            << sim_->particles().num_elements() << " sphere elements, " << sim_->team_size()
            << " threads" << std::endl;
}

void DemRun::remove_outputs_after(long step) {
  // An interrupted run wrote a last frame and snapshot after its checkpoint; the resumed run
  // writes its own. Files of frames from frame_ on and snapshots after `step` go. A fresh run
  // (step -1, frame_ 0) clears them all: a pilot zone reads every snapshot of a folder.
  for (const auto& entry : fs::directory_iterator(fs::path(out_) / "vtu")) {
    const std::string name = entry.path().filename().string();
    const std::size_t dash = name.rfind('-');
    if (dash != std::string::npos && std::atoi(name.c_str() + dash + 1) >= frame_)
      fs::remove(entry.path());
  }
  if (fs::is_directory(fs::path(out_) / "fem"))
    for (const auto& entry : fs::directory_iterator(fs::path(out_) / "fem")) {
      const std::string name = entry.path().filename().string();  // fem_NNNNN[.RRRR].(p)vtu
      if (name.rfind("fem_", 0) == 0 && std::atoi(name.c_str() + 4) >= frame_)
        fs::remove(entry.path());
    }
  for (const auto& entry : fs::directory_iterator(fs::path(out_) / "snapshots")) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("state-", 0) == 0 && std::atol(name.c_str() + 6) > step)
      fs::remove(entry.path());
  }
}

int DemRun::loop_and_finish() {
  catch_stop_signals();
  loop_start_ = last_progress_ = last_checkpoint_ = Clock::now();
  try {
    advance();
  } catch (const std::exception& e) {
    // Keep what the run wrote: the histories up to the failure explain it.
    finish("failed: " + std::string(e.what()));
    throw;
  }
  const bool interrupted = stop_signal() != 0;
  if (interrupted && prm_.checkpoint_interval > 0) write_checkpoint();
  finish(interrupted ? "interrupted" : "finished");
  if (interrupted && prm_.checkpoint_interval > 0)
    std::cout << "trackbed: interrupted at t = " << sim_->time()
              << " s; continue with: trackbed resume " << out_ << std::endl;
  return interrupted ? 130 : 0;
}

void DemRun::write_checkpoint() {
  RunCheckpoint c;
  c.case_file = absolute_path(prm_.file);
  c.case_fingerprint = prm_.fingerprint;
  c.version = TRACKBED_VERSION;
  c.threads = omp_get_max_threads();
  c.engine = sim_->engine_state();
  c.next_history = next_history_;
  c.next_frame = next_frame_;
  c.next_snapshot = next_snapshot_;
  for (const auto& [t, file] : pvd_particles_->entries()) c.frame_times.push_back(t);
  for (auto* f : {series_->walls.get(), series_->energy.get(), series_->bodies.get()})
    c.history_bytes.push_back(f->flushed_size());
  c.warned_critical = warned_critical_;
  c.loop_start_step = loop_start_step_;
  const auto now = Clock::now();
  c.wall_seconds = earlier_wall_seconds_ + std::chrono::duration<double>(now - start_).count();
  c.loop_seconds = earlier_loop_seconds_ + std::chrono::duration<double>(now - loop_start_).count();
  c.initial_energy = initial_energy_;
  c.initial_positions = initial_positions_;
  c.has_push = push_ != nullptr;
  if (push_) c.push = push_->progress();
  c.coupled = subgrade_ != nullptr;
  if (subgrade_) c.coupling = subgrade_->progress();
  write_run_checkpoint(out_ + "/" + kCheckpointFile, c);
  last_checkpoint_ = Clock::now();
}

void DemRun::advance() {
  const double dt = sim_->time_step();
  auto running = [&] { return push_ ? !push_->finished() : sim_->step_count() < total_steps_; };
  while (running() && stop_signal() == 0) {
    if (sim_->step_count() == prm_.warmup_steps && prm_.warmup_steps > 0) {
      loop_start_ = Clock::now();
      loop_start_step_ = sim_->step_count();
      earlier_loop_seconds_ = 0;
    }
    if (push_) {
      const bool held = !push_->pushing();
      push_->control(*sim_, !subgrade_ || subgrade_->settled());
      // A push test's snapshots run on the push's clock: one where the push starts, the bed at
      // rest under the sleeper (a pilot zone's reference, docs/zones.md#pilot-zones), then one
      // every interval.
      if (held && push_->pushing() && prm_.snapshot_interval > 0) {
        write_snapshot();
        next_snapshot_ = sim_->time() + prm_.snapshot_interval;
      }
    }
    sim_->step();
    if (subgrade_) subgrade_->after_step();
    const double t = sim_->time() + 0.5 * dt;  // tolerant of round-off in the clock
    if (prm_.history_interval > 0 && t >= next_history_) {
      const dem::EnergyBudget now = write_history();
      for (const auto* f : {series_->walls.get(), series_->energy.get(), series_->bodies.get()})
        f->require_written();  // a full disk or a read-only file system stops the run here
      next_history_ += prm_.history_interval;
      check_health(now);
    }
    if (t >= next_frame_) {
      write_frame();
      next_frame_ += prm_.vtu_interval;
    }
    if (t >= next_snapshot_) {
      write_snapshot();
      next_snapshot_ += prm_.snapshot_interval;
    }
    if (std::chrono::duration<double>(Clock::now() - last_progress_).count() >=
        prm_.progress_interval) {
      check_health(sim_->energy());
      if (push_) total_steps_ = std::lround(push_->expected_end(*sim_) / dt);
      report_progress(false);
    }
    if (prm_.checkpoint_interval > 0 &&
        std::chrono::duration<double>(Clock::now() - last_checkpoint_).count() >=
            prm_.checkpoint_interval) {
      check_health(
          sim_->energy());  // a checkpoint is always of a sound state: the one a failed run keeps
      write_checkpoint();
    }
    if (sim_->step_count() == test_signal_.first) std::raise(test_signal_.second);
  }
  loop_seconds_ =
      earlier_loop_seconds_ + std::chrono::duration<double>(Clock::now() - loop_start_).count();
  check_health(sim_->energy());
}

void DemRun::check_health(const dem::EnergyBudget& now) const {
  sim_->check_finite();
  sim_->check_energy(initial_energy_, now);
}

void DemRun::finish(const std::string& status) {
  const bool finished = status == "finished";
  if (loop_seconds_ == 0)
    loop_seconds_ =
        earlier_loop_seconds_ + std::chrono::duration<double>(Clock::now() - loop_start_).count();
  report_progress(true);
  // The last state in the histories and frames, unless the loop has just written it.
  const double t = sim_->time(), dt = sim_->time_step();
  if (!written_this_step(next_history_, prm_.history_interval, t, dt)) write_history();
  // A blown-up state (NaN) is not worth a frame or a snapshot. An interrupted run's last frame
  // goes when it is resumed (a frame after its checkpoint); its state is in the checkpoint, and
  // a snapshot would stay behind as a file the uninterrupted run does not have.
  if ((finished || status == "interrupted") &&
      !written_this_step(next_frame_, prm_.vtu_interval, t, dt))
    write_frame();
  if (finished) write_snapshot();
  // A failed run keeps the histories it could write; one whose writing failed goes.
  for (auto* f : {series_->walls.get(), series_->energy.get(), series_->bodies.get()})
    if (finished || status == "interrupted" || f->written()) f->commit();
  if (subgrade_) subgrade_->finish(finished || status == "interrupted");
  if (push_) push_->write_csv(out_ + "/push.csv");
  write_summary(status);
  if (prm_.plot && finished) make_plot();
  // A finished run needs no checkpoint (and it is the largest file of the folder).
  if (finished) {
    fs::remove(fs::path(out_) / kCheckpointFile);
    remove_start_record(out_);
  }
  std::cout << "trackbed: results in " << out_ << (finished ? "" : " (" + status + ")")
            << std::endl;
}

void DemRun::write_summary(const std::string& status) {
  const auto& p = sim_->particles();
  const dem::EnergyBudget e = sim_->energy();
  const double wall =
      earlier_wall_seconds_ + std::chrono::duration<double>(Clock::now() - start_).count();
  const long timed = sim_->step_count() - loop_start_step_;
  const double scale = std::max({std::abs(e.kinetic) + e.strain, e.dissipated(),
                                 std::abs(e.gravity_work), std::abs(e.wall_work), 1e-300});
  std::vector<SummaryItem> items = {
      {"bodies", "bodies", "", double(p.num_bodies())},
      {"clumps", "clumps", "", double(p.num_clumps())},
      {"elements", "sphere elements", "", double(p.num_elements())},
      {"contacts", "contacts (last step)", "", double(sim_->num_contacts())},
      {"steps", "steps", "", double(sim_->step_count())},
      {"time_step_s", "time step", "s", sim_->time_step()},
      {"critical_time_step_s", "critical time step", "s", sim_->critical_timestep()},
      {"simulated_time_s", "simulated time", "s", sim_->time()},
      {"wall_time_s", "wall time", "s", wall},
      {"timed_steps", "timed steps (after warm-up)", "", double(timed)},
      {"loop_time_s", "loop time of the timed steps", "s", loop_seconds_},
      {"sphere_steps_per_s", "sphere-steps per second", "",
       loop_seconds_ > 0 ? p.num_elements() * timed / loop_seconds_ : 0.0},
      {"threads", "threads", "", double(sim_->team_size())},
      {"neighbor_builds", "neighbour list builds", "", double(sim_->num_neighbor_builds())},
      {"kinetic_energy", "kinetic energy", "J", e.kinetic},
      {"strain_energy", "strain energy", "J", e.strain},
      {"dissipated_energy", "dissipated energy", "J", e.dissipated()},
      {"energy_balance_error", "energy balance error (relative)", "",
       prm_.track_energy ? (e.total() - initial_energy_.total()) / scale : NAN},
      {"max_particle_contact_force_n", "max particle-particle contact force", "N",
       sim_->max_particle_contact_force()},
      {"max_wall_contact_force_n", "max particle-wall contact force", "N",
       sim_->max_wall_contact_force()},
  };
  for (const auto& w : sim_->planes())
    items.push_back({"wall_force_z_" + w.name, "wall " + w.name + " force z", "N", w.force.z()});
  for (const auto& m : sim_->meshes())
    for (int k = 0; k < 3; ++k)
      items.push_back({"mesh_force_" + std::string(1, "xyz"[k]) + "_" + m.name,
                       "mesh " + m.name + " force " + "xyz"[k], "N", m.contact_force[k]});
  // The tracked bodies' mass properties (their centres are in history/bodies.csv): a clump's
  // are those of its pebbles' union, not of a sphere of its size.
  for (int b : tracked_) {
    const std::string id = std::to_string(p.id[b]), label = "body " + id;
    items.push_back({"body_" + id + "_elements", label + " sphere elements", "",
                     double(p.first_element[b + 1] - p.first_element[b])});
    items.push_back({"body_" + id + "_mass_kg", label + " mass", "kg", p.mass[b]});
    for (int k = 0; k < 3; ++k)
      items.push_back({"body_" + id + "_principal_inertia_" + std::to_string(k + 1) + "_kg_m2",
                       label + " principal inertia " + std::to_string(k + 1), "kg m^2",
                       p.inertia[b][k]});
  }
  if (push_)
    for (const auto& i : push_->summary()) items.push_back(i);
  if (subgrade_) {
    for (const auto& i : subgrade_->summary()) items.push_back(i);
    items.push_back({"fe_coupling_share", "share of the wall time in FE and coupling", "",
                     subgrade_->fe_seconds() / wall});
  }

  dem::AtomicFile json(out_ + "/summary.json");
  json.stream() << std::setprecision(10) << "{\n  \"case\": \""
                << json_escape(absolute_path(prm_.file)) << "\",\n  \"status\": \""
                << json_escape(status) << "\"";
  for (const auto& i : items) {
    json.stream() << ",\n  \"" << i.key << "\": ";
    if (std::isfinite(i.value))
      json.stream() << i.value;
    else
      json.stream() << "null";
  }
  json.stream() << "\n}\n";
  json.commit();

  dem::AtomicFile txt(out_ + "/summary.txt");
  txt.stream() << "trackbed summary: " << absolute_path(prm_.file) << " (" << status << ")\n";
  for (const auto& i : items)
    txt.stream() << "  " << std::left << std::setw(40) << i.label << std::right << std::setw(16)
                 << std::setprecision(6) << i.value << " " << i.unit << "\n";
  txt.commit();
}

void DemRun::make_plot() {
  run_plot_script("plot_history.py", out_);
  if (push_) run_plot_script("plot_push.py", out_, "push-plot.log");
  if (push_) run_plot_script("plot_displacement.py", out_, "displacement-plot.log");
  run_plot_script("plot_force_chains.py", out_, "force-chains-plot.log");
}

}  // namespace trackbed::cases
