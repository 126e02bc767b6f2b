// Helpers shared by the readers of trackbed's parameter files (case files and sample files):
// declaring and reading vectors, and turning deal.II's exceptions into one line. Includes
// deal.II's ParameterHandler: only for the .cc files that read parameters.
#pragma once

#include <deal.II/base/parameter_handler.h>

#include <array>
#include <exception>
#include <string>

#include "dem/types.h"

namespace trackbed::cases {

void declare_vector(dealii::ParameterHandler& prm, const std::string& name, const std::string& def,
                    const std::string& doc);
dem::Vec3 vector_of(const dealii::ParameterHandler& prm, const std::string& name);
std::array<double, 6> six_of(const dealii::ParameterHandler& prm, const std::string& name);
// deal.II's exception text is several lines; users get the "additional information" part as
// one line.
std::string one_line(const std::exception& e);
// Parses `path` into `prm` (declared by the caller); throws dem::InputError naming the file and
// pointing at `trackbed --print-parameters` for a missing file or a parse error.
void parse_parameter_file(dealii::ParameterHandler& prm, const std::string& path,
                          const std::string& print_command);

}  // namespace trackbed::cases
