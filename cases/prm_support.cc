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
