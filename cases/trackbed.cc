// trackbed: railway ballast track simulator. The command line:
//   trackbed run CASE.prm [--mode dem] [--threads N] [--output DIR]
//   trackbed build-sample SAMPLE.prm [--threads N] [--output DIR]
//   trackbed --print-parameters      every case-file parameter with default and documentation
//   trackbed build-sample --print-parameters   the same for sample files
//   trackbed --help | --version
#include <exception>
#include <iostream>
#include <string>
#include <vector>

#include "cases/case_parameters.h"
#include "cases/dem_run.h"
#include "cases/sample_parameters.h"
#include "cases/sample_run.h"
#include "dem/input_error.h"

namespace {

const char* const kUsage =
    "usage: trackbed run CASE.prm [--mode dem|coupled] [--threads N] [--output DIR]\n"
    "       trackbed build-sample SAMPLE.prm [--threads N] [--output DIR]\n"
    "       trackbed --print-parameters | build-sample --print-parameters\n"
    "       trackbed --help | --version\n"
    "\n"
    "Runs the railway ballast model described by CASE.prm (deal.II parameter file syntax) and\n"
    "writes a results folder: CSV histories, ParaView files, HDF5 snapshots, summary.json,\n"
    "summary.txt and plot.png. The default case is cases/default.prm.\n"
    "build-sample builds a ballast sample of a track section (deposition, compaction, sleeper\n"
    "seating, balls converted to clumps in a zone) and writes sample.h5 for cases to load.\n"
    "  --mode      override 'mode' (dem: DEM with rigid walls; coupled: with the FE tier)\n"
    "  --threads   OpenMP threads (overrides 'simulation/threads')\n"
    "  --output    results folder (overrides 'output/folder')\n";

int fail(const std::string& message, int code = 2) {
  std::cerr << "trackbed: error: " << message << std::endl;
  return code;
}

// The options common to run and build-sample: --threads N and --output DIR (and --mode for run).
// Returns an error message, or "" when every option was understood.
std::string parse_options(const std::vector<std::string>& args, bool with_mode, std::string& mode,
                          int& threads, std::string& output) {
  for (std::size_t i = 2; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (i + 1 >= args.size()) return "option '" + a + "' needs a value";
    const std::string& v = args[++i];
    if (a == "--mode" && with_mode) {
      if (v != "dem" && v != "coupled") return "--mode " + v + ": valid: dem, coupled";
      mode = v;
    } else if (a == "--threads") {
      try {
        threads = std::stoi(v);
      } catch (const std::exception&) {
        threads = -1;
      }
      if (threads < 0) return "--threads " + v + ": valid: an integer >= 0 (0: OMP_NUM_THREADS)";
    } else if (a == "--output") {
      output = v;
    } else {
      return "unknown option '" + a +
             "'; valid: " + (with_mode ? "--mode, --threads, --output" : "--threads, --output");
    }
  }
  return "";
}

int build_sample(const std::vector<std::string>& args) {
  if (args.size() >= 2 && args[1] == "--print-parameters") {
    trackbed::cases::print_sample_parameters(std::cout);
    return 0;
  }
  if (args.size() < 2)
    return fail("'build-sample' needs a sample file: trackbed build-sample SAMPLE.prm");
  trackbed::cases::SampleParameters prm = trackbed::cases::read_sample_file(args[1]);
  std::string unused;
  const std::string bad = parse_options(args, false, unused, prm.threads, prm.output_folder);
  if (!bad.empty()) return fail(bad);
  trackbed::cases::SampleRun run(std::move(prm));
  return run.run();
}

}  // namespace

int main(int argc, char** argv) {
  const std::vector<std::string> args(argv + 1, argv + argc);
  if (args.empty()) return fail(std::string("no command given\n") + kUsage);
  if (args[0] == "--help" || args[0] == "-h") {
    std::cout << kUsage;
    return 0;
  }
  if (args[0] == "--version") {
    std::cout << "trackbed " << TRACKBED_VERSION << std::endl;
    return 0;
  }
  if (args[0] == "--print-parameters") {
    trackbed::cases::print_parameters(std::cout);
    return 0;
  }
  if (args[0] != "run" && args[0] != "build-sample")
    return fail("unknown command '" + args[0] +
                "'; valid: run, build-sample, --print-parameters, --help, --version");
  try {
    if (args[0] == "build-sample") return build_sample(args);
    if (args.size() < 2) return fail("'run' needs a case file: trackbed run CASE.prm");
    trackbed::cases::CaseParameters prm = trackbed::cases::read_case_file(args[1]);
    const std::string bad = parse_options(args, true, prm.mode, prm.threads, prm.output_folder);
    if (!bad.empty()) return fail(bad);
    if (prm.mode == "coupled")
      return fail(prm.file +
                  ": mode = coupled needs the FE tier, which this build does not "
                  "have yet; valid: mode = dem");
    trackbed::cases::DemRun run(std::move(prm));
    return run.run();
  } catch (const trackbed::dem::InputError& e) {
    return fail(e.what());
  } catch (const std::exception& e) {
    return fail(e.what(), 1);
  }
}
