#include "cases/parameters/coupling_parameters.h"

#include <string>

#include "common/input_error.h"
#include "common/number_text.h"

namespace trackbed::cases {

using dealii::ParameterHandler;
using dealii::Patterns::Bool;
using dealii::Patterns::Double;
using dealii::Patterns::Integer;
using dealii::Patterns::Selection;

namespace {

// A layer's material: Young's modulus, Poisson's ratio, density (the defaults are `m`'s).
void declare_layer(ParameterHandler& prm, const std::string& name, const fem::Material& m,
                   const std::string& what) {
  prm.enter_subsection(name);
  prm.declare_entry("youngs modulus", number_text(m.youngs_modulus), Double(0),
                    "Young's modulus of the " + what + ", Pa");
  prm.declare_entry("poisson ratio", number_text(m.poisson_ratio), Double(-1, 0.5),
                    "Poisson's ratio of the " + what);
  prm.declare_entry("density", number_text(m.density), Double(0),
                    "Density of the " + what + ", kg/m^3");
  prm.leave_subsection();
}

void parse_layer(ParameterHandler& prm, const ParameterSource& in, const std::string& name,
                 fem::Material& m) {
  prm.enter_subsection(name);
  m.name = name;
  m.youngs_modulus = prm.get_double("youngs modulus");
  m.poisson_ratio = prm.get_double("poisson ratio");
  m.density = prm.get_double("density");
  prm.leave_subsection();
  m.validate(in.path + ": fem/" + name);
}

}  // namespace

void declare_coupling(ParameterHandler& prm) {
  const coupling::QuasiStaticParameters d;
  prm.enter_subsection("coupling");
  prm.declare_entry("scheme", "quasi-static", Selection("quasi-static"),
                    "quasi-static: staggered, the FE subgrade solved statically every interval "
                    "with the bed's mean load (push tests)");
  prm.declare_entry("interval", std::to_string(d.interval_steps), Integer(1),
                    "DEM steps per exchange with the FE subgrade (T)");
  prm.declare_entry("relaxation", number_text(d.relaxation), Double(0, 1),
                    "Under-relaxation factor of the interface displacement, (0, 1]: every "
                    "exchange's, or without Aitken every one's");
  prm.declare_entry("aitken", d.aitken ? "true" : "false", Bool(),
                    "Aitken's dynamic relaxation once the load ramp is complete");
  prm.declare_entry("tolerance", number_text(d.tolerance), Double(0),
                    "Converged when the work of the bed's load on the interface residual is at "
                    "most this fraction of its work on the FE displacement (a push waits for it)");
  prm.declare_entry("ramp", std::to_string(d.ramp_exchanges), Integer(1),
                    "Exchanges over which the bed's load on the subgrade ramps up to its full "
                    "value");
  prm.leave_subsection();
}

void parse_coupling(ParameterHandler& prm, const ParameterSource& in, CaseParameters& c) {
  prm.enter_subsection("coupling");
  coupling::QuasiStaticParameters& p = c.coupling;
  p.interval_steps = prm.get_integer("interval");
  p.relaxation = prm.get_double("relaxation");
  p.aitken = prm.get_bool("aitken");
  p.tolerance = prm.get_double("tolerance");
  p.ramp_exchanges = prm.get_integer("ramp");
  prm.leave_subsection();
  try {
    p.validate();
  } catch (const InputError& e) {
    throw InputError(in.path + ": " + e.what());
  }
}

void declare_fem(ParameterHandler& prm) {
  const coupling::SubgradeParameters d;
  const TrackSection& l = d.layers;
  prm.enter_subsection("fem");
  prm.declare_entry("degree", std::to_string(d.degree), Integer(1, 2),
                    "Polynomial degree of the elements (1: trilinear, 2: triquadratic)");
  prm.declare_entry("element size", number_text(d.element_size), Double(0),
                    "Element size in the embankment, m (twice it in the ground beside it)");
  prm.declare_entry("solver",
                    d.solver.method == fem::SolverParameters::Method::direct ? "direct" : "cg amg",
                    Selection("cg amg|direct"),
                    "direct: one sparse LU factorisation, a back-substitution per exchange (the "
                    "subgrade's few thousand cells); cg amg: conjugate gradients with algebraic "
                    "multigrid (large meshes)");
  prm.declare_entry("solver tolerance", number_text(d.solver.relative_tolerance), Double(0, 1),
                    "Relative residual of the iterative solver (cg amg)");
  prm.enter_subsection("layers");
  prm.declare_entry("lower ballast thickness", number_text(l.lower_ballast_thickness), Double(0),
                    "Equivalent-continuum ballast under the formation, m; 0: none");
  prm.declare_entry("sub-ballast thickness", number_text(l.sub_ballast_thickness), Double(0),
                    "Sub-ballast layer, m");
  prm.declare_entry("embankment height", number_text(l.embankment_height), Double(0),
                    "Subgrade fill above the natural ground, m");
  prm.declare_entry("embankment slope", number_text(l.embankment_slope), Double(0),
                    "Embankment slope, horizontal per vertical");
  prm.declare_entry("ground depth", number_text(l.ground_depth), Double(0),
                    "Natural ground below the embankment, m (its base is fixed)");
  prm.declare_entry("ground half width", number_text(l.ground_half_width), Double(0),
                    "Distance from the track centre line to the lateral boundary, m (rollers)");
  prm.leave_subsection();
  declare_layer(prm, "sub-ballast", d.sub_ballast, "sub-ballast");
  declare_layer(prm, "subgrade", d.subgrade, "embankment fill");
  declare_layer(prm, "ground", d.ground, "natural ground");
  declare_layer(prm, "lower ballast", d.lower_ballast, "equivalent-continuum lower ballast");
  prm.leave_subsection();
}

void parse_fem(ParameterHandler& prm, const ParameterSource& in, CaseParameters& c) {
  coupling::SubgradeParameters& p = c.subgrade;
  TrackSection& l = p.layers;
  prm.enter_subsection("fem");
  p.degree = prm.get_integer("degree");
  p.element_size = prm.get_double("element size");
  p.solver.method = prm.get("solver") == "direct" ? fem::SolverParameters::Method::direct
                                                  : fem::SolverParameters::Method::cg_amg;
  p.solver.relative_tolerance = prm.get_double("solver tolerance");
  prm.enter_subsection("layers");
  l.lower_ballast_thickness = prm.get_double("lower ballast thickness");
  l.sub_ballast_thickness = prm.get_double("sub-ballast thickness");
  l.embankment_height = prm.get_double("embankment height");
  l.embankment_slope = prm.get_double("embankment slope");
  l.ground_depth = prm.get_double("ground depth");
  l.ground_half_width = prm.get_double("ground half width");
  prm.leave_subsection();
  parse_layer(prm, in, "sub-ballast", p.sub_ballast);
  parse_layer(prm, in, "subgrade", p.subgrade);
  parse_layer(prm, in, "ground", p.ground);
  parse_layer(prm, in, "lower ballast", p.lower_ballast);
  prm.leave_subsection();
  for (const auto& [name, value] : {std::pair<const char*, double>{"element size", p.element_size},
                                    {"layers/sub-ballast thickness", l.sub_ballast_thickness},
                                    {"layers/embankment height", l.embankment_height},
                                    {"layers/ground depth", l.ground_depth},
                                    {"layers/ground half width", l.ground_half_width}})
    if (!(value > 0))
      throw InputError(in.path + ": fem/" + name + " = " + number_text(value) + "; valid: > 0");
}

}  // namespace trackbed::cases
