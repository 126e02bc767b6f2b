#include "dem/samples/template_library.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "common/input_error.h"
#include "dem/io/atomic_file.h"
#include "dem/io/clump_template_file.h"
#include "dem/io/csv_table.h"
#include "dem/samples/closed_surface.h"

namespace trackbed::dem {
namespace {

namespace fs = std::filesystem;

constexpr const char* kColumns[] = {
    "name",          "setting",        "distance",     "ratio",        "resolution", "seed",
    "surface",       "pebbles",        "pebble_count", "min_radius",   "max_radius", "volume_error",
    "inertia_error", "surface_volume", "longest",      "intermediate", "shortest",   "elongation",
    "flatness",      "sphericity",     "angularity",   "faces",        "sieve_size"};

// The columns the reader needs; the others document how a row was made.
constexpr const char* kRequired[] = {
    "name",     "setting",    "surface",  "pebbles",    "pebble_count", "longest", "intermediate",
    "shortest", "elongation", "flatness", "sphericity", "angularity",   "faces",   "sieve_size"};

bool parse_number(const std::string& text, double& value) {
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, value);
  return ec == std::errc() && ptr == end && std::isfinite(value);
}

// A file named in row `row`, resolved against the manifest's folder; it must exist.
std::string library_file(const CsvTable& csv, int row, const std::string& column) {
  const std::string& name = csv.text(row, column);
  const fs::path path = fs::path(csv.path()).parent_path() / name;
  std::error_code ec;
  if (name.empty() || !fs::is_regular_file(path, ec)) {
    throw input_error_at(csv.path(), csv.line_of(row),
                         column + " file '" + name + "' not found (looked for " + path.string() +
                             "); name an existing file relative to the manifest's folder");
  }
  return path.string();
}

ShapeIndices row_shape(const CsvTable& csv, int row) {
  ShapeIndices s;
  s.longest = csv.number(row, "longest");
  s.intermediate = csv.number(row, "intermediate");
  s.shortest = csv.number(row, "shortest");
  s.elongation = csv.number(row, "elongation");
  s.flatness = csv.number(row, "flatness");
  s.sphericity = csv.number(row, "sphericity");
  s.angularity = csv.number(row, "angularity");
  const double faces = csv.number(row, "faces");
  s.faces = static_cast<int>(faces);
  s.sieve_size = csv.number(row, "sieve_size");
  if (!(s.sieve_size > 0.0) || s.faces != faces || s.faces < 4) {
    throw input_error_at(csv.path(), csv.line_of(row),
                         "sieve_size '" + csv.text(row, "sieve_size") + "' or faces '" +
                             csv.text(row, "faces") +
                             "' is not valid; the sieve size is > 0 (metres), faces a whole "
                             "number >= 4");
  }
  return s;
}

ClumpTemplate row_clump(const CsvTable& csv, int row, MassSource source) {
  const std::string name = csv.text(row, "name");
  const std::string pebble_path = library_file(csv, row, "pebbles");
  ClumpTemplate clump = read_clump_template_csv(pebble_path, name);
  const double count = csv.number(row, "pebble_count");
  if (count != static_cast<double>(clump.spheres.size())) {
    throw input_error_at(csv.path(), csv.line_of(row),
                         "pebble_count " + csv.text(row, "pebble_count") + " but '" +
                             csv.text(row, "pebbles") + "' holds " +
                             std::to_string(clump.spheres.size()) +
                             " pebbles; regenerate the library with trackbed-templates");
  }
  const std::string surface_path = library_file(csv, row, "surface");
  if (source == MassSource::pebbles) return clump;
  // The pebbles back in the file's frame, which is the surface's.
  std::vector<SphereShape> pebbles;
  for (const SphereShape& s : clump.spheres) {
    pebbles.push_back({clump.input_centroid + clump.input_axes * s.centre, s.radius});
  }
  return make_clump_template_with_mass(name, pebbles,
                                       surface_mass_properties(read_closed_surface(surface_path)));
}

}  // namespace

std::vector<LibraryTemplate> read_template_library(const std::string& manifest,
                                                   const std::string& setting, MassSource source) {
  const CsvTable csv(manifest, "template library manifest");
  for (const char* c : kRequired) csv.require(c);
  std::vector<std::string> known;
  for (int row = 0; row < csv.num_rows(); ++row) {
    const std::string& s = csv.text(row, "setting");
    if (std::find(known.begin(), known.end(), s) == known.end()) known.push_back(s);
  }
  if (std::find(known.begin(), known.end(), setting) == known.end()) {
    std::string list;
    for (const std::string& s : known) list += (list.empty() ? "" : ", ") + s;
    throw InputError(manifest + ": setting '" + setting + "' is not in the library; known " +
                     "settings: " + (list.empty() ? "none (the manifest has no rows)" : list));
  }
  std::vector<LibraryTemplate> out;
  for (int row = 0; row < csv.num_rows(); ++row) {
    if (csv.text(row, "setting") != setting) continue;
    LibraryTemplate t;
    t.shape = row_shape(csv, row);
    t.sieve_size = t.shape.sieve_size;
    t.setting = setting;
    t.clump = row_clump(csv, row, source);
    out.push_back(std::move(t));
  }
  return out;
}

std::string setting_name(const BubblePackSettings& settings) {
  std::ostringstream s;
  s << "D" << settings.distance << "R" << settings.ratio;
  return s.str();
}

BubblePackSettings parse_setting(const std::string& name, const BubblePackSettings& defaults) {
  BubblePackSettings s = defaults;
  const std::size_t r = name.find('R');
  if (name.size() < 4 || name[0] != 'D' || r == std::string::npos ||
      !parse_number(name.substr(1, r - 1), s.distance) ||
      !parse_number(name.substr(r + 1), s.ratio)) {
    throw InputError("bubble-pack setting '" + name +
                     "' is not valid; write D<distance>R<ratio>, e.g. D120R0.5");
  }
  return s;
}

void write_ascii_stl(const TriangleMesh& surface, const std::string& path,
                     const std::string& name) {
  AtomicFile file(path);
  std::ofstream& out = file.stream();
  out << std::setprecision(8);
  out << "solid " << name << "\n";
  for (int t = 0; t < static_cast<int>(surface.triangles.size()); ++t) {
    const Vec3 n = surface.triangle_normal(t);
    out << "facet normal " << n.x() << " " << n.y() << " " << n.z() << "\nouter loop\n";
    for (int v : surface.triangles[t]) {
      const Vec3& p = surface.vertices[v];
      out << "vertex " << p.x() << " " << p.y() << " " << p.z() << "\n";
    }
    out << "endloop\nendfacet\n";
  }
  out << "endsolid " << name << "\n";
  file.commit();
}

void write_pebble_csv(const std::vector<SphereShape>& pebbles, const std::string& path,
                      const std::string& comment) {
  AtomicFile file(path);
  std::ofstream& out = file.stream();
  out << std::setprecision(9);
  out << "# " << comment << "\nx,y,z,radius\n";
  for (const SphereShape& p : pebbles) {
    out << p.centre.x() << "," << p.centre.y() << "," << p.centre.z() << "," << p.radius << "\n";
  }
  file.commit();
}

void write_manifest(const std::vector<LibraryEntry>& entries, const std::string& path) {
  AtomicFile file(path);
  std::ofstream& out = file.stream();
  out << std::setprecision(8);
  out << "# trackbed clump template library: one row per template; lengths in metres, angles in "
         "degrees (docs/templates.md)\n";
  for (const char* c : kColumns) out << (c == kColumns[0] ? "" : ",") << c;
  out << "\n";
  for (const LibraryEntry& e : entries) {
    const BubblePackResult& p = e.packing;
    const ShapeIndices& s = e.shape;
    out << e.name << "," << e.setting << "," << e.pack.distance << "," << e.pack.ratio << ","
        << e.pack.resolution << "," << e.seed << "," << e.surface_file << "," << e.pebble_file
        << "," << p.pebble_count() << "," << p.min_radius << "," << p.max_radius << ","
        << p.volume_error << "," << p.inertia_error << "," << p.surface_mass.volume << ","
        << s.longest << "," << s.intermediate << "," << s.shortest << "," << s.elongation << ","
        << s.flatness << "," << s.sphericity << "," << s.angularity << "," << s.faces << ","
        << s.sieve_size << "\n";
  }
  file.commit();
}

}  // namespace trackbed::dem
