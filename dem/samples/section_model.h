// The DEM model of a track section at each stage of a sample build: its materials (with the
// stage's friction and damping), the walls (base, crib walls, and the temporary mould walls at the
// foot of the slopes during deposition) and the sleeper with the degrees of freedom of seating.
// Shared by the ball-sample build (sample_builder.h) and the zone conversion (clump_conversion.h).
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "common/track_section.h"
#include "dem/engine/material.h"
#include "dem/engine/simulation.h"
#include "dem/io/sample.h"
#include "dem/samples/grading.h"
#include "dem/samples/settling.h"

namespace trackbed::dem {

// Material names are fixed, so that a case loading the sample finds them: "ballast" (stones and
// the base), "sleeper", "wall" (crib and mould walls: frictionless by default, since a crib wall
// stands for the symmetry plane halfway to the next sleeper, where no shear acts).
struct SectionMaterials {
  Material ballast, sleeper, wall;
  SectionMaterials();
};

// What a stage changes in the materials.
struct StageMaterials {
  double friction_factor = 1;  // scales the ballast friction (and the ballast-sleeper friction)
  double rolling_factor = 1;   // scales the ballast rolling friction
  std::optional<double> local_damping;  // replaces the ballast local damping
  // Adds the clumps' material (SectionModel::kClumpMaterialName), the ballast without rolling
  // resistance, for the clumps of a conversion: the paper's contact model gives rolling resistance
  // to balls only (Table 2).
  bool clump_material = false;
  // The clumps' material keeps the ballast's rolling friction (scaled by rolling_factor), as the
  // shipped cases run the clumps: a split settling's equilibrium stage (clump_conversion.h).
  bool clump_rolling = false;
};

struct StageWalls {
  bool mould = false;    // vertical walls at x = +-half_base_width (deposition)
  bool sleeper = false;  // the sleeper mesh (from `sleeper_body`, or at its design position)
};

class SectionModel {
 public:
  // `preparation_damping` is the normal dashpot of the ballast's contacts, a fraction of
  // critical (PFC dp_mode 1), added at every stage: it damps the rattling of stones that local
  // damping, acting on the resultant force of a body only, leaves (docs/samples.md,
  // "Equilibrium"). A sample at rest carries no trace of it.
  SectionModel(TrackSection section, SectionMaterials materials, SimulationSettings settings,
               double preparation_damping = 0);

  const TrackSection& section() const { return section_; }
  const SectionMaterials& materials() const { return materials_; }
  MaterialTable material_table(const StageMaterials& stage = {}) const;

  // A model of `particles` with the stage's walls. The sleeper is `sleeper_body` if given (a
  // loaded sample's, at its seated pose) or a box at its design position raised by
  // sleeper_lift(particles); its vertical DOF is a
  // servo holding its weight (PFC's servo, automatic gain), every other DOF fixed.
  Simulation make(Particles particles, const StageWalls& walls, const StageMaterials& stage = {},
                  const std::optional<MeshBody>& sleeper_body = std::nullopt) const;
  // Makes `c` require the sleeper seated, the extra condition of a seating stage: since it was
  // last judged (the checks judge it only where the ratio meets the criterion: one check
  // interval, or more after checks above it) its mean load is within 1 % of what its servo holds
  // (its weight, or a tamping load) and its mean speed is below `max_speed`. Means, not the
  // values at the check: the servo's speed follows the load error of each step, which the
  // contacts of a settling bed scatter from step to step (docs/samples.md, "Equilibrium").
  void require_seated_sleeper(SettleCriterion& c, double max_speed = 1e-4) const;
  // Makes `c` let the sleeper go once the bed carries no more than its weight: its vertical DOF
  // turns from the servo to free under gravity after the first step whose contact load is at most
  // the weight, and the sleeper sinks into the bed at the pace the bed gives way rather than at the
  // servo's (a servo's speed is its relaxation times the load error over the contacts' stiffness
  // per step: slow on a bed that yields, docs/samples.md, "Equilibrium"). Released no earlier, so
  // that the force a growth has pent up under the sleeper does not launch it. Call after
  // require_seated_sleeper, whose per-step recording it keeps.
  void release_sleeper_when_carried(SettleCriterion& c) const;
  // The sleeper at its design position raised by `lift` (m), as make() places it: its mesh and
  // mass (the controls are make()'s).
  MeshBody sleeper_at(double lift) const;
  // Walls every stage has, numbered first: base, crib walls (unless periodic), side walls (a box).
  int permanent_walls() const;
  // The load of the sleeper's weight, downward (N, negative): what the servo of make()'s sleeper
  // holds.
  double sleeper_weight() const { return section_.sleeper_mass * settings_.gravity.z(); }

  // The sample of a model's current state: bodies, walls, sleeper and contact springs, with the
  // shapes and sieve sizes of the bodies by id (a body missing from `sieve_size` is refused).
  Sample to_sample(const Simulation& sim, const std::map<std::int64_t, int>& shape_of_id,
                   const std::map<std::int64_t, double>& sieve_size_of_id,
                   const std::vector<std::string>& shapes) const;

  // The info lines every sample carries: the section and material parameters.
  std::vector<std::pair<std::string, std::string>> info() const;

  static constexpr const char* kSleeperName = "sleeper";
  // The name of the clumps' material in a table made with StageMaterials::clump_material, and
  // its index there (found by the name, not by the order of material_table's add() calls).
  static constexpr const char* kClumpMaterialName = "ballast-clump";
  int clump_material() const;

 private:
  TrackSection section_;
  SectionMaterials materials_;
  SimulationSettings settings_;
  double preparation_damping_;
};

// The section, materials and grading recorded in a sample's info lines (SectionModel::info,
// grading_info); throw InputError naming the missing line.
TrackSection section_of(const Sample& sample);
SectionMaterials materials_of(const Sample& sample);
SieveTable grading_of(const Sample& sample);
// The info lines of a grading: its source, sizes and passing.
std::vector<std::pair<std::string, std::string>> grading_info(const SieveTable& grading);

// What is kept of a deposited bed when it is trimmed to the section: the bodies whose centre lies
// in the design profile's trapezoid prism (above the base, at most at the crest, inside the
// slopes and the section length), except those whose centre is above the sleeper's bottom and
// that reach into the sleeper's solid at its design position or where it is placed (raised by
// sleeper_lift). Stones under the sleeper that protrude into it stay: the sleeper is placed on
// them and seats itself. A rule can leave out either cut: the slopes (a bed kept in its mould,
// only levelled at the crest) or the sleeper's box (a bed whose sleeper is already seated in it).
struct TrimRule {
  bool slopes = true;
  bool sleeper = true;
};
std::vector<char> bodies_in_section(const Particles& p, const TrackSection& section,
                                    TrimRule rule = {});
// How far above its design position the sleeper must start to clear the bodies centred below its
// bottom (0 if none reaches into it).
double sleeper_lift(const Particles& p, const TrackSection& section);

}  // namespace trackbed::dem
