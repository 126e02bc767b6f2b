// The only translation unit of the driver that includes deal.II: declares every case-file
// parameter (with units, defaults and valid ranges) and reads them into CaseParameters.
#include "cases/parameters/case_parameters.h"

#include <deal.II/base/parameter_handler.h>

#include <algorithm>
#include <iterator>
#include <sstream>

#include "cases/parameters/coupling_parameters.h"
#include "cases/parameters/prm_support.h"
#include "common/input_error.h"

namespace trackbed::cases {

using dealii::ParameterHandler;
using dealii::Patterns::Anything;
using dealii::Patterns::Bool;
using dealii::Patterns::Double;
using dealii::Patterns::FileName;
using dealii::Patterns::Integer;
using dealii::Patterns::List;
using dealii::Patterns::Selection;

namespace {

constexpr int kMaxMaterials = 8, kMaxPairs = 16, kMaxPlanes = 16, kMaxMeshes = 8;
const char* const kDofNames[6] = {"x", "y", "z", "rotation x", "rotation y", "rotation z"};

const Double kStiffness(0, 1e15), kFriction(0, 100), kRatio(0, 1);

// "servo -3728 gain 1e-6 max 0.01" and friends.
dem::DofControl parse_dof(const std::string& text, const std::string& where) {
  std::istringstream in(text);
  std::string mode;
  in >> mode;
  dem::DofControl c;
  const std::string valid =
      "; valid: fixed | free | velocity V | force F | servo F [gain G] [max V] [relaxation R]";
  auto number = [&](const char* what) {
    double v;
    if (!(in >> v)) throw InputError(where + " = '" + text + "': " + what + " missing" + valid);
    return v;
  };
  if (mode == "fixed")
    c.mode = dem::DofMode::fixed;
  else if (mode == "free")
    c.mode = dem::DofMode::free;
  else if (mode == "velocity")
    c.mode = dem::DofMode::velocity, c.value = number("velocity");
  else if (mode == "force")
    c.mode = dem::DofMode::force, c.value = number("force");
  else if (mode == "servo") {
    c.mode = dem::DofMode::servo;
    c.value = number("load");
    std::string word;
    while (in >> word) {
      if (word == "gain")
        c.gain = number("gain");
      else if (word == "max")
        c.max_speed = number("max speed");
      else if (word == "relaxation")
        c.relaxation = number("relaxation");
      else
        throw InputError(where + " = '" + text + "': unknown word '" + word + "'" + valid);
    }
    if (c.gain < 0 || !(c.relaxation > 0 && c.relaxation < 1) ||
        (c.gain == 0 && !(c.max_speed > 0)))
      throw InputError(where + " = '" + text +
                       "': a servo needs gain G >= 0, relaxation in (0, 1), and max V > 0 "
                       "when the gain is automatic" +
                       valid);
  } else {
    throw InputError(where + " = '" + text + "': unknown mode '" + mode + "'" + valid);
  }
  std::string rest;
  if (mode != "servo" && in >> rest)
    throw InputError(where + " = '" + text + "': unexpected '" + rest + "'" + valid);
  return c;
}

// simulation: the run's clock, threads, neighbour list and seed (and the top-level mode).
void declare_simulation(ParameterHandler& prm) {
  prm.declare_entry("mode", "dem", Selection("dem|coupled"),
                    "dem: standalone DEM with rigid walls; coupled: with the FE tier");
  prm.enter_subsection("simulation");
  prm.declare_entry("time step", "0", Double(0, 1),
                    "Time step in s; 0 = the critical timestep times 'critical timestep fraction'");
  prm.declare_entry("critical timestep fraction", "0.2", Double(1e-6, 1),
                    "Fraction of the critical timestep used when 'time step' is 0");
  prm.declare_entry("allow timestep above critical", "false", Bool(),
                    "Run even if the time step exceeds the critical one (expert use)");
  prm.declare_entry("end time", "0.5", Double(0), "Simulated time to run, s");
  prm.declare_entry("number of steps", "0", Integer(0), "Steps to run; > 0 overrides 'end time'");
  prm.declare_entry("untimed warm-up steps", "0", Integer(0),
                    "Steps excluded from the loop timing reported in summary.json (benchmarks)");
  prm.declare_entry("threads", "0", Integer(0, 1024), "OpenMP threads; 0 = OMP_NUM_THREADS");
  prm.declare_entry("verlet skin", "0.004", Double(0, 10), "Verlet skin of the neighbour list, m");
  prm.declare_entry("track energy", "true", Bool(),
                    "Tally dissipation and work every step for the energy balance");
  prm.declare_entry("energy error limit", "0.1", Double(1e-6, 1),
                    "The run stops as blown up when its energy balance error rises above this: "
                    "energy that no work put in");
  prm.declare_entry("seed", "1", Integer(0), "Seed of the random generators");
  prm.leave_subsection();
}

void parse_simulation(ParameterHandler& prm, const ParameterSource&, CaseParameters& c) {
  c.mode = prm.get("mode");
  prm.enter_subsection("simulation");
  c.time_step = prm.get_double("time step");
  c.critical_fraction = prm.get_double("critical timestep fraction");
  c.allow_supercritical = prm.get_bool("allow timestep above critical");
  c.end_time = prm.get_double("end time");
  c.number_of_steps = prm.get_integer("number of steps");
  c.warmup_steps = prm.get_integer("untimed warm-up steps");
  c.threads = prm.get_integer("threads");
  c.skin = prm.get_double("verlet skin");
  c.track_energy = prm.get_bool("track energy");
  c.energy_error_limit = prm.get_double("energy error limit");
  c.seed = prm.get_integer("seed");
  prm.leave_subsection();
}

// physics: gravity.
void declare_physics(ParameterHandler& prm) {
  prm.enter_subsection("physics");
  declare_vector(prm, "gravity", "0, 0, -9.81", "Gravitational acceleration, m/s^2");
  prm.leave_subsection();
}

void parse_physics(ParameterHandler& prm, const ParameterSource&, CaseParameters& c) {
  prm.enter_subsection("physics");
  c.gravity = vector_of(prm, "gravity");
  prm.leave_subsection();
}

// materials: the materials and their per-entity contact values.
void declare_materials(ParameterHandler& prm) {
  prm.enter_subsection("materials");
  prm.declare_entry("number of materials", "1", Integer(1, kMaxMaterials), "Materials defined");
  for (int i = 0; i < kMaxMaterials; ++i) {
    prm.enter_subsection("material " + std::to_string(i));
    prm.declare_entry("name", i == 0 ? "ballast" : "material" + std::to_string(i), Anything(),
                      "Name used by particles, walls and pairs");
    declare_material_values(prm, dem::Material());
    prm.leave_subsection();
  }
  prm.leave_subsection();
}

void parse_materials(ParameterHandler& prm, const ParameterSource& in, CaseParameters& c) {
  prm.enter_subsection("materials");
  const int nmat = prm.get_integer("number of materials");
  for (int i = 0; i < nmat; ++i) {
    prm.enter_subsection("material " + std::to_string(i));
    dem::Material m;
    m.name = name_of(prm, in.path + ": materials/material " + std::to_string(i) + "/");
    read_material_values(prm, m);
    c.materials.push_back(m);
    prm.leave_subsection();
  }
  prm.leave_subsection();
}

// contact pairs: pairs of materials with contact properties of their own.
void declare_contact_pairs(ParameterHandler& prm) {
  prm.enter_subsection("contact pairs");
  prm.declare_entry("number of pairs", "0", Integer(0, kMaxPairs),
                    "Pairs of materials with their own contact properties");
  for (int i = 0; i < kMaxPairs; ++i) {
    prm.enter_subsection("pair " + std::to_string(i));
    prm.declare_entry("materials", "", Anything(), "Two material names, e.g. 'ballast, sleeper'");
    prm.declare_entry("normal stiffness", "2e7", Double(1e-9, 1e15), "N/m");
    prm.declare_entry("shear stiffness", "2e7", kStiffness, "N/m");
    prm.declare_entry("friction", "0.5", kFriction, "-");
    prm.declare_entry("rolling friction", "0", kFriction, "-");
    prm.declare_entry("normal damping ratio", "0", kRatio, "-");
    prm.declare_entry("shear damping ratio", "0", kRatio, "-");
    prm.declare_entry("normal damping rate", "0", Double(0, 1e9), "1/s");
    prm.leave_subsection();
  }
  prm.leave_subsection();
}

void parse_contact_pairs(ParameterHandler& prm, const ParameterSource& in, CaseParameters& c) {
  const std::string& path = in.path;
  prm.enter_subsection("contact pairs");
  const int npairs = prm.get_integer("number of pairs");
  for (int i = 0; i < npairs; ++i) {
    const std::string where = "contact pairs/pair " + std::to_string(i);
    prm.enter_subsection("pair " + std::to_string(i));
    const auto names = dealii::Utilities::split_string_list(prm.get("materials"));
    if (names.size() != 2)
      throw InputError(path + ": " + where + "/materials = '" + prm.get("materials") +
                       "'; valid: two material names separated by a comma");
    PairParameters pp;
    pp.material_a = names[0];
    pp.material_b = names[1];
    pp.properties.kn = prm.get_double("normal stiffness");
    pp.properties.ks = prm.get_double("shear stiffness");
    pp.properties.mu = prm.get_double("friction");
    pp.properties.mu_roll = prm.get_double("rolling friction");
    pp.properties.normal_damping_ratio = prm.get_double("normal damping ratio");
    pp.properties.shear_damping_ratio = prm.get_double("shear damping ratio");
    pp.properties.normal_damping_rate = prm.get_double("normal damping rate");
    c.pairs.push_back(pp);
    prm.leave_subsection();
  }
  prm.leave_subsection();
}

// plane walls: infinite plane walls.
void declare_plane_walls(ParameterHandler& prm) {
  prm.enter_subsection("plane walls");
  prm.declare_entry("number of walls", "0", Integer(0, kMaxPlanes), "Infinite plane walls");
  for (int i = 0; i < kMaxPlanes; ++i) {
    prm.enter_subsection("wall " + std::to_string(i));
    prm.declare_entry("name", "wall" + std::to_string(i), Anything(), "Name in outputs");
    declare_vector(prm, "point", "0, 0, 0", "A point of the plane, m");
    declare_vector(prm, "normal", "0, 0, 1", "Normal pointing into the particles");
    declare_vector(prm, "velocity", "0, 0, 0", "Translation velocity, m/s");
    prm.declare_entry("material", "", Anything(), "Material name (empty: the first material)");
    prm.leave_subsection();
  }
  prm.leave_subsection();
}

void parse_plane_walls(ParameterHandler& prm, const ParameterSource& in, CaseParameters& c) {
  prm.enter_subsection("plane walls");
  const int nplanes = prm.get_integer("number of walls");
  for (int i = 0; i < nplanes; ++i) {
    prm.enter_subsection("wall " + std::to_string(i));
    c.planes.push_back({name_of(prm, in.path + ": plane walls/wall " + std::to_string(i) + "/"),
                        prm.get("material"), vector_of(prm, "point"), vector_of(prm, "normal"),
                        vector_of(prm, "velocity")});
    prm.leave_subsection();
  }
  prm.leave_subsection();
}

// meshes: triangle-mesh bodies and their degrees of freedom.
void declare_meshes(ParameterHandler& prm) {
  prm.enter_subsection("meshes");
  prm.declare_entry("number of meshes", "0", Integer(0, kMaxMeshes), "Triangle-mesh bodies");
  for (int i = 0; i < kMaxMeshes; ++i) {
    prm.enter_subsection("mesh " + std::to_string(i));
    prm.declare_entry("name", "mesh" + std::to_string(i), Anything(), "Name in outputs");
    prm.declare_entry("file", "", Anything(),
                      "STL file (ASCII or binary; each ASCII solid is a named part); empty: box");
    prm.declare_entry("box", "0, 0, 0, 1, 1, 1", List(Double(), 6, 6),
                      "Lower and upper corner of a box mesh when no file is given, m");
    prm.declare_entry("from sample", "false", Bool(),
                      "Take geometry, pose, mass and inertia from the particles/sample file's "
                      "mesh of this name (e.g. its seated sleeper); the DOFs come from here");
    prm.declare_entry("scale", "1", Double(1e-12), "Scale applied to the STL coordinates");
    declare_vector(prm, "translation", "0, 0, 0", "Translation applied after scaling, m");
    prm.declare_entry("material", "", Anything(), "Material name (empty: the first material)");
    prm.declare_entry("density", "0", Double(0),
                      "kg/m^3; > 0: mass, centre and inertia from the closed mesh");
    prm.declare_entry("mass", "0", Double(0), "kg; > 0 overrides the mass from the density");
    prm.declare_entry("weight", "false", Bool(), "Gravity acts on its free and force DOFs");
    for (const char* d : kDofNames)
      prm.declare_entry(std::string("dof ") + d, "fixed", Anything(),
                        "fixed | free | velocity V | force F | servo F [gain G] [max V] "
                        "[relaxation R] (SI; gain 0 or absent: automatic, PFC style)");
    prm.leave_subsection();
  }
  prm.leave_subsection();
}

void parse_meshes(ParameterHandler& prm, const ParameterSource& in, CaseParameters& c) {
  const std::string& path = in.path;
  const ValueFolders& folders = in.folders;
  prm.enter_subsection("meshes");
  const int nmeshes = prm.get_integer("number of meshes");
  for (int i = 0; i < nmeshes; ++i) {
    const std::string where = path + ": meshes/mesh " + std::to_string(i) + "/";
    prm.enter_subsection("mesh " + std::to_string(i));
    MeshParameters m;
    m.name = name_of(prm, where);
    m.file = folders.resolve("meshes/mesh " + std::to_string(i) + "/file", prm.get("file"));
    m.from_sample = prm.get_bool("from sample");
    m.box = six_of(prm, "box");
    m.scale = prm.get_double("scale");
    m.translation = vector_of(prm, "translation");
    m.material = prm.get("material");
    m.density = prm.get_double("density");
    m.mass = prm.get_double("mass");
    m.weight = prm.get_bool("weight");
    for (int d = 0; d < 6; ++d) {
      const std::string key = std::string("dof ") + kDofNames[d];
      m.dof[d] = parse_dof(prm.get(key), where + key);
    }
    c.meshes.push_back(m);
    prm.leave_subsection();
  }
  prm.leave_subsection();
}

// particles: where the bodies come from: a particle file, a sample, or the generator.
void declare_particles(ParameterHandler& prm) {
  prm.enter_subsection("particles");
  prm.declare_entry("file", "", Anything(), "Particle CSV (docs/formats.md); empty: generator");
  prm.declare_entry("sample file", "", Anything(),
                    "Sample built by 'trackbed build-sample' (.h5): its bodies, contact springs "
                    "and walls; its material names must be defined in 'materials'");
  prm.declare_entry("sample walls", "true", Bool(), "Add the sample's plane walls");
  prm.declare_entry("clump material", "", Anything(),
                    "Material of the sample's clumps (e.g. one without rolling friction, as in "
                    "the paper); empty: the sample's own");
  prm.declare_entry("templates", "", Anything(),
                    "Clump templates as 'name:file.csv, name2:file2.csv'");
  prm.enter_subsection("generator");
  prm.declare_entry("number", "0", Integer(0), "Bodies placed by random sequential addition");
  prm.declare_entry("region", "0, 0, 0, 1, 1, 1", List(Double(), 6, 6),
                    "Lower and upper corner of the box they are placed in, m");
  prm.declare_entry("minimum radius", "0.0112", Double(1e-9), "m (uniform by number)");
  prm.declare_entry("maximum radius", "0.0315", Double(1e-9), "m");
  prm.declare_entry("clump fraction", "0", Double(0, 1), "Share of bodies that are clumps");
  prm.declare_entry("clump template", "", Anything(), "Template name for the clumps");
  prm.declare_entry("material", "", Anything(), "Material name (empty: the first material)");
  prm.leave_subsection();
  prm.leave_subsection();
}

void parse_particles(ParameterHandler& prm, const ParameterSource& in, CaseParameters& c) {
  const std::string& path = in.path;
  const ValueFolders& folders = in.folders;
  prm.enter_subsection("particles");
  c.particle_file = folders.resolve("particles/file", prm.get("file"));
  c.sample_file = folders.resolve("particles/sample file", prm.get("sample file"));
  c.sample_walls = prm.get_bool("sample walls");
  c.clump_material = prm.get("clump material");
  for (const auto& item : dealii::Utilities::split_string_list(prm.get("templates"))) {
    const auto colon = item.find(':');
    if (colon == std::string::npos || colon == 0 || colon + 1 == item.size())
      throw InputError(path + ": particles/templates entry '" + item +
                       "'; valid: 'name:file.csv' items separated by commas");
    c.templates.emplace_back(item.substr(0, colon),
                             folders.resolve("particles/templates", item.substr(colon + 1)));
  }
  prm.enter_subsection("generator");
  c.generator.count = prm.get_integer("number");
  c.generator.region = six_of(prm, "region");
  c.generator.radius_min = prm.get_double("minimum radius");
  c.generator.radius_max = prm.get_double("maximum radius");
  c.generator.clump_fraction = prm.get_double("clump fraction");
  c.generator.clump_template = prm.get("clump template");
  c.generator.material = prm.get("material");
  prm.leave_subsection();
  prm.leave_subsection();
}

// push test: the lateral push of a mesh body.
void declare_push_test(ParameterHandler& prm) {
  prm.enter_subsection("push test");
  prm.declare_entry("mesh", "", Anything(),
                    "Mesh held until the bed is in equilibrium, then pushed at the velocity of "
                    "its DOF along 'direction' for 'distance', its resistance recorded in "
                    "push.csv; the run ends with the push ('end time' is not used). Empty: none");
  prm.declare_entry("direction", "x", Selection("x|y|z"), "The pushed DOF");
  prm.declare_entry("distance", "0.005", Double(1e-9, 10), "Push distance, m");
  prm.declare_entry("path", "", List(Double(-10, 10)),
                    "Displacements the mesh moves to in turn at the DOF's speed, m along the "
                    "push (the velocity's sign is +), e.g. '0.004, -0.004, 0': up 4 mm, down to "
                    "4 mm below the start, back; empty: 'distance' one way");
  prm.declare_entry("minimum hold", "0.02", Double(0, 100), "Time held at least, s");
  prm.declare_entry("maximum hold", "1", Double(0, 100),
                    "Time held at most, s (the push then starts; the summary says so)");
  prm.declare_entry("equilibrium ratio", "1e-3", Double(1e-9, 1),
                    "Mean unbalanced force ratio that ends the hold (3 checks in a row)");
  prm.declare_entry("hold along the push", "fixed", Selection("fixed|free"),
                    "During the hold the mesh is held still along the push (fixed: the push "
                    "starts from the net load the bed leaves on it) or free along it under that "
                    "load and its mass (free: the push starts from zero net load, where it came "
                    "to rest)");
  prm.declare_entry("report displacement", "0.002", Double(0, 10),
                    "Displacement at which the lateral force is also reported, m");
  prm.declare_entry("smoothing window", "0.0002", Double(0, 1),
                    "Displacement window of the running mean of the reported resistance, m");
  prm.leave_subsection();
}

void parse_push_test(ParameterHandler& prm, const ParameterSource& in, CaseParameters& c) {
  const std::string& path = in.path;
  prm.enter_subsection("push test");
  c.push.mesh = prm.get("mesh");
  c.push.axis = static_cast<int>(std::string("xyz").find(prm.get("direction")));
  c.push.distance = prm.get_double("distance");
  c.push.path =
      dealii::Utilities::string_to_double(dealii::Utilities::split_string_list(prm.get("path")));
  for (std::size_t k = 0; k < c.push.path.size(); ++k)
    if (c.push.path[k] == (k == 0 ? 0.0 : c.push.path[k - 1]))
      throw InputError(path + ": push test/path = " + prm.get("path") + ": point " +
                       std::to_string(k + 1) +
                       " repeats the one before it (the start is 0); valid: each point "
                       "differs from the one before");
  c.push.min_hold = prm.get_double("minimum hold");
  c.push.max_hold = prm.get_double("maximum hold");
  c.push.equilibrium_ratio = prm.get_double("equilibrium ratio");
  c.push.free_during_hold = prm.get("hold along the push") == "free";
  if (c.push.max_hold < c.push.min_hold)
    throw InputError(path + ": push test/maximum hold = " + prm.get("maximum hold") +
                     " is below minimum hold = " + prm.get("minimum hold") +
                     "; valid: maximum hold >= minimum hold");
  c.push.report_at = prm.get_double("report displacement");
  c.push.smoothing = prm.get_double("smoothing window");
  prm.leave_subsection();
}

// output: the results folder and what is written when.
void declare_output(ParameterHandler& prm) {
  prm.enter_subsection("output");
  prm.declare_entry("folder", "results/default", Anything(),
                    "Results folder (relative to the working directory)");
  prm.declare_entry("history interval", "1e-3", Double(0),
                    "s between CSV rows; 0 = only the first and last rows");
  prm.declare_entry("vtu interval", "0", Double(0),
                    "s between ParaView frames; 0 = only the first and last frames");
  prm.declare_entry("snapshot interval", "0", Double(0), "s between HDF5 snapshots; 0 = last");
  prm.declare_entry("progress interval", "2", Double(0), "Wall seconds between progress lines");
  prm.declare_entry("checkpoint interval", "600", Double(0),
                    "Wall seconds between checkpoints (checkpoint.h5, for 'trackbed resume'); "
                    "one is also written when the run is interrupted; 0 = none");
  prm.declare_entry("tracked bodies", "", List(Integer(0)),
                    "Body ids (rows of the particle file) whose history is written");
  prm.declare_entry("plot", "true", Bool(), "Write a PNG plot of the histories (matplotlib)");
  prm.leave_subsection();
}

void parse_output(ParameterHandler& prm, const ParameterSource& in, CaseParameters& c) {
  prm.enter_subsection("output");
  c.output_folder = output_folder_of(prm, in);
  c.history_interval = prm.get_double("history interval");
  c.vtu_interval = prm.get_double("vtu interval");
  c.snapshot_interval = prm.get_double("snapshot interval");
  c.progress_interval = prm.get_double("progress interval");
  c.checkpoint_interval = prm.get_double("checkpoint interval");
  for (const auto& s : dealii::Utilities::split_string_list(prm.get("tracked bodies")))
    c.tracked_bodies.push_back(std::stol(s));
  c.plot = prm.get_bool("plot");
  prm.leave_subsection();
}

// What no single subsection can check: where the bodies come from, and what needs a sample.
void check_sources(const CaseParameters& c, const std::string& path) {
  if (c.particle_file.empty() && c.sample_file.empty() && c.generator.count == 0)
    throw InputError(path +
                     ": particles: none of 'file', 'sample file' and 'generator/number' is "
                     "given; valid: a particle CSV file, a sample or a generator with "
                     "number > 0");
  if (!c.sample_file.empty() && (!c.particle_file.empty() || c.generator.count > 0))
    throw InputError(path +
                     ": particles: 'sample file' is given with 'file' or a generator; "
                     "valid: a sample alone (its body ids are its own)");
  if (!c.clump_material.empty() && c.sample_file.empty())
    throw InputError(path + ": particles/clump material needs particles/sample file");
  for (const auto& m : c.meshes)
    if (m.from_sample && c.sample_file.empty())
      throw InputError(path + ": meshes/" + m.name +
                       ": 'from sample = true' needs particles/sample file");
}

void declare(ParameterHandler& prm) {
  declare_simulation(prm);
  declare_physics(prm);
  declare_materials(prm);
  declare_contact_pairs(prm);
  declare_plane_walls(prm);
  declare_meshes(prm);
  declare_particles(prm);
  declare_push_test(prm);
  declare_coupling(prm);
  declare_fem(prm);
  declare_output(prm);
}

}  // namespace

CaseParameters read_case_file(const std::string& path) {
  ParameterHandler prm;
  declare(prm);
  // A relative file name resolves against the folder of the file that set it (an included file's
  // names stay its own).
  const ValueFolders folders = parse_parameter_file(prm, path, "trackbed --print-parameters");
  const ParameterSource in{path, folders};
  CaseParameters c;
  c.file = path;
  read_values(path, [&] {
    parse_simulation(prm, in, c);
    parse_physics(prm, in, c);
    parse_materials(prm, in, c);
    parse_contact_pairs(prm, in, c);
    parse_plane_walls(prm, in, c);
    parse_meshes(prm, in, c);
    parse_particles(prm, in, c);
    parse_push_test(prm, in, c);
    parse_coupling(prm, in, c);
    parse_fem(prm, in, c);
    parse_output(prm, in, c);
  });
  check_sources(c, path);
  c.fingerprint = fingerprint(prm);
  return c;
}

void print_parameters(std::ostream& out, bool json) {
  ParameterHandler prm;
  declare(prm);
  prm.print_parameters(out, json ? ParameterHandler::JSON : ParameterHandler::PRM);
}

}  // namespace trackbed::cases
