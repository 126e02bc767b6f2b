// The elastic subgrade of a coupled run (mode = coupled): the ballast bed of a track-section
// sample rests on the FE continuum of the case's `fem` subsection instead of the rigid base plane,
// through the quasi-static staggered scheme of its `coupling` subsection (docs/coupling.md).
//
// The FE body is distributed over the MPI processes; the DEM runs on process 0 with its OpenMP
// threads. Process 0 leads: before each collective step (an exchange, an FE frame, a checkpoint's
// FE state) it tells the other processes, which serve() until the run ends, what comes next.
//
// Outputs beside the DEM run's (process 0):
//   history/interface.csv    one row per exchange: loads, balance, residuals, relaxation, FE solve
//                            (no timings: a resumed run writes the same bytes)
//   history/settlement.csv   one row per exchange: sleeper and formation settlement
//   fem.pvd (+ fem/)         the FE body with each ParaView frame: displacement, stress
//   interface.pvd (+ vtu/interface-NNNNNN.vtu)  the formation wall: displacement, load, traction
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "cases/parameters/case_parameters.h"
#include "cases/reports/report_support.h"
#include "common/track_section.h"
#include "coupling/quasi_static_scheme.h"
#include "coupling/subgrade.h"
#include "dem/engine/simulation.h"
#include "dem/io/atomic_file.h"
#include "dem/io/vtu_writer.h"

namespace trackbed::cases {

class SubgradeCoupling {
 public:
  // What a checkpoint keeps of the coupling, so that a resumed run goes on bit for bit.
  struct Progress {
    std::vector<double> fe_displacement;  // FE dofs (ElasticBody::displacement_dofs)
    coupling::QuasiStaticState scheme;
    std::vector<dem::Vec3> interval_origin;  // the wall's displacement at the interval's start
    std::vector<long> history_bytes;         // interface.csv, settlement.csv
    double interface_work = 0, strain_energy = 0, fe_seconds = 0, sleeper_z0 = 0;
  };

  // Builds the subgrade under the ballast bed of `section` (the sample's). Collective over
  // MPI_COMM_WORLD; InputError for bad `fem` or `coupling` parameters.
  SubgradeCoupling(const CaseParameters& prm, const TrackSection& section);
  // The leader releases the processes that serve it, if the run has not.
  ~SubgradeCoupling();
  SubgradeCoupling(const SubgradeCoupling&) = delete;
  SubgradeCoupling& operator=(const SubgradeCoupling&) = delete;

  bool leader() const { return rank_ == 0; }
  // One line for the run's log: cells, dofs, processes, formation vertices, interval.
  std::string description() const;
  // The formation wall as a deformable DEM mesh of `material`, at the reference positions.
  dem::MeshBody formation_body(int material) const;

  // --- The leader (process 0), in the order a run calls them ---
  // After Simulation::setup: the scheme on the formation mesh `mesh` of `sim`; `sleeper` is the
  // mesh whose settlement is reported (-1: none). Opens the outputs in `out`: new, or continued
  // after `progress` with the run's ParaView frames at `frame_times` (a resumed run, whose FE
  // state and scheme it restores). Collective.
  void start(dem::Simulation& sim, int mesh, int sleeper, const std::string& out,
             const Progress* progress = nullptr, const std::vector<double>& frame_times = {});
  // After each DEM step: an exchange when the step count is a multiple of the interval.
  void after_step();
  // The scheme has converged at the last exchange (a push test holds until it has).
  bool settled() const { return scheme_->converged(); }
  // The FE body and the formation wall of ParaView frame k at `time`. Collective.
  void write_frame(int k, double time);
  // The coupling's state for a checkpoint. Collective (the FE state is gathered).
  Progress progress();
  std::vector<SummaryItem> summary() const;
  // Wall seconds in FE solves and the coupling's maps so far (a resumed run's earlier parts too).
  double fe_seconds() const { return fe_seconds_; }
  // Releases the serving processes and commits the histories; a run that is not `sound` (it
  // failed) drops a history whose writing failed.
  void finish(bool sound);

  // --- The other processes ---
  // Takes part in every collective step the leader announces, until it finishes.
  void serve();

 private:
  enum class Command : int { finish, start, exchange, frame, state, restore };
  void announce(Command command, int argument = 0);
  void exchange();
  void restore(const Progress& progress);
  void write_interface_frame(int k);
  void open_outputs(const Progress* progress, const std::vector<double>& frame_times);
  void write_histories(const coupling::ExchangeReport& report);
  // Area-weighted mean of -u_z over the formation, m.
  double mean_formation_settlement() const;

  int rank_ = 0;
  std::string out_;
  std::unique_ptr<coupling::Subgrade> subgrade_;
  coupling::QuasiStaticParameters parameters_;
  std::unique_ptr<coupling::QuasiStaticScheme> scheme_;
  bool released_ = false;

  // The leader's.
  dem::Simulation* sim_ = nullptr;
  int sleeper_ = -1;
  std::vector<double> vertex_area_;  // a third of the area of the triangles at each vertex
  std::unique_ptr<dem::AtomicFile> interface_csv_, settlement_csv_;
  std::unique_ptr<dem::PvdCollection> pvd_fem_, pvd_interface_;
  std::vector<dem::Vec3> interval_origin_;
  double interface_work_ = 0, strain_energy_ = 0, fe_seconds_ = 0, sleeper_z0_ = 0;
  coupling::ExchangeReport last_;
};

}  // namespace trackbed::cases
