#include "dem/clump_template.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>
#include <utility>

#include "dem/input_error.h"

namespace trackbed::dem {
namespace {

constexpr double kPi = 3.14159265358979323846;

std::string trim(const std::string& s) {
  const auto begin = s.find_first_not_of(" \t\r");
  if (begin == std::string::npos) return "";
  return s.substr(begin, s.find_last_not_of(" \t\r") - begin + 1);
}

// Splits on every comma, so "1,2,3," has four fields and the count check catches it.
std::vector<std::string> split_fields(const std::string& line) {
  std::vector<std::string> fields;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    fields.push_back(trim(line.substr(start, comma - start)));
    if (comma == std::string::npos) return fields;
    start = comma + 1;
  }
}

// from_chars, unlike strtod, ignores the C locale: "0.5" is read the same everywhere.
bool parse_double(const std::string& text, double& value) {
  if (text.empty()) return false;
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, value);
  return ec == std::errc() && ptr == end;
}

}  // namespace

double ClumpTemplate::equivalent_radius() const {
  return std::cbrt(3.0 * volume / (4.0 * kPi));
}

ClumpTemplate make_clump_template(std::string name,
                                  const std::vector<SphereShape>& spheres_in_any_frame,
                                  double relative_tolerance) {
  MassProperties mp;
  try {
    mp = sphere_union_mass_properties(spheres_in_any_frame, relative_tolerance);
  } catch (const InputError& e) {
    throw InputError("clump template '" + name + "': " + e.what());
  }
  ClumpTemplate t;
  t.name = std::move(name);
  t.volume = mp.volume;
  t.principal_moments = mp.principal_moments;
  t.bounding_radius = 0.0;
  // principal_axes maps principal to input coordinates; its transpose maps back.
  const Mat3 to_principal = mp.principal_axes.transpose();
  t.spheres.reserve(spheres_in_any_frame.size());
  for (const SphereShape& sp : spheres_in_any_frame) {
    const SphereShape moved{to_principal * (sp.centre - mp.centroid), sp.radius};
    t.bounding_radius = std::max(t.bounding_radius, moved.centre.norm() + moved.radius);
    t.spheres.push_back(moved);
  }
  return t;
}

ClumpTemplate scaled(const ClumpTemplate& clump, double factor) {
  if (!(std::isfinite(factor) && factor > 0.0)) {
    std::ostringstream msg;
    msg << "clump template '" << clump.name << "': scale factor " << factor
        << " is not valid; it must be finite and > 0";
    throw InputError(msg.str());
  }
  ClumpTemplate t = clump;
  for (SphereShape& sp : t.spheres) {
    sp.centre *= factor;
    sp.radius *= factor;
  }
  t.volume *= factor * factor * factor;
  // Inertia per unit density is a volume times a squared length.
  t.principal_moments *= std::pow(factor, 5);
  t.bounding_radius *= factor;
  return t;
}

ClumpTemplate read_clump_template_csv(const std::string& path, const std::string& name) {
  std::ifstream in(path);
  if (!in) {
    throw InputError(path + ": cannot open clump template file '" + name +
                     "'; valid: an existing, readable CSV file with columns x,y,z,radius");
  }
  static const std::array<std::string, 4> kColumns = {"x", "y", "z", "radius"};
  std::array<std::size_t, 4> column_of{};
  std::size_t num_fields = 0;
  int header_line = 0;

  std::vector<SphereShape> spheres;
  std::string line;
  int lineno = 0;
  while (std::getline(in, line)) {
    ++lineno;
    const std::string text = trim(line);
    if (text.empty() || text[0] == '#') continue;
    const std::vector<std::string> fields = split_fields(text);

    if (header_line == 0) {
      for (std::size_t c = 0; c < kColumns.size(); ++c) {
        std::size_t found = fields.size();
        for (std::size_t f = 0; f < fields.size(); ++f) {
          if (fields[f] != kColumns[c]) continue;
          if (found != fields.size()) {
            throw input_error_at(path, lineno,
                                 "column '" + kColumns[c] + "' appears twice in the header");
          }
          found = f;
        }
        if (found == fields.size()) {
          throw input_error_at(path, lineno,
                               "header has no column '" + kColumns[c] +
                                   "'; it must name the columns x,y,z,radius (any order, extra "
                                   "columns ignored)");
        }
        column_of[c] = found;
      }
      num_fields = fields.size();
      header_line = lineno;
      continue;
    }

    if (fields.size() != num_fields) {
      throw input_error_at(path, lineno,
                           "row has " + std::to_string(fields.size()) +
                               " fields but the header (line " + std::to_string(header_line) +
                               ") has " + std::to_string(num_fields) +
                               "; give one value per header column");
    }
    std::array<double, 4> values{};
    for (std::size_t c = 0; c < kColumns.size(); ++c) {
      const std::string& field = fields[column_of[c]];
      if (!parse_double(field, values[c]) || !std::isfinite(values[c])) {
        throw input_error_at(path, lineno,
                             "column '" + kColumns[c] + "': '" + field +
                                 "' is not valid; it must be a finite number (metres)");
      }
    }
    if (!(values[3] > 0.0)) {
      throw input_error_at(
          path, lineno,
          "radius " + fields[column_of[3]] + " is not valid; a sphere radius must be > 0 (metres)");
    }
    spheres.push_back({Vec3(values[0], values[1], values[2]), values[3]});
  }

  if (header_line == 0) {
    throw input_error_at(path, std::max(lineno, 1),
                         "clump template '" + name +
                             "' has no header line; the file needs a header x,y,z,radius and "
                             "one row per sphere");
  }
  if (spheres.empty()) {
    throw input_error_at(path, header_line,
                         "clump template '" + name +
                             "' has no spheres after the header; give at least one row with "
                             "x,y,z,radius");
  }
  return make_clump_template(name, spheres);
}

}  // namespace trackbed::dem
