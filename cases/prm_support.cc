#include "cases/prm_support.h"

#include <deal.II/base/exceptions.h>

#include <filesystem>
#include <sstream>

#include "dem/input_error.h"

namespace trackbed::cases {

void declare_vector(dealii::ParameterHandler& prm, const std::string& name, const std::string& def,
                    const std::string& doc) {
  prm.declare_entry(name, def, dealii::Patterns::List(dealii::Patterns::Double(), 3, 3), doc);
}

dem::Vec3 vector_of(const dealii::ParameterHandler& prm, const std::string& name) {
  const auto v =
      dealii::Utilities::string_to_double(dealii::Utilities::split_string_list(prm.get(name)));
  return dem::Vec3(v[0], v[1], v[2]);
}

std::array<double, 6> six_of(const dealii::ParameterHandler& prm, const std::string& name) {
  const auto v =
      dealii::Utilities::string_to_double(dealii::Utilities::split_string_list(prm.get(name)));
  return {{v[0], v[1], v[2], v[3], v[4], v[5]}};
}

void declare_material_values(dealii::ParameterHandler& prm, const dem::Material& d,
                             const std::string& role) {
  using dealii::Patterns::Double;
  auto text = [](double v) {
    std::ostringstream s;
    s << v;
    return s.str();
  };
  prm.declare_entry("density", text(d.density), Double(1e-9),
                    "kg/m^3" + (role.empty() ? std::string() : " (" + role + ")"));
  prm.declare_entry("normal stiffness", text(d.normal_stiffness), Double(1e-9, 1e15),
                    "Entity normal stiffness, N/m (pairs combine in series unless a contact "
                    "pair gives its own value)");
  prm.declare_entry("shear stiffness", text(d.shear_stiffness), Double(0, 1e15),
                    "Entity shear stiffness, N/m");
  prm.declare_entry("friction", text(d.friction), Double(0, 100), "Coulomb friction coefficient");
  prm.declare_entry("rolling friction", text(d.rolling_friction), Double(0, 100),
                    "Rolling resistance coefficient mu_r (0: none)");
  prm.declare_entry("normal damping ratio", text(d.normal_damping_ratio), Double(0, 1),
                    "Normal dashpot, fraction of critical");
  prm.declare_entry("shear damping ratio", text(d.shear_damping_ratio), Double(0, 1),
                    "Shear dashpot, fraction of critical");
  prm.declare_entry("normal damping rate", text(d.normal_damping_rate), Double(0, 1e9),
                    "Normal dashpot as gamma_n in 1/s: F = gamma_n m_eff v_n (LAMMPS style)");
  prm.declare_entry("local damping", text(d.local_damping), Double(0, 0.999),
                    "Local damping coefficient alpha");
}

void read_material_values(const dealii::ParameterHandler& prm, dem::Material& m) {
  m.density = prm.get_double("density");
  m.normal_stiffness = prm.get_double("normal stiffness");
  m.shear_stiffness = prm.get_double("shear stiffness");
  m.friction = prm.get_double("friction");
  m.rolling_friction = prm.get_double("rolling friction");
  m.normal_damping_ratio = prm.get_double("normal damping ratio");
  m.shear_damping_ratio = prm.get_double("shear damping ratio");
  m.normal_damping_rate = prm.get_double("normal damping rate");
  m.local_damping = prm.get_double("local damping");
}

std::string one_line(const std::exception& e) {
  std::string text;
  if (const auto* d = dynamic_cast<const dealii::ExceptionBase*>(&e)) {
    std::ostringstream s;
    d->print_info(s);
    text = s.str();
  } else {
    text = e.what();
  }
  std::string out;
  for (char c : text) {
    if (c == '\n' || c == '\r' || c == '\t') c = ' ';
    if (c == ' ' && (out.empty() || out.back() == ' ')) continue;
    out += c;
  }
  while (!out.empty() && out.back() == ' ') out.pop_back();
  return out;
}

void parse_parameter_file(dealii::ParameterHandler& prm, const std::string& path,
                          const std::string& print_command) {
  if (!std::filesystem::exists(path))
    throw dem::InputError(path + ": file not found; valid: a .prm file (see '" + print_command +
                          "')");
  try {
    prm.parse_input(path);
  } catch (const std::exception& e) {
    throw dem::InputError(path + ": " + one_line(e) + "; valid names and ranges: " + print_command);
  }
}

}  // namespace trackbed::cases
