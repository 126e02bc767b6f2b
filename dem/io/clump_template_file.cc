#include "dem/io/clump_template_file.h"

#include <vector>

#include "common/input_error.h"
#include "dem/io/csv_table.h"

namespace trackbed::dem {

ClumpTemplate read_clump_template_csv(const std::string& path, const std::string& name) {
  const std::string what = "clump template '" + name + "'";
  const CsvTable csv(path, what);
  for (const char* c : {"x", "y", "z", "radius"}) csv.require(c);
  std::vector<SphereShape> spheres;
  for (int row = 0; row < csv.num_rows(); ++row) {
    const double r = csv.number(row, "radius");
    if (!(r > 0.0))
      throw input_error_at(path, csv.line_of(row),
                           "radius " + csv.text(row, "radius") +
                               " is not valid; a sphere radius must be > 0 (metres)");
    spheres.push_back({Vec3(csv.number(row, "x"), csv.number(row, "y"), csv.number(row, "z")), r});
  }
  if (spheres.empty())
    throw input_error_at(path, csv.header_line(),
                         what +
                             " has no spheres after the header; give at least one row with "
                             "x,y,z,radius");
  return make_clump_template(name, spheres);
}

}  // namespace trackbed::dem
