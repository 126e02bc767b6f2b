// The library of ballast clump templates shipped in cases/templates/ballast/: stone surfaces
// (STL), their pebbles at each bubble-pack setting (template CSV) and a manifest, library.csv,
// with one row per template (docs/templates.md). Reading for the sample builder, writing for
// trackbed-templates.
#pragma once

#include <string>
#include <vector>

#include "dem/engine/clump_template.h"
#include "dem/engine/triangle_mesh.h"
#include "dem/samples/ballast_stone.h"
#include "dem/samples/bubble_pack.h"

namespace trackbed::dem {

struct LibraryTemplate {
  ClumpTemplate clump;
  // Metres: the sieve size of the stone's surface at the scale of `clump` (scaling the clump by f
  // scales it by f); ShapeIndices::sieve_size defines it.
  double sieve_size = 0.0;
  ShapeIndices shape;
  std::string setting;  // e.g. "D120R0.5"
};

// All templates of one setting of the manifest, in manifest order, with mass properties from
// `source` (surface: from the STL the row names, which must pass check_closed_surface; pebbles:
// the union of the pebbles). File names in the manifest are relative to its folder. Throws
// InputError naming the manifest and line for a missing file, a malformed row or a pebble count
// that does not match the pebble file, and for an unknown setting, listing the known ones.
std::vector<LibraryTemplate> read_template_library(const std::string& manifest,
                                                   const std::string& setting, MassSource source);

// "D<distance>R<ratio>", e.g. "D120R0.5", and back. parse_setting keeps the other fields of
// `defaults` and throws InputError (naming the text and the valid form) for anything else.
std::string setting_name(const BubblePackSettings& settings);
BubblePackSettings parse_setting(const std::string& name, const BubblePackSettings& defaults);

// One manifest row: a packed stone.
struct LibraryEntry {
  std::string name, setting, surface_file, pebble_file;  // files relative to the manifest
  BubblePackSettings pack;
  long long seed = -1;  // of make_ballast_stone; -1 for a surface from elsewhere
  ShapeIndices shape;
  BubblePackResult packing;
};

// ASCII STL, one solid named `name`, 8 significant digits (a 1e-8 relative rounding, far below
// the 1e-6 vertex-merging tolerance, so the file reads back as the same closed surface).
void write_ascii_stl(const TriangleMesh& surface, const std::string& path, const std::string& name);
// A template CSV (docs/clumps.md) of the pebbles, 9 significant digits, with `comment` on top.
void write_pebble_csv(const std::vector<SphereShape>& pebbles, const std::string& path,
                      const std::string& comment);
void write_manifest(const std::vector<LibraryEntry>& entries, const std::string& path);

}  // namespace trackbed::dem
