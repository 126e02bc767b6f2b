// A DEM run: standalone (mode = dem), or on an FE subgrade (mode = coupled, subgrade_coupling.h,
// whose outputs it adds). Builds the model a case file describes, runs it with a
// progress line, and writes the results folder:
//   history/walls.csv, history/energy.csv, history/bodies.csv   time series
//   particles.pvd, contacts.pvd, walls.pvd (+ vtu/)              ParaView
//   snapshots/state-NNNNNNNNN.h5                                    HDF5 model state
//   summary.json, summary.txt, plot.png                          what a person opens first
//   checkpoint.h5          the state to resume from (run_checkpoint.h), every `checkpoint
//                          interval` of wall time and on interruption; removed when it finishes
#pragma once

#include <chrono>
#include <fstream>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "cases/parameters/case_parameters.h"
#include "cases/runs/push_test.h"
#include "cases/runs/run_checkpoint.h"
#include "cases/runs/subgrade_coupling.h"
#include "dem/engine/contact_state.h"
#include "dem/engine/simulation.h"
#include "dem/io/sample.h"
#include "dem/io/vtu_writer.h"

namespace trackbed::cases {

class DemRun {
 public:
  explicit DemRun(CaseParameters parameters);
  ~DemRun();
  // Returns the process exit status: 0 finished, 130 interrupted by a signal.
  int run();
  // Continues an interrupted run of the same case from its checkpoint, in its results folder
  // (the parameters' output folder); the same exit statuses.
  int resume(RunCheckpoint checkpoint);

 private:
  // The model (dem_run_model.cc): the case's materials, bodies, walls and meshes, the sample's.
  void build_model();
  dem::MaterialTable make_materials() const;
  // The sample's bodies (if any), the particle file's and the generator's.
  dem::Particles make_particles(const dem::Sample* sample, const dem::MaterialTable& materials);
  // The sample's plane walls the run keeps, then the case's.
  void add_planes(const dem::Sample* sample);
  void add_mesh(const MeshParameters& m, const dem::Sample* sample);
  // mode = coupled: the subgrade under the sample's section (first, so that the MPI processes
  // that serve it build it with this one); its formation replaces the sample's base plane.
  void make_subgrade(const dem::Sample& sample);
  // The sample's plane walls the run keeps (all but a coupled run's base), in order.
  std::vector<int> kept_sample_planes(const dem::Sample& sample) const;
  // The mesh whose settlement a coupled run reports: the pushed one, else one named "sleeper".
  int sleeper_mesh() const;
  // The bodies of particles/sample file with the case's material indices, and the sample's
  // contact springs renumbered to the model's walls (restored after setup).
  // With particles/clump material, the clumps get that material.
  dem::Particles sample_particles(const dem::Sample& sample, const dem::MaterialTable& materials);
  // Setup and the run's start (fresh), or the checkpoint's state (resumed).
  void start_fresh();
  void start_from(RunCheckpoint& c);
  // The push test of the case, if any (after build_model).
  void make_push_test();
  // The run's step count from its end time or push test and the time step (set up or restored);
  // InputError beyond 1e12 steps.
  void count_steps();
  // Opens the histories and ParaView collections: new, or continued after `c`'s bytes and frames.
  void open_outputs(const RunCheckpoint* c = nullptr);
  int loop_and_finish();
  void write_checkpoint();
  void find_tracked_bodies();
  // Removes the frames and snapshots an interrupted run wrote after its checkpoint at `step`.
  void remove_outputs_after(long step);
  // One row of each history file; returns the energy budget of that state (the health check
  // after it takes it, rather than a second pass over the contacts).
  dem::EnergyBudget write_history();
  void write_frame();
  // The ParaView file of one kind (particles, contacts, walls) of frame k, relative to out_.
  static std::string frame_file(const char* kind, int k);
  void write_snapshot();
  void report_progress(bool last);
  void advance();  // the time loop with its outputs
  // Stops a run that has blown up (non-finite state, energy from nowhere): throws with the reason.
  // `now` is sim_->energy() of the present state.
  void check_health(const dem::EnergyBudget& now) const;
  void finish(const std::string& status);
  void write_summary(const std::string& status);
  void make_plot();

  CaseParameters prm_;
  std::unique_ptr<dem::Simulation> sim_;
  std::string out_;
  long total_steps_ = 0;

  struct Series;
  std::unique_ptr<Series> series_;
  std::unique_ptr<PushTest> push_;
  std::unique_ptr<SubgradeCoupling> subgrade_;
  int formation_mesh_ = -1;
  std::unique_ptr<dem::PvdCollection> pvd_particles_, pvd_contacts_, pvd_walls_;
  std::vector<dem::Vec3> initial_positions_;
  std::vector<int> tracked_;  // body indices of output/tracked bodies
  dem::ContactState sample_contacts_;
  std::vector<int> sample_material_;  // case material of each sample material
  int frame_ = 0;
  bool warned_critical_ = false;

  using Clock = std::chrono::steady_clock;
  Clock::time_point start_, last_progress_, loop_start_, last_checkpoint_;
  long loop_start_step_ = 0;
  double loop_seconds_ = 0;
  // Wall and loop seconds of the run's earlier parts (a resumed run: up to its checkpoint).
  double earlier_wall_seconds_ = 0, earlier_loop_seconds_ = 0;
  long part_first_step_ = 0;                 // the step this part of the run started at
  std::pair<long, int> test_signal_{-1, 0};  // step, signal (TRACKBED_TEST_SIGNAL)
  double next_history_ = 0, next_frame_ = 0, next_snapshot_ = 0;
  dem::EnergyBudget initial_energy_;
};

}  // namespace trackbed::cases
