// Building the ball sample of a track section (docs/samples.md, "Building a sample"):
//
//   run():  draw_stones()      sizes from the sieve grading, enough to fill the deposition box
//           calibrate()        the deposition friction that gives the target porosity, from
//                              depositions of a small box (porosity_calibration.h)
//           deposit()          a loose cloud falls and settles under gravity with that friction,
//                              between the base, the crib walls and vertical mould walls at the
//                              foot of the slopes; then the friction is restored
//          [seat_in_mould()]   optionally first: level the crest, clear the sleeper's box, and
//                              seat the sleeper in the mould at a reduced friction, so that the
//                              stones under it slide into place; then restore the friction
//           trim()             keep the stones inside the design profile (cut the slopes, level
//                              the crest) and clear the sleeper's box; remove the mould
//           seat_sleeper()     place the sleeper on the bed (or keep it where it was seated),
//                              press it in with a tamping load and let it settle under its weight
//                              (servo) to equilibrium
//
// Every stage ends on the mean unbalanced force ratio (settling.h). A build takes checkpoints at
// the checks of its stages (checkpoint()) and goes on from one (run(from)) bit for bit as the
// uninterrupted build, with the same number of threads.
#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "dem/io/engine_state.h"
#include "dem/io/sample.h"
#include "dem/samples/grading.h"
#include "dem/samples/porosity_calibration.h"
#include "dem/samples/section_model.h"
#include "dem/samples/settling.h"

namespace trackbed::dem {

struct SampleBuildSettings {
  TrackSection section;
  SectionMaterials materials;
  SieveTable grading = en13450_ballast_grading();
  double target_porosity = 0.40;  // under the sleeper, at the end of compaction
  // Deposited volume beyond the section's box up to the crest, so that the settled bed stands
  // above the crest everywhere before it is levelled.
  double overfill = 0.08;
  double cloud_solid_fraction = 0.30;  // of the loose cloud (random addition reaches ~0.35)
  double deposition_damping = 0.3;     // ballast local damping while the cloud falls
  double preparation_damping = 0.3;    // normal dashpot ratio of every stage (section_model.h)
  // Ballast friction factor during deposition; < 0: calibrated for the target porosity.
  double deposition_friction = -1;
  CalibrationSettings calibration;  // factors tried; box and bed size are set from the section
  // The sleeper is pressed into the bed with this many times its weight before it is seated
  // under its weight (1: no tamping).
  double tamping_load_factor = 1;
  // > 0: the sleeper is first seated while the bed is still in its mould, with the ballast
  // friction scaled by this factor, before the friction is restored and the slopes are cut
  // (docs/samples.md, "Seating in the mould"); 0: seated on the finished profile only.
  double mould_seating_friction = 0;
  // At most this long (s simulated): at a low friction the bed creeps under the sleeper for as
  // long as it carries it, and the stage may end here without meeting the seating criterion.
  double mould_seating_time = 1.0;
  // In the mould the sleeper is let go from its seating servo once the bed carries no more than
  // its weight (at once, as it starts clear of the stones), and sinks under its weight as the bed
  // gives way; false keeps it on the servo, whose slow gain let it bear at most 38 % of its
  // weight there in the full-size section (docs/samples.md, "Seating in the mould").
  bool mould_sleeper_free = true;
  double stage_ratio = 1e-3;        // equilibrium of the intermediate stages
  double equilibrium_ratio = 1e-4;  // equilibrium of the finished sample
  double max_stage_time = 4.0;      // s simulated per stage at most
  double time_step = 0;             // s; 0: critical_fraction x the critical step of each stage
  double critical_fraction = 0.35;
  double skin = 0.004;
  std::uint64_t seed = 1;
};

// The record of a build, for the summary.
struct BuildReport {
  std::vector<StageReport> stages;
  int stones_drawn = 0;
  std::vector<CalibrationPoint> calibration;  // empty when the friction was given
  double deposition_friction_factor = 1;
  double porosity = 0;  // under the sleeper, after deposition
};

// The stages of a ball build that step the section's model, in their order (a build skips those
// its settings leave out); a checkpoint names the one it was taken in.
enum class BuildStage : int {
  deposition,               // the cloud falls, at the deposition friction
  settling,                 // and settles
  friction_restored,        // the ballast's friction back (seated on the profile)
  mould_seating,            // the sleeper seated in the mould at a reduced friction
  mould_friction_restored,  // the ballast's friction back, the sleeper on the bed
  tamping,                  // the trimmed bed under the sleeper pressed in
  seating,                  // the sleeper seated under its weight: the finished sample
};
constexpr int kBuildStages = 7;
std::string to_string(BuildStage s);

// Where an interrupted ball build stands at a check of one of its stages: what run() needs to go
// on from there. The stones are drawn again from the seed; the calibration is in the report.
struct BuildCheckpoint {
  BuildStage stage = BuildStage::deposition;
  StagePoint point;
  std::vector<double> criterion_memory;  // the stage's (SettleCriterion::memory)
  BuildReport report;                    // the calibration and the stages finished before
  // How far above its design position the sleeper was placed (its mesh is made again there and
  // moved to its saved pose); NaN before it is placed.
  double sleeper_lift = std::numeric_limits<double>::quiet_NaN();
  EngineState engine;
  std::string file;  // the checkpoint it was read from: a state that does not fit names it
};

class SampleBuilder {
 public:
  explicit SampleBuilder(SampleBuildSettings settings);

  StageRunner& runner() { return runner_; }
  // The model of the finished sample (after run()), for its outputs.
  const Simulation& simulation() const { return *sim_; }
  // Builds the ball sample; from the checkpoint of an interrupted build of the same settings when
  // given. Throws InputError for invalid settings or a checkpoint of a stage this build does not
  // have, std::runtime_error if a stage blows up.
  Sample run(BuildCheckpoint* from = nullptr);
  // Whether one of the stages above is running (not the calibration, whose depositions of a
  // small box are made again on resume).
  bool in_stage() const { return in_stage_; }
  // The build's state at a check of its running stage, for runner().at_check.
  BuildCheckpoint checkpoint(const StagePoint& at) const;
  const BuildReport& report() const { return report_; }

 private:
  // The walls and materials of a stage's model.
  struct StageModel {
    StageWalls walls;
    StageMaterials materials;
  };
  StageModel model_of(BuildStage s) const;
  void draw_stones();
  void calibrate();
  void deposit();
  void restore_friction(BuildStage s, double factor);  // from `factor` times the ballast's
  // Whether the sleeper is first seated in the mould (a mould seating friction factor > 0).
  bool seats_in_mould() const { return settings_.mould_seating_friction > 0; }
  void seat_in_mould();
  void seat_sleeper();
  void trimmed_model();
  // The sleeper placed on `p` at its design position, raised clear of the stones (sleeper_lift_).
  MeshBody placed_sleeper(const Particles& p);
  // Enters stage `s`: `make` sets up its model, or, for a build resumed in it, the checkpoint's
  // model is restored. False, with nothing done, for a stage finished before the checkpoint.
  bool begin(BuildStage s, const std::function<void()>& make);
  void restore();
  // Settles the stage entered by begin(), from the checkpoint's point for a resumed one.
  void settle(const std::string& name, const SettleCriterion& c);
  SimulationSettings stage_settings() const;
  double core_porosity(const Particles& p) const;
  void next_stage(const Particles& particles, const StageModel& m,
                  const std::optional<MeshBody>& sleeper = std::nullopt);

  SampleBuildSettings settings_;
  SectionModel model_;
  StageRunner runner_;
  BuildReport report_;
  std::vector<double> sieve_size_;  // per stone id
  std::unique_ptr<Simulation> sim_;
  // The running stage, its criterion (whose memory a checkpoint keeps) and where it started.
  BuildStage stage_ = BuildStage::deposition;
  SettleCriterion criterion_;
  StagePoint start_;
  bool in_stage_ = false;
  double sleeper_lift_ = std::numeric_limits<double>::quiet_NaN();
  BuildCheckpoint* resume_ = nullptr;  // until the build reaches the checkpoint's stage
};

// The box under the sleeper in which a sample's porosity is measured: the sleeper's footprint
// in x, the section length less one largest stone at each crib wall in y, and from one largest
// stone above the base to the sleeper bottom in z.
void porosity_box(const TrackSection& section, double largest_stone, Vec3& lower, Vec3& upper);

}  // namespace trackbed::dem
