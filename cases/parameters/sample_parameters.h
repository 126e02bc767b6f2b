// The contents of a sample file (.prm, deal.II ParameterHandler syntax) for `trackbed
// build-sample`: the section, the grading, the materials, the build and the zone of clumps.
// Only sample_parameters.cc sees deal.II. Parameters, units and defaults: docs/samples.md and
// `trackbed build-sample --print-parameters`.
#pragma once

#include <iosfwd>
#include <string>

#include "dem/samples/bubble_pack.h"
#include "dem/samples/clump_conversion.h"
#include "dem/samples/sample_builder.h"

namespace trackbed::cases {

struct SampleParameters {
  std::string file;                // the sample file this came from
  dem::SampleBuildSettings build;  // section, materials, grading and the build stages
  // Zone of clumps: a preset or an expression (dem/samples/zone.h). all-ball builds the ball
  // sample; anything else converts the balls in the zone of `base_sample` (built first when empty).
  std::string preset = "all-ball";
  std::string zone_text;    // the custom zone (a preset's is made for the base sample's section)
  std::string zone_folder;  // where the zone's relative names (pilot runs) resolve
  std::string base_sample;
  std::string templates;  // library manifest
  std::string template_setting = "D120R0.5";
  dem::MassSource mass_from = dem::MassSource::surface;
  dem::ConversionSettings conversion;
  int threads = 0;
  std::string fingerprint;  // fingerprint() of the parameters, for 'trackbed resume'
  // output
  std::string output_folder = "results/samples/section";
  double progress_interval = 5;
  double checkpoint_interval = 600;  // wall s between checkpoints of a conversion; 0: none
  bool vtu = true, plot = true;
};

// Reads and validates a sample file; a relative path in it resolves against the folder of the
// file that set it (the sample file or a file it includes). Throws
// InputError with one line naming the file and the parameter.
SampleParameters read_sample_file(const std::string& path);
void print_sample_parameters(std::ostream& out, bool json = false);

// The zone expression of a preset for a section, with the push toward +x: all-clump, all-ball,
// half-by-height, optimised (docs/samples.md, "Zone presets"). Throws InputError for an unknown
// name, listing the valid ones.
std::string preset_zone(const std::string& preset, const TrackSection& section);

}  // namespace trackbed::cases
