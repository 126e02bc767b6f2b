// A standalone DEM run (mode = dem): builds the model a case file describes, runs it with a
// progress line, and writes the results folder:
//   history/walls.csv, history/energy.csv, history/bodies.csv   time series
//   particles.pvd, contacts.pvd, walls.pvd (+ vtu/)              ParaView
//   snapshots/state-NNNNNNNNN.h5                                    HDF5 model state
//   summary.json, summary.txt, plot.png                          what a person opens first
#pragma once

#include <chrono>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "cases/case_parameters.h"
#include "cases/push_test.h"
#include "dem/contact_state.h"
#include "dem/sample.h"
#include "dem/simulation.h"
#include "dem/vtu_writer.h"

namespace trackbed::cases {

class DemRun {
 public:
  explicit DemRun(CaseParameters parameters);
  ~DemRun();
  // Returns the process exit status: 0 finished, 130 interrupted by a signal.
  int run();

 private:
  void build_model();
  // The bodies of particles/sample file with the case's material indices, and the sample's
  // contact springs renumbered to the model's walls (restored after setup).
  // With particles/clump material, the clumps get that material.
  dem::Particles sample_particles(const dem::Sample& sample, const dem::MaterialTable& materials);
  void add_sample_walls(const dem::Sample& sample);
  void open_outputs();
  void write_history();
  void write_frame();
  void write_snapshot();
  void report_progress(bool last);
  void advance();  // the time loop with its outputs
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
  std::unique_ptr<dem::PvdCollection> pvd_particles_, pvd_contacts_, pvd_walls_;
  std::vector<dem::Vec3> initial_positions_;
  std::vector<int> tracked_;  // body indices of output/tracked bodies
  dem::ContactState sample_contacts_;
  std::vector<int> sample_material_;  // case material of each sample material
  int frame_ = 0;
  bool warned_critical_ = false;

  using Clock = std::chrono::steady_clock;
  Clock::time_point start_, last_progress_, loop_start_;
  long loop_start_step_ = 0;
  double loop_seconds_ = 0;
  double next_history_ = 0, next_frame_ = 0, next_snapshot_ = 0;
  dem::EnergyBudget initial_energy_;
};

}  // namespace trackbed::cases
