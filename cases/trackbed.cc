// trackbed: railway ballast track simulator. The command line:
//   trackbed run CASE.prm [--mode dem] [--threads N] [--output DIR]
//   trackbed --print-parameters      every case-file parameter with default and documentation
//   trackbed --help | --version
#include <exception>
#include <iostream>
#include <string>
#include <vector>

#include "cases/case_parameters.h"
#include "cases/dem_run.h"
#include "dem/input_error.h"

namespace {

const char* const kUsage =
    "usage: trackbed run CASE.prm [--mode dem|coupled] [--threads N] [--output DIR]\n"
    "       trackbed --print-parameters\n"
    "       trackbed --help | --version\n"
    "\n"
    "Runs the railway ballast model described by CASE.prm (deal.II parameter file syntax) and\n"
    "writes a results folder: CSV histories, ParaView files, HDF5 snapshots, summary.json,\n"
    "summary.txt and plot.png. The default case is cases/default.prm.\n"
    "  --mode      override 'mode' (dem: DEM with rigid walls; coupled: with the FE tier)\n"
    "  --threads   OpenMP threads (overrides 'simulation/threads')\n"
    "  --output    results folder (overrides 'output/folder')\n";

int fail(const std::string& message, int code = 2) {
  std::cerr << "trackbed: error: " << message << std::endl;
  return code;
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
  if (args[0] != "run")
    return fail("unknown command '" + args[0] +
                "'; valid: run, --print-parameters, --help, "
                "--version");
  if (args.size() < 2) return fail("'run' needs a case file: trackbed run CASE.prm");

  try {
    trackbed::cases::CaseParameters prm = trackbed::cases::read_case_file(args[1]);
    for (std::size_t i = 2; i < args.size(); ++i) {
      const std::string& a = args[i];
      if (i + 1 >= args.size()) return fail("option '" + a + "' needs a value");
      const std::string& v = args[++i];
      if (a == "--mode") {
        if (v != "dem" && v != "coupled") return fail("--mode " + v + ": valid: dem, coupled");
        prm.mode = v;
      } else if (a == "--threads") {
        try {
          prm.threads = std::stoi(v);
        } catch (const std::exception&) {
          prm.threads = -1;
        }
        if (prm.threads < 0)
          return fail("--threads " + v + ": valid: an integer >= 0 (0: OMP_NUM_THREADS)");
      } else if (a == "--output") {
        prm.output_folder = v;
      } else {
        return fail("unknown option '" + a + "'; valid: --mode, --threads, --output");
      }
    }
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
