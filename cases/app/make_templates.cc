// trackbed-templates: (re)generates the ballast clump template library, or packs one STL surface
// with pebbles (docs/templates.md).
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "common/input_error.h"
#include "dem/samples/ballast_stone.h"
#include "dem/samples/bubble_pack.h"
#include "dem/samples/closed_surface.h"
#include "dem/samples/template_library.h"

namespace {

using namespace trackbed::dem;
namespace fs = std::filesystem;

constexpr const char* kUsage =
    "usage:\n"
    "  trackbed-templates [--count N] [--seed S] [--settings D120R0.5,D130R0.4]\n"
    "                     [--resolution N] [--output DIR]\n"
    "      makes N random ballast stones (seeds S, S+1, ...; default 24 from 1), packs each at\n"
    "      every setting and writes DIR/stoneNN.stl, DIR/stoneNN-SETTING.csv and\n"
    "      DIR/library.csv (default DIR: cases/templates/ballast)\n"
    "  trackbed-templates --stl FILE --distance D --ratio R [--resolution N]\n"
    "                     [--output FILE.csv]\n"
    "      packs one closed STL surface and prints its pebble count, radii, errors and shape\n"
    "      indices; with --output also writes the pebbles as a template CSV\n";

struct Options {
  int count = 24;
  long long seed = 1;
  std::vector<std::string> settings = {"D120R0.5", "D130R0.4"};
  std::string output;
  std::string stl;
  BubblePackSettings pack;
  bool distance_given = false, ratio_given = false;
};

[[noreturn]] void usage_error(const std::string& message) {
  std::cerr << "trackbed-templates: " << message << "\n" << kUsage;
  std::exit(2);
}

// A whole number in [lo, hi] or a usage error naming the option.
long long whole_number(const std::string& option, const std::string& text, long long lo,
                       long long hi) {
  char* end = nullptr;
  const long long value = std::strtoll(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || value < lo || value > hi) {
    usage_error(option + " '" + text + "' is not valid; give a whole number from " +
                std::to_string(lo) + " to " + std::to_string(hi));
  }
  return value;
}

double real_number(const std::string& option, const std::string& text) {
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0') usage_error(option + " '" + text + "' is not a number");
  return value;
}

std::vector<std::string> split(const std::string& list) {
  std::vector<std::string> out;
  std::size_t start = 0;
  while (start <= list.size()) {
    const std::size_t comma = std::min(list.find(',', start), list.size());
    out.push_back(list.substr(start, comma - start));
    start = comma + 1;
  }
  return out;
}

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--help" || arg == "-h") {
      std::cout << kUsage;
      std::exit(0);
    }
    if (i + 1 >= argc) usage_error("option " + arg + " needs a value, or is unknown");
    const std::string value = argv[++i];
    if (arg == "--count") {
      o.count = static_cast<int>(whole_number(arg, value, 1, 999));
    } else if (arg == "--seed") {
      o.seed = whole_number(arg, value, 0, 1LL << 60);
    } else if (arg == "--settings") {
      o.settings = split(value);
    } else if (arg == "--resolution") {
      o.pack.resolution = static_cast<int>(whole_number(arg, value, 8, 256));
    } else if (arg == "--output") {
      o.output = value;
    } else if (arg == "--stl") {
      o.stl = value;
    } else if (arg == "--distance") {
      o.pack.distance = real_number(arg, value);
      o.distance_given = true;
    } else if (arg == "--ratio") {
      o.pack.ratio = real_number(arg, value);
      o.ratio_given = true;
    } else {
      usage_error("unknown option " + arg);
    }
  }
  if (!o.stl.empty() && !(o.distance_given && o.ratio_given)) {
    usage_error("--stl needs --distance and --ratio");
  }
  return o;
}

void print_packing(const std::string& name, const BubblePackResult& p, const ShapeIndices& s) {
  std::printf(
      "%-20s pebbles %4d  radii %.4g-%.4g m  volume error %+.3f  inertia error %.3f  "
      "L %.4g I %.4g S %.4g m  I/L %.2f S/I %.2f  sphericity %.3f  angularity %.1f deg  "
      "faces %d  sieve %.4g m\n",
      name.c_str(), p.pebble_count(), p.min_radius, p.max_radius, p.volume_error, p.inertia_error,
      s.longest, s.intermediate, s.shortest, s.elongation, s.flatness, s.sphericity, s.angularity,
      s.faces, s.sieve_size);
}

int pack_one_stl(const Options& o) {
  const TriangleMesh surface = read_closed_surface(o.stl);
  const BubblePackResult p = bubble_pack(surface, o.pack, o.stl);
  print_packing(fs::path(o.stl).stem().string(), p, shape_indices(surface));
  std::printf(
      "principal moments per unit density: surface %.6g %.6g %.6g, pebbles %.6g %.6g %.6g\n",
      p.surface_mass.principal_moments[0], p.surface_mass.principal_moments[1],
      p.surface_mass.principal_moments[2], p.pebble_mass.principal_moments[0],
      p.pebble_mass.principal_moments[1], p.pebble_mass.principal_moments[2]);
  if (!o.output.empty()) {
    write_pebble_csv(p.pebbles, o.output,
                     o.stl + " packed at " + setting_name(o.pack) + ", " +
                         std::to_string(p.pebble_count()) + " pebbles, metres, frame of the STL");
    std::printf("wrote %s\n", o.output.c_str());
  }
  return 0;
}

int make_library(const Options& o) {
  const fs::path folder = o.output.empty() ? "cases/templates/ballast" : o.output;
  fs::create_directories(folder);
  std::vector<BubblePackSettings> packs;
  for (const std::string& s : o.settings) packs.push_back(parse_setting(s, o.pack));
  std::vector<LibraryEntry> entries;
  for (int i = 0; i < o.count; ++i) {
    char stem[32];
    std::snprintf(stem, sizeof stem, "stone%02d", i + 1);
    const std::string surface_file = std::string(stem) + ".stl";
    const long long seed = o.seed + i;
    write_ascii_stl(make_ballast_stone(static_cast<std::uint64_t>(seed)),
                    (folder / surface_file).string(), stem);
    // Everything is computed from the surface as read back, so the manifest matches what a
    // reader of the files computes.
    const TriangleMesh surface = read_closed_surface((folder / surface_file).string());
    const ShapeIndices shape = shape_indices(surface);
    for (const BubblePackSettings& pack : packs) {
      LibraryEntry e;
      e.setting = setting_name(pack);
      e.name = std::string(stem) + "-" + e.setting;
      e.surface_file = surface_file;
      e.pebble_file = e.name + ".csv";
      e.pack = pack;
      e.seed = seed;
      e.shape = shape;
      e.packing = bubble_pack(surface, pack, e.name);
      write_pebble_csv(e.packing.pebbles, (folder / e.pebble_file).string(),
                       e.name + ": " + std::to_string(e.packing.pebble_count()) +
                           " pebbles filling " + surface_file + " (same frame), metres");
      print_packing(e.name, e.packing, shape);
      entries.push_back(std::move(e));
    }
  }
  write_manifest(entries, (folder / "library.csv").string());
  std::printf("wrote %zu templates to %s\n", entries.size(), (folder / "library.csv").c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const Options options = parse(argc, argv);
  try {
    return options.stl.empty() ? make_library(options) : pack_one_stl(options);
  } catch (const std::exception& e) {
    std::cerr << "trackbed-templates: error: " << e.what() << "\n";
    return 1;
  }
}
