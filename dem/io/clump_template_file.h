// Clump templates from CSV files: one sphere a row (docs/clumps.md).
#pragma once

#include <string>

#include "dem/engine/clump_template.h"

namespace trackbed::dem {

// Reads the spheres of a template from a CSV file and makes the template. The header line names
// the columns x, y, z and radius in any order (extra columns are ignored); each further line is
// one sphere in metres; '#' comment lines and blank lines are skipped. Bad input throws
// InputError with the file and line (docs/clumps.md).
ClumpTemplate read_clump_template_csv(const std::string& path, const std::string& name);

}  // namespace trackbed::dem
