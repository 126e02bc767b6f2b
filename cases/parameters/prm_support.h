// Helpers shared by the readers of trackbed's parameter files (case files and sample files):
// declaring and reading vectors, and turning deal.II's exceptions into one line. Includes
// deal.II's ParameterHandler: only for the .cc files that read parameters.
#pragma once

#include <deal.II/base/parameter_handler.h>

#include <array>
#include <exception>
#include <map>
#include <stdexcept>
#include <string>

#include "common/input_error.h"
#include "dem/engine/material.h"
#include "dem/engine/types.h"

namespace trackbed::cases {

void declare_vector(dealii::ParameterHandler& prm, const std::string& name, const std::string& def,
                    const std::string& doc);
dem::Vec3 vector_of(const dealii::ParameterHandler& prm, const std::string& name);
std::array<double, 6> six_of(const dealii::ParameterHandler& prm, const std::string& name);
// The entries of a material's subsection (density, stiffnesses, friction, rolling friction,
// dashpots, local damping) with the values of `defaults`, and their reading; the caller enters
// and leaves the subsection. `role` is added to the density's documentation.
void declare_material_values(dealii::ParameterHandler& prm, const dem::Material& defaults,
                             const std::string& role = "");
void read_material_values(const dealii::ParameterHandler& prm, dem::Material& m);
// Every parameter's value as read, one "subsection/name = value" line each, except those that do
// not change what a run or a build computes (where it writes, how often it reports or
// checkpoints, its threads: a resumed one may set them anew). `trackbed resume` compares them.
std::string fingerprint(const dealii::ParameterHandler& prm);
// deal.II's exception text is several lines; users get the "additional information" part as
// one line.
std::string one_line(const std::exception& e);
// Which file set each parameter last, so that a relative file name in a value resolves against
// the folder of the file that wrote it: an included sample or case file keeps its own paths.
class ValueFolders {
 public:
  // The folder of the file that set `key` ("subsection/.../name") last; the top-level file's
  // folder for a value left at its default.
  std::string folder_of(const std::string& key) const;
  // `value` when empty or absolute, else `value` from folder_of(key), normalised.
  std::string resolve(const std::string& key, const std::string& value) const;

 private:
  friend ValueFolders parse_parameter_file(dealii::ParameterHandler&, const std::string&,
                                           const std::string&);
  std::string top_;
  std::map<std::string, std::string> set_in_;
};

// Parses `path` into `prm` (declared by the caller); throws InputError naming the file and
// pointing at `trackbed --print-parameters` for a missing file or a parse error. Files named by
// 'include FILE' lines are found relative to the folder of the file that names them; errors
// name the file and line they are in. Returns where each value was set, for resolving paths.
ValueFolders parse_parameter_file(dealii::ParameterHandler& prm, const std::string& path,
                                  const std::string& print_command);

// Where the values being read come from, for the parse_ function of each subsection: the
// parameter file (for messages) and the folder of the file that set each value (relative file
// names resolve against it).
struct ParameterSource {
  const std::string& path;
  const ValueFolders& folders;
};

// The `name` entry of the subsection the caller is in (a material, wall or mesh): names head CSV
// columns and JSON keys, so InputError at `where` unless 1 to 64 letters, digits, '_', '-', '.'.
std::string name_of(const dealii::ParameterHandler& prm, const std::string& where);

// Runs `read` (the parse_ functions of a parameter file at `path`): a value that matched its
// pattern but that deal.II or the standard library cannot convert (a subnormal number, an integer
// beyond range) becomes one InputError line naming the file and the entry.
template <class Read>
void read_values(const std::string& path, Read&& read);

// The `folder` entry of the output subsection the caller is in; InputError naming the file when
// it is empty (a run or build would write under the root folder).
std::string output_folder_of(const dealii::ParameterHandler& prm, const ParameterSource& in);

// The InputError of read_values: the file and the exception's text as one line.
InputError value_error(const std::string& path, const std::exception& e);

template <class Read>
void read_values(const std::string& path, Read&& read) {
  try {
    read();
  } catch (const dealii::ExceptionBase& e) {
    throw value_error(path, e);
  } catch (const std::logic_error& e) {  // std::stol and the like: invalid_argument, out_of_range
    throw value_error(path, e);
  }
}

}  // namespace trackbed::cases
