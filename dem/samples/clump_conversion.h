// Converting the balls of a sample inside a zone to clumps (the multi-layer shape model): each
// ball becomes a clump of a library template whose pebbles have the ball's volume, with the
// ball's mass, at the ball's centre, in a uniformly random orientation; the overlaps the angular
// shapes make with their neighbours are relaxed by growing the clumps (docs/samples.md,
// "Converting balls to clumps"):
//
//   run():  replace()   balls in the zone -> clumps in the orientation that fits largest among
//                       their neighbours, shrunk to that fit (clump_fitting.h)
//           grow()      grow every clump to full size over growth_time under gravity, the
//                       friction scaled by growth_friction_factor, the sleeper held by its servo
//           settle()    friction restored, the model run to equilibrium, the sleeper seated;
//                       optionally in two stages: densification without the clumps' rolling
//                       resistance, then equilibrium with it
//
// A ball of sieve size a becomes a clump whose sieve size is that of its pebbles
// (clump_sieve_size): the volume and mass are kept exactly, the sieve size changes by the
// template's shape.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "dem/io/engine_state.h"
#include "dem/io/sample.h"
#include "dem/samples/section_model.h"
#include "dem/samples/settling.h"
#include "dem/samples/template_library.h"
#include "dem/samples/zone.h"

namespace trackbed::dem {

// The growth's step: the critical step of the full-size clumps where their balls are, fixed (a
// probe model); or that of the model as it stands, renewed at every check.
enum class GrowthStep { probe, renewed };

// The stages of a conversion, in their order (densification only when the settling is split).
enum class ConversionStage : int { growth, densification, equilibrium };
constexpr int kConversionStages = 3;
std::string to_string(ConversionStage s);

struct ConversionSettings {
  double growth_time = 0.1;  // s simulated over which the clumps grow to full size
  int growth_interval = 50;  // steps between two growth increments
  GrowthStep growth_step = GrowthStep::probe;
  // The renewed growth step in units of critical_fraction x the bed's critical step; above 1 the
  // bodies that need it are density scaled to take it, renewed at every check, as the settling's
  // (docs/samples.md, "Time step"). A probe step takes 1 only.
  double growth_step_factor = 1;
  double growth_friction_factor = 1;  // ballast friction (and rolling) factor while growing
  int orientation_trials = 16;        // random orientations tried per clump (clump_fitting.h)
  double preparation_damping = 0.3;   // normal dashpot ratio while converting (section_model.h)
  // A converted bed settles more slowly than a deposited ball bed (its clumps were pushed apart
  // while growing): 1e-3 takes about half the time of 1e-4 (docs/samples.md, "Equilibrium").
  double equilibrium_ratio = 1e-3;
  double max_stage_time = 4.0;     // s simulated for the final settling at most
  double critical_fraction = 0.8;  // of the critical step of the converted model
  // The final settling's step in units of critical_fraction x the grown bed's critical step;
  // above 1 the bodies that need it are density scaled to take it (Simulation::
  // scale_density_for_step), their scaling renewed at every check.
  double settling_step_factor = 1;
  // Above 0, the final settling is split in two (docs/samples.md, "Densify without the clumps'
  // rolling friction, then settle with it"): down to this ratio without the clumps' rolling
  // resistance (densification: the clumps slide and roll into place freely), then to
  // equilibrium_ratio with the clumps given the ballast's rolling friction, which the cases run
  // them with. 0: one stage, without it (the paper's Table 2 gives rolling resistance to balls
  // only).
  double densification_ratio = 0;
  double skin = 0.004;
  std::uint64_t seed = 1;
};

struct ConversionReport {
  std::vector<StageReport> stages;
  int converted = 0;
  double start_scale_min = 1, start_scale_mean = 1;  // growth start factors
};

// Where an interrupted conversion stands, at a check of one of its stages, with the engine's
// state there: enough to go on as the uninterrupted conversion would (checkpoints,
// cases/runs/sample_checkpoint.h).
struct ConversionCheckpoint {
  ConversionStage stage = ConversionStage::growth;
  StagePoint point;
  std::vector<double> criterion_memory;  // the equilibrium stage's (SettleCriterion::memory)
  std::vector<StageReport> done;         // the stages finished before
  EngineState engine;
  std::string file;  // the checkpoint it was read from: a state that does not fit names it
};

class ClumpConversion {
 public:
  // The section and materials are those the base sample was built with (its info lines).
  ClumpConversion(const Sample& base, ZonePtr zone, std::vector<LibraryTemplate> templates,
                  ConversionSettings settings);

  // How many of the base sample's bodies it turns into clumps: the balls whose centre lies in the
  // zone.
  int balls_in_zone() const;
  StageRunner& runner() { return runner_; }
  // The model of the finished sample (after run()), for its outputs.
  const Simulation& simulation() const { return *sim_; }
  // Converts; from the checkpoint of an interrupted conversion of the same input when given (the
  // replacement, deterministic, is made again; the stage goes on from the saved state).
  Sample run(ConversionCheckpoint* from = nullptr);
  // The conversion's state at a check of its running stage, for runner().at_check.
  ConversionCheckpoint checkpoint(const StagePoint& at) const;
  const ConversionReport& report() const { return report_; }

 private:
  struct Growing {
    int first_element;              // of the body (indices after setup)
    std::vector<SphereShape> full;  // its elements at full size, in its principal frame
    double start_scale;
  };
  void replace();
  // The engine state and the equilibrium criterion's memory of checkpoint `from`; InputError
  // naming its file when they do not fit the model.
  void restore(ConversionCheckpoint& from);
  void grow(ConversionCheckpoint* from);
  void settle(ConversionCheckpoint* from);
  // Gives the settling model step dt for the stage judged by `c`, of which `steps_done` steps are
  // done: density scaled for it (settling_step_factor above 1), now and at every check.
  void take_settling_step(SettleCriterion& c, double dt, long steps_done);
  void set_growth(double fraction);

  const Sample& base_;
  ZonePtr zone_;
  std::vector<bool> converts_;  // per body of the base sample: turned into a clump
  std::vector<LibraryTemplate> templates_;
  std::vector<double> pebble_volume_;      // per template: volume of its pebbles' union
  std::vector<double> pebble_sieve_size_;  // per template: sieve size of its pebbles
  ConversionSettings settings_;
  SectionModel model_;
  StageRunner runner_;
  ConversionReport report_;
  Particles particles_;
  std::map<std::int64_t, int> shape_of_id_;
  std::map<std::int64_t, double> sieve_size_of_id_;
  std::map<std::int64_t, double> start_scale_of_id_;
  std::vector<Growing> growing_;
  std::unique_ptr<Simulation> sim_;
  ConversionStage stage_ = ConversionStage::growth;  // running
  SettleCriterion settled_;                          // the equilibrium stage's criterion
};

}  // namespace trackbed::dem
