// The only translation unit of `trackbed build-sample` that includes deal.II: declares every
// sample-file parameter (units, defaults, ranges) and reads them into SampleParameters.
#include "cases/parameters/sample_parameters.h"

#include <cstdlib>

#include "cases/parameters/prm_support.h"
#include "common/input_error.h"
#include "common/number_text.h"
#include "dem/samples/grading.h"
#include "dem/samples/zone.h"

namespace trackbed::cases {

using dealii::ParameterHandler;
using dealii::Patterns::Anything;
using dealii::Patterns::Bool;
using dealii::Patterns::Double;
using dealii::Patterns::Integer;
using dealii::Patterns::List;
using dealii::Patterns::Selection;

namespace {

const char* const kPresets = "all-ball|all-clump|half-by-height|optimised|custom";

// section: the single-sleeper section (the one TrackSection).
void declare_section(ParameterHandler& prm, const dem::SampleBuildSettings& b) {
  const TrackSection& s = b.section;
  prm.enter_subsection("section");
  prm.declare_entry("sleeper length", number_text(s.sleeper_length), Double(1e-3, 100),
                    "m, across the track (x, the push direction)");
  prm.declare_entry("sleeper width", number_text(s.sleeper_width), Double(1e-3, 100),
                    "m, along the track (y)");
  prm.declare_entry("sleeper bottom width", number_text(s.sleeper_bottom_width), Double(0, 100),
                    "m along y at the sleeper's bottom, its top being 'sleeper width': a "
                    "wedge-shaped section (ballast box test); 0: a box");
  prm.declare_entry("sleeper height", number_text(s.sleeper_height), Double(1e-3, 100), "m");
  prm.declare_entry("sleeper mass", number_text(s.sleeper_mass), Double(1e-6, 1e6), "kg");
  prm.declare_entry("depth under sleeper", number_text(s.depth_under_sleeper), Double(1e-3, 100),
                    "m of ballast between the base (z = 0) and the sleeper bottom");
  prm.declare_entry("shoulder width", number_text(s.shoulder_width), Double(0, 100),
                    "m of crest beyond each sleeper end");
  prm.declare_entry("slope", number_text(s.slope), Double(0, 100),
                    "Horizontal per vertical of the shoulder slopes (1:1.75 -> 1.75)");
  prm.declare_entry("length", number_text(s.length), Double(1e-3, 1000),
                    "m along the track: one sleeper spacing, crib walls at +-length/2");
  prm.declare_entry("boundary", "walls", Selection("walls|periodic"),
                    "Along the track: frictionless crib walls (symmetry planes) or periodic");
  prm.declare_entry("sides", "slopes", Selection("slopes|walls"),
                    "Across the track: shoulder slopes, or the side walls of a box at "
                    "+-(sleeper length / 2 + shoulder width) (needs slope 0)");
  prm.leave_subsection();
}

void parse_section(ParameterHandler& prm, const ParameterSource& in, SampleParameters& p) {
  const std::string& path = in.path;
  dem::SampleBuildSettings& b = p.build;
  TrackSection& s = b.section;
  prm.enter_subsection("section");
  s.sleeper_length = prm.get_double("sleeper length");
  s.sleeper_width = prm.get_double("sleeper width");
  s.sleeper_height = prm.get_double("sleeper height");
  s.sleeper_mass = prm.get_double("sleeper mass");
  s.depth_under_sleeper = prm.get_double("depth under sleeper");
  s.shoulder_width = prm.get_double("shoulder width");
  s.slope = prm.get_double("slope");
  s.length = prm.get_double("length");
  s.periodic = prm.get("boundary") == "periodic";
  s.side_walls = prm.get("sides") == "walls";
  s.sleeper_bottom_width = prm.get_double("sleeper bottom width");
  prm.leave_subsection();
  s.validate(path);
}

// grading: the stones' size distribution.
void declare_grading(ParameterHandler& prm, const dem::SampleBuildSettings&) {
  prm.enter_subsection("grading");
  prm.declare_entry("file", "", Anything(),
                    "Sieve table CSV (columns size in m, passing in %); empty: EN 13450 31.5/63");
  prm.leave_subsection();
}

void parse_grading(ParameterHandler& prm, const ParameterSource& in, SampleParameters& p) {
  const ValueFolders& folders = in.folders;
  dem::SampleBuildSettings& b = p.build;
  prm.enter_subsection("grading");
  const std::string grading = folders.resolve("grading/file", prm.get("file"));
  if (!grading.empty()) b.grading = dem::read_sieve_table_csv(grading);
  prm.leave_subsection();
}

// materials: the ballast and sleeper materials of the build.
void declare_materials(ParameterHandler& prm, const dem::SampleBuildSettings& b) {
  prm.enter_subsection("materials");
  for (const auto& [m, role] : {std::pair{&b.materials.ballast, "stones and the base"},
                                {&b.materials.sleeper, "the sleeper"},
                                {&b.materials.wall, "crib and mould walls"}}) {
    prm.enter_subsection(m->name);
    declare_material_values(prm, *m, role);
    prm.leave_subsection();
  }
  prm.leave_subsection();
}

void parse_materials(ParameterHandler& prm, const ParameterSource&, SampleParameters& p) {
  dem::SampleBuildSettings& b = p.build;
  prm.enter_subsection("materials");
  for (dem::Material* m : {&b.materials.ballast, &b.materials.sleeper, &b.materials.wall}) {
    prm.enter_subsection(m->name);
    read_material_values(prm, *m);
    prm.leave_subsection();
  }
  prm.leave_subsection();
}

// build: deposition, compaction and the seated sleeper.
void declare_build(ParameterHandler& prm, const dem::SampleBuildSettings& b) {
  prm.enter_subsection("build");
  prm.declare_entry("target porosity", number_text(b.target_porosity), Double(0.2, 0.7),
                    "Porosity under the sleeper that compaction aims at (reached from above)");
  prm.declare_entry("overfill", number_text(b.overfill), Double(0, 1),
                    "Extra volume deposited above the crest, fraction of the box volume");
  prm.declare_entry("cloud solid fraction", number_text(b.cloud_solid_fraction), Double(0.01, 0.35),
                    "Solid fraction of the loose cloud placed by random addition");
  prm.declare_entry("deposition damping", number_text(b.deposition_damping), Double(0, 0.999),
                    "Ballast local damping while the cloud falls");
  prm.declare_entry("preparation damping ratio", number_text(b.preparation_damping), Double(0, 1),
                    "Normal dashpot (fraction of critical) of the ballast's contacts while the "
                    "sample is built and converted: it damps the rattling of stones");
  prm.declare_entry("deposition friction factor", "auto", Anything(),
                    "Ballast friction factor while the bed is deposited, in [0, 1]; auto: "
                    "calibrated for the target porosity by depositions of a small box");
  std::string factors;
  for (double f : b.calibration.factors) factors += (factors.empty() ? "" : ", ") + number_text(f);
  prm.declare_entry("calibration friction factors", factors, List(Double(0, 1), 2),
                    "Friction factors of the calibration depositions (auto)");
  prm.declare_entry("tamping load factor", number_text(b.tamping_load_factor), Double(1, 1e4),
                    "The sleeper is pressed into the bed with this many times its weight, then "
                    "seated under its weight (1: no tamping)");
  prm.declare_entry("mould seating friction factor", number_text(b.mould_seating_friction),
                    Double(0, 1),
                    "0: the sleeper is seated on the finished profile; a factor in (0, 1]: it is "
                    "first seated while the bed is still in its mould with the ballast friction "
                    "scaled by this factor, then the friction is restored and the slopes cut");
  prm.declare_entry("mould seating time", number_text(b.mould_seating_time), Double(1e-6, 1e3),
                    "s simulated at most of the seating in the mould: at a low friction the bed "
                    "creeps under the sleeper, and the stage ends here unconverged");
  prm.declare_entry("mould seating sleeper", b.mould_sleeper_free ? "free" : "servo",
                    Selection("free|servo"),
                    "In the mould the sleeper is free under its weight, or held by its seating "
                    "servo (slow: it bears a fraction of its weight there)");
  prm.declare_entry("stage ratio", number_text(b.stage_ratio), Double(1e-8, 0.5),
                    "Mean unbalanced force ratio ending the intermediate stages");
  prm.declare_entry("equilibrium ratio", number_text(b.equilibrium_ratio), Double(1e-8, 0.5),
                    "Mean unbalanced force ratio of the finished sample");
  prm.declare_entry("maximum stage time", number_text(b.max_stage_time), Double(1e-3, 1e3),
                    "s simulated per stage at most");
  prm.declare_entry("time step", "0", Double(0, 1),
                    "s; 0: critical timestep fraction x the critical step of the loose cloud");
  prm.declare_entry("critical timestep fraction", number_text(b.critical_fraction), Double(1e-3, 1),
                    "Of the loose cloud's critical step (one contact per body: 0.35 anticipates "
                    "about 8 in the packed bed)");
  prm.declare_entry("verlet skin", number_text(b.skin), Double(1e-6, 1), "m");
  prm.declare_entry("seed", "1", Integer(0), "Seed of the grading draw and the cloud");
  prm.declare_entry("threads", "0", Integer(0, 1024), "OpenMP threads; 0 = OMP_NUM_THREADS");
  prm.leave_subsection();
}

void parse_build(ParameterHandler& prm, const ParameterSource& in, SampleParameters& p) {
  const std::string& path = in.path;
  dem::SampleBuildSettings& b = p.build;
  prm.enter_subsection("build");
  b.target_porosity = prm.get_double("target porosity");
  b.overfill = prm.get_double("overfill");
  b.cloud_solid_fraction = prm.get_double("cloud solid fraction");
  b.deposition_damping = prm.get_double("deposition damping");
  b.preparation_damping = prm.get_double("preparation damping ratio");
  p.conversion.preparation_damping = b.preparation_damping;
  const std::string friction = prm.get("deposition friction factor");
  if (friction == "auto") {
    b.deposition_friction = -1;
  } else {
    char* end = nullptr;
    b.deposition_friction = std::strtod(friction.c_str(), &end);
    if (end == friction.c_str() || *end != '\0' || !(b.deposition_friction >= 0) ||
        b.deposition_friction > 1)
      throw InputError(path + ": build/deposition friction factor = '" + friction +
                       "'; valid: auto or a number in [0, 1]");
  }
  b.calibration.factors = dealii::Utilities::string_to_double(
      dealii::Utilities::split_string_list(prm.get("calibration friction factors")));
  b.tamping_load_factor = prm.get_double("tamping load factor");
  b.mould_seating_friction = prm.get_double("mould seating friction factor");
  b.mould_seating_time = prm.get_double("mould seating time");
  b.mould_sleeper_free = prm.get("mould seating sleeper") == "free";
  b.stage_ratio = prm.get_double("stage ratio");
  b.equilibrium_ratio = prm.get_double("equilibrium ratio");
  b.max_stage_time = prm.get_double("maximum stage time");
  b.time_step = prm.get_double("time step");
  b.critical_fraction = prm.get_double("critical timestep fraction");
  b.skin = prm.get_double("verlet skin");
  b.seed = prm.get_integer("seed");
  p.threads = prm.get_integer("threads");
  prm.leave_subsection();
}

// zone: which balls become clumps, and how the conversion grows and settles them.
void declare_zone(ParameterHandler& prm, const dem::SampleBuildSettings&) {
  const dem::ConversionSettings c;
  prm.enter_subsection("zone");
  prm.declare_entry(
      "preset", "all-ball", Selection(kPresets),
      "Clumps where: all-ball (none), all-clump (all), half-by-height (above "
      "265/350 of the depth under the sleeper), optimised (a geometric zone: under and "
      "beside the sleeper and the shoulder wedge at the pushed +x end; the shipped "
      "optimised cases take theirs from a pilot push instead), custom (clump zone)");
  prm.declare_entry("clump zone", "", Anything(),
                    "Zone expression (docs/zones.md) when preset = custom");
  prm.declare_entry("base sample", "", Anything(),
                    "Ball sample (.h5) whose balls are converted; empty: build it first");
  prm.declare_entry("templates", "../templates/ballast/library.csv", Anything(),
                    "Clump template library manifest (docs/templates.md)");
  prm.declare_entry("template setting", "D120R0.5", Anything(),
                    "Bubble-pack setting of the templates: D<distance>R<ratio>");
  prm.declare_entry("mass from", "surface", Selection("surface|pebbles"),
                    "Clump volume and inertia from the stone surface (PFC) or the pebble union");
  prm.declare_entry("growth time", number_text(c.growth_time), Double(1e-4, 10),
                    "s over which converted clumps grow to full size");
  prm.declare_entry("growth step", "probe", Selection("probe|renewed"),
                    "Step of the growth: the critical step of the fully grown clumps where their "
                    "balls are (probe), or of the model as it stands, renewed every 500 steps");
  prm.declare_entry("growth step factor", number_text(c.growth_step_factor), Double(1, 100),
                    "Renewed growth step in units of the bed's own; above 1 the bodies that need "
                    "it are density scaled (docs/samples.md); the probe's step takes 1 only");
  prm.declare_entry("growth friction factor", number_text(c.growth_friction_factor), Double(0, 1),
                    "Ballast friction and rolling factor while the clumps grow");
  prm.declare_entry("orientation trials", std::to_string(c.orientation_trials), Integer(1, 1000),
                    "Random orientations tried per clump; the one that fits largest is kept");
  prm.declare_entry("equilibrium ratio", number_text(c.equilibrium_ratio), Double(1e-8, 0.5),
                    "Mean unbalanced force ratio of the converted sample");
  prm.declare_entry("maximum settling time", number_text(c.max_stage_time), Double(1e-3, 1e3),
                    "s simulated for the final equilibrium at most");
  prm.declare_entry("settling step factor", number_text(c.settling_step_factor), Double(1, 100),
                    "Step of the final equilibrium in units of the grown bed's own; above 1 the "
                    "bodies that need it are density scaled (docs/samples.md)");
  prm.declare_entry("densification ratio", number_text(c.densification_ratio), Double(0, 0.5),
                    "Above 0 (and above the equilibrium ratio): the final settling in two "
                    "stages, down to this ratio without the clumps' rolling resistance, then to "
                    "the equilibrium ratio with the ballast's (docs/samples.md); 0: one stage, "
                    "without");
  prm.declare_entry("seed", "1", Integer(0), "Seed of the template choice and orientations");
  prm.leave_subsection();
}

void parse_zone(ParameterHandler& prm, const ParameterSource& in, SampleParameters& p) {
  const std::string& path = in.path;
  const ValueFolders& folders = in.folders;
  dem::SampleBuildSettings& b = p.build;
  prm.enter_subsection("zone");
  p.preset = prm.get("preset");
  const std::string custom = prm.get("clump zone");
  if (p.preset == "custom" && custom.empty())
    throw InputError(path +
                     ": zone/clump zone is empty; valid: a zone expression "
                     "(docs/zones.md) when zone/preset = custom");
  if (p.preset != "custom" && !custom.empty())
    throw InputError(path + ": zone/clump zone is given but zone/preset = " + p.preset +
                     "; valid: preset = custom with a clump zone, or no clump zone");
  p.zone_text = custom;
  p.zone_folder = folders.folder_of("zone/clump zone");
  // Parsed here so that a bad zone stops the run before anything is built.
  if (!custom.empty()) dem::parse_zone(custom, path + ": zone/clump zone", p.zone_folder);
  p.base_sample = folders.resolve("zone/base sample", prm.get("base sample"));
  p.templates = folders.resolve("zone/templates", prm.get("templates"));
  p.template_setting = prm.get("template setting");
  p.mass_from =
      prm.get("mass from") == "surface" ? dem::MassSource::surface : dem::MassSource::pebbles;
  p.conversion.growth_time = prm.get_double("growth time");
  p.conversion.growth_friction_factor = prm.get_double("growth friction factor");
  p.conversion.growth_step =
      prm.get("growth step") == "probe" ? dem::GrowthStep::probe : dem::GrowthStep::renewed;
  p.conversion.growth_step_factor = prm.get_double("growth step factor");
  if (p.conversion.growth_step_factor > 1 && p.conversion.growth_step == dem::GrowthStep::probe)
    throw InputError(path + ": zone/growth step factor = " + prm.get("growth step factor") +
                     " with zone/growth step = probe (a fixed step); valid: 1, or growth "
                     "step = renewed");
  p.conversion.orientation_trials = prm.get_integer("orientation trials");
  p.conversion.equilibrium_ratio = prm.get_double("equilibrium ratio");
  p.conversion.max_stage_time = prm.get_double("maximum settling time");
  p.conversion.settling_step_factor = prm.get_double("settling step factor");
  p.conversion.densification_ratio = prm.get_double("densification ratio");
  if (p.conversion.densification_ratio > 0 &&
      p.conversion.densification_ratio <= p.conversion.equilibrium_ratio)
    throw InputError(path + ": zone/densification ratio = " + prm.get("densification ratio") +
                     " is not above zone/equilibrium ratio = " + prm.get("equilibrium ratio") +
                     "; valid: 0 (one settling stage) or a ratio above the equilibrium's");
  p.conversion.seed = prm.get_integer("seed");
  p.conversion.skin = b.skin;
  prm.leave_subsection();
}

// output: the sample folder and what is written.
void declare_output(ParameterHandler& prm, const dem::SampleBuildSettings&) {
  prm.enter_subsection("output");
  prm.declare_entry("folder", "results/samples/section", Anything(),
                    "Results folder (relative to the working directory)");
  prm.declare_entry("progress interval", "5", Double(0), "Wall seconds between progress lines");
  prm.declare_entry("checkpoint interval", "600", Double(0),
                    "Wall seconds between checkpoints of a conversion to clumps (checkpoint.h5, "
                    "for 'trackbed resume'); one is also written when the build is interrupted; "
                    "0 = none");
  prm.declare_entry("vtu", "true", Bool(), "Write ParaView files of the finished sample");
  prm.declare_entry("plot", "true", Bool(), "Write grading.png and sample.png (matplotlib)");
  prm.leave_subsection();
}

void parse_output(ParameterHandler& prm, const ParameterSource& in, SampleParameters& p) {
  prm.enter_subsection("output");
  p.output_folder = output_folder_of(prm, in);
  p.progress_interval = prm.get_double("progress interval");
  p.checkpoint_interval = prm.get_double("checkpoint interval");
  p.vtu = prm.get_bool("vtu");
  p.plot = prm.get_bool("plot");
  prm.leave_subsection();
}

void declare(ParameterHandler& prm) {
  const dem::SampleBuildSettings defaults;
  declare_section(prm, defaults);
  declare_grading(prm, defaults);
  declare_materials(prm, defaults);
  declare_build(prm, defaults);
  declare_zone(prm, defaults);
  declare_output(prm, defaults);
}

}  // namespace

std::string preset_zone(const std::string& preset, const TrackSection& s) {
  if (preset == "all-ball") return "none";
  if (preset == "all-clump") return "all";
  // The paper's half-by-height model: balls in the bottom 265 mm, clumps in the 80 mm under the
  // sleeper (depth 350 mm) and in the crib; kept in proportion for other depths.
  const double split = s.depth_under_sleeper * 265.0 / 350.0;
  if (preset == "half-by-height")
    return "halfspace(0, 0, " + exact_number_text(split) + ", 0, 0, -1)";
  if (preset == "optimised") {
    // Under and beside the sleeper down to 50 mm (at depth 350 mm) below it, and the shoulder
    // wedge in front of the pushed (+x) end, from that level at the sleeper end up to the crest
    // edge: 20 % of the ballast volume of the paper's section, as its 5,036 of 24,394 stones.
    const double bottom = s.depth_under_sleeper * (1 - 50.0 / 350.0);
    const double top = s.crest_z() + s.sleeper_height;  // above every stone centre
    const double half = 0.5 * s.sleeper_length, y = s.length;
    return "box(" + exact_number_text(-half) + ", " + exact_number_text(-y) + ", " +
           exact_number_text(bottom) + ", " + exact_number_text(half) + ", " +
           exact_number_text(y) + ", " + exact_number_text(top) + ") | prism(y, " +
           exact_number_text(-y) + ", " + exact_number_text(y) + ", " + exact_number_text(half) +
           ", " + exact_number_text(bottom) + ", " + exact_number_text(s.half_crest_width()) +
           ", " + exact_number_text(s.crest_z()) + ", " + exact_number_text(s.half_crest_width()) +
           ", " + exact_number_text(top) + ", " + exact_number_text(half) + ", " +
           exact_number_text(top) + ")";
  }
  throw InputError("zone preset '" + preset + "' is unknown; valid: " + kPresets);
}

SampleParameters read_sample_file(const std::string& path) {
  ParameterHandler prm;
  declare(prm);
  // A relative file name resolves against the folder of the file that set it (an included file's
  // names stay its own).
  const ValueFolders folders =
      parse_parameter_file(prm, path, "trackbed build-sample --print-parameters");

  const ParameterSource in{path, folders};
  SampleParameters p;
  p.file = path;
  read_values(path, [&] {
    parse_section(prm, in, p);
    parse_grading(prm, in, p);
    parse_materials(prm, in, p);
    parse_build(prm, in, p);
    parse_zone(prm, in, p);
    parse_output(prm, in, p);
  });
  p.fingerprint = fingerprint(prm);
  return p;
}

void print_sample_parameters(std::ostream& out, bool json) {
  ParameterHandler prm;
  declare(prm);
  prm.print_parameters(out, json ? ParameterHandler::JSON : ParameterHandler::PRM);
}

}  // namespace trackbed::cases
