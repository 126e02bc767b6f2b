// trackbed: railway ballast track simulator. The command line:
//   trackbed run CASE.prm [--mode dem|coupled] [--threads N] [--output DIR]
//   mpirun -np P trackbed run COUPLED.prm       the FE subgrade on P processes, the DEM on the
//   first trackbed resume DIR [--threads N]        continue an interrupted run from its checkpoint
//   trackbed build-sample SAMPLE.prm [--threads N] [--output DIR]
//   trackbed --print-parameters [json]   every case-file parameter with default and documentation
//   trackbed build-sample --print-parameters [json]   the same for sample files
//   trackbed --help | --version
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <iterator>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "cases/app/stop_signal.h"
#include "cases/parameters/case_parameters.h"
#include "cases/parameters/sample_parameters.h"
#include "cases/runs/dem_run.h"
#include "cases/runs/run_checkpoint.h"
#include "cases/runs/sample_checkpoint.h"
#include "cases/runs/sample_run.h"
#include "cases/runs/start_record.h"
#include "common/absolute_path.h"
#include "common/input_error.h"
#include "common/output_folder.h"
#include "dem/io/sample.h"
#include "dem/samples/section_model.h"
#include "fem/mpi_runtime.h"

namespace {

const char* const kUsage =
    "usage: trackbed run CASE.prm [--mode dem|coupled] [--threads N] [--output DIR]\n"
    "       trackbed resume DIR [--threads N]\n"
    "       trackbed build-sample SAMPLE.prm [--threads N] [--output DIR]\n"
    "       trackbed --print-parameters [json] | build-sample --print-parameters [json]\n"
    "       trackbed --help | --version\n"
    "\n"
    "Runs the railway ballast model described by CASE.prm (deal.II parameter file syntax) and\n"
    "writes a results folder: CSV histories, ParaView files, HDF5 snapshots, summary.json,\n"
    "summary.txt and plot.png. The default case is cases/default.prm.\n"
    "resume continues a run or a sample build that was interrupted (Ctrl-C, SIGTERM, a crash)\n"
    "from the last checkpoint in its results folder DIR, and ends it as the uninterrupted one\n"
    "would have; one stopped before its first checkpoint starts again from the beginning.\n"
    "build-sample builds a ballast sample of a track section (deposition, compaction, sleeper\n"
    "seating, balls converted to clumps in a zone) and writes sample.h5 for cases to load.\n"
    "  --mode      override 'mode' (dem: DEM with rigid walls; coupled: the bed on an FE\n"
    "              subgrade; 'mpirun -np P trackbed run ...' spreads the FE over P processes)\n"
    "  --threads   OpenMP threads (overrides 'simulation/threads')\n"
    "  --output    results folder (overrides 'output/folder')\n";

// The processes of the launch as mpirun tells them (1 without mpirun), and this one's rank,
// known before MPI starts: only a coupled run starts it.
int launch_value(const char* open_mpi, const char* pmi, int otherwise) {
  for (const char* name : {open_mpi, pmi})
    if (const char* v = std::getenv(name)) return std::atoi(v);
  return otherwise;
}
int launched_processes() {
  return launch_value("OMPI_COMM_WORLD_SIZE", "PMI_SIZE", 1);
}
int launch_rank() {
  return launch_value("OMPI_COMM_WORLD_RANK", "PMI_RANK", 0);
}

// One line on stderr, from the first process only (the others of a launch meet the same error).
int fail(const std::string& message, int code = 2) {
  if (launch_rank() == 0) std::cerr << "trackbed: error: " << message << std::endl;
  return code;
}

// Starts MPI (once) for a coupled run; returns this process's rank.
using StartMpi = std::function<int()>;

// A DEM run or a sample build is one process (its OpenMP threads); only a coupled run spreads
// its FE subgrade over an MPI launch.
void require_one_process(const std::string& what) {
  if (launched_processes() > 1)
    throw trackbed::InputError(what +
                               " runs in one process, with OpenMP threads; valid: one "
                               "process, or mode = coupled under mpirun (its FE subgrade on "
                               "every process)");
}

// A process of a coupled launch other than the first: builds its part of the FE subgrade and
// takes part in every exchange the first announces, until the run ends.
int serve_subgrade(const trackbed::cases::CaseParameters& prm) {
  if (prm.sample_file.empty()) return 2;  // the first process says why
  // Ctrl-C or SIGTERM reaches every process of the launch; the first stops the run (with a
  // checkpoint, which needs the others), so they do not stop on their own.
  trackbed::cases::catch_stop_signals();
  const trackbed::dem::Sample sample = trackbed::dem::read_sample(prm.sample_file);
  trackbed::cases::SubgradeCoupling subgrade(prm, trackbed::dem::section_of(sample));
  subgrade.serve();
  return 0;
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
      if (v.empty()) return "--output '': valid: a folder name";
      output = v;
    } else {
      return "unknown option '" + a +
             "'; valid: " + (with_mode ? "--mode, --threads, --output" : "--threads, --output");
    }
  }
  return "";
}

// The first line that differs between two fingerprints of a parameter file (fingerprint()).
std::string first_difference(const std::string& then, const std::string& now) {
  std::istringstream a(then), b(now);
  std::string la, lb;
  while (true) {
    const bool more_a = static_cast<bool>(std::getline(a, la));
    const bool more_b = static_cast<bool>(std::getline(b, lb));
    if (!more_a && !more_b) return "";
    if (!more_a || !more_b || la != lb)
      return "'" + (more_a ? la : std::string("(nothing)")) + "' then, '" +
             (more_b ? lb : std::string("(nothing)")) + "' now";
  }
}

// Throws InputError when the parameter file `file` (a case or sample file: `what`) that the
// checkpoint `path` names is gone.
void require_file(const std::string& path, const std::string& file, const std::string& what) {
  if (!std::filesystem::is_regular_file(file))
    throw trackbed::InputError(path + ": the " + what + " " + file + " is missing; valid: the " +
                               what + " it started from, where it was");
}

// Throws InputError naming the checkpoint `checkpoint` when `file`'s parameters (fingerprint
// `now`) differ from those it started with (`then`, saved in the checkpoint), naming the first
// that differs.
void require_unchanged(const std::string& checkpoint, const std::string& file,
                       const std::string& then, const std::string& now) {
  const std::string changed = first_difference(then, now);
  if (!changed.empty())
    throw trackbed::InputError(checkpoint + ": " + file + " has changed since it started: " +
                               changed + "; valid: the file as it was, or a new start");
}

// Throws InputError unless the checkpoint `path` was written by this version of trackbed: a
// resumed run continues bit for bit only in the program that started it.
void require_same_version(const std::string& path, const std::string& version) {
  if (version != TRACKBED_VERSION)
    throw trackbed::InputError(path + ": written by trackbed " + trackbed::excerpt(version) +
                               ", this is " + TRACKBED_VERSION + "; valid: resume with trackbed " +
                               trackbed::excerpt(version) + ", or start anew");
}

// The threads of a resumed run or build: those asked for, else the checkpoint's.
int resumed_threads(int asked, int saved) {
  const int threads = asked > 0 ? asked : saved;
  if (threads != saved)
    std::cout << "trackbed: resuming on " << threads << " threads where it ran on " << saved
              << ": the results will not be bit for bit those of an uninterrupted one" << std::endl;
  return threads;
}

// Runs `start` (a fresh run or build in `folder`, which begin_fresh `created` or not); bad input
// found while it sets up leaves neither a start record (there is nothing to start anew) nor a
// folder it created.
template <class Start>
int abandoned_on_input_error(const std::string& folder, bool created, Start&& start) {
  try {
    return start();
  } catch (const trackbed::InputError&) {
    trackbed::cases::abandon_fresh(folder, created);
    throw;
  }
}

// Starts a run afresh in its results folder (the first process of a coupled launch; the others
// serve the FE subgrade).
int start_run(trackbed::cases::CaseParameters prm, const StartMpi& start_mpi) {
  using namespace trackbed::cases;
  if (prm.mode == "coupled") {
    if (start_mpi() > 0) return serve_subgrade(prm);
  } else {
    require_one_process("a DEM run (mode = dem)");
  }
  const std::string folder = prm.output_folder;
  const bool created = begin_fresh(
      folder, {"run", trackbed::absolute_path(prm.file), prm.fingerprint, prm.mode, prm.threads},
      trackbed::output_folder_parameter(prm.file, folder));
  return abandoned_on_input_error(folder, created, [&] { return DemRun(std::move(prm)).run(); });
}

// Starts a sample build afresh in its results folder.
int start_build(trackbed::cases::SampleParameters prm) {
  using namespace trackbed::cases;
  require_one_process("a sample build");
  const std::string folder = prm.output_folder;
  const bool created = begin_fresh(
      folder, {"build-sample", trackbed::absolute_path(prm.file), prm.fingerprint, "", prm.threads},
      trackbed::output_folder_parameter(prm.file, folder));
  return abandoned_on_input_error(folder, created, [&] { return SampleRun(std::move(prm)).run(); });
}

// A run or build stopped before its first checkpoint (its start record `r`, no checkpoint):
// started again from the beginning, in the same folder, from the same unchanged parameter file.
int start_anew(const std::string& dir, const trackbed::cases::StartRecord& r, int threads,
               const StartMpi& start_mpi) {
  using namespace trackbed::cases;
  const std::string record = (std::filesystem::path(dir) / kStartFile).string();
  const bool build = r.command == "build-sample";
  require_file(record, r.file, build ? "sample file" : "case file");
  if (launch_rank() == 0)
    std::cout << "trackbed: " << dir << " was stopped before its first checkpoint: starting "
              << r.file << " anew" << std::endl;
  if (build) {
    SampleParameters prm = read_sample_file(r.file);
    require_unchanged(record, r.file, r.fingerprint, prm.fingerprint);
    prm.output_folder = dir;
    prm.threads = threads > 0 ? threads : r.threads;
    return start_build(std::move(prm));
  }
  CaseParameters prm = read_case_file(r.file);
  require_unchanged(record, r.file, r.fingerprint, prm.fingerprint);
  prm.output_folder = dir;
  prm.mode = r.mode;
  prm.threads = threads > 0 ? threads : r.threads;
  return start_run(std::move(prm), start_mpi);
}

int resume(const std::vector<std::string>& args, const StartMpi& start_mpi) {
  namespace fs = std::filesystem;
  using namespace trackbed::cases;
  if (args.size() < 2) return fail("'resume' needs a results folder: trackbed resume DIR");
  const std::string dir = args[1];
  int threads = -1;
  for (std::size_t i = 2; i < args.size(); i += 2) {
    if (args[i] != "--threads" || i + 1 >= args.size())
      return fail("resume: unknown option '" + args[i] + "'; valid: --threads N");
    try {
      threads = std::stoi(args[i + 1]);
    } catch (const std::exception&) {
      threads = 0;
    }
    if (threads < 1) return fail("--threads " + args[i + 1] + ": valid: an integer >= 1");
  }
  const std::string path = (fs::path(dir) / kCheckpointFile).string();
  if (!fs::is_regular_file(path)) {
    std::ifstream summary(fs::path(dir) / "summary.json");
    const std::string text((std::istreambuf_iterator<char>(summary)), {});
    if (text.find("\"status\": \"finished\"") != std::string::npos)
      return fail(dir + ": the run finished; there is nothing to resume");
    if (fs::is_regular_file(fs::path(dir) / "sample.h5"))
      return fail(dir + ": the sample build finished; there is nothing to resume");
    if (const auto record = read_start_record(dir))
      return start_anew(dir, *record, threads, start_mpi);
    return fail(path +
                ": no such file; valid: the results folder of a run or a sample build "
                "stopped after it started");
  }
  if (is_sample_checkpoint(path)) {
    require_one_process("a sample build");
    SampleCheckpoint checkpoint = read_sample_checkpoint(path);
    require_same_version(path, checkpoint.version);
    require_file(path, checkpoint.sample_file, "sample file");
    SampleParameters prm = read_sample_file(checkpoint.sample_file);
    require_unchanged(path, checkpoint.sample_file, checkpoint.fingerprint, prm.fingerprint);
    prm.output_folder = dir;
    prm.threads = resumed_threads(threads, checkpoint.threads);
    SampleRun run(std::move(prm));
    return run.resume(std::move(checkpoint));
  }
  RunCheckpoint checkpoint = read_run_checkpoint(path);
  require_same_version(path, checkpoint.version);
  require_file(path, checkpoint.case_file, "case file");
  CaseParameters prm = read_case_file(checkpoint.case_file);
  require_unchanged(path, checkpoint.case_file, checkpoint.case_fingerprint, prm.fingerprint);
  prm.output_folder = dir;
  if (checkpoint.coupled) {
    prm.mode = "coupled";
    if (start_mpi() > 0) return serve_subgrade(prm);
  } else {
    require_one_process("a DEM run");
  }
  prm.threads = resumed_threads(threads, checkpoint.threads);
  DemRun run(std::move(prm));
  return run.resume(std::move(checkpoint));
}

int build_sample(const std::vector<std::string>& args) {
  if (args.size() >= 2 && args[1] == "--print-parameters") {
    trackbed::cases::print_sample_parameters(std::cout, args.size() > 2 && args[2] == "json");
    return 0;
  }
  if (args.size() < 2)
    return fail("'build-sample' needs a sample file: trackbed build-sample SAMPLE.prm");
  trackbed::cases::SampleParameters prm = trackbed::cases::read_sample_file(args[1]);
  std::string unused;
  const std::string bad = parse_options(args, false, unused, prm.threads, prm.output_folder);
  if (!bad.empty()) return fail(bad);
  return start_build(std::move(prm));
}

}  // namespace

// trackbed run CASE.prm [options]
int run(const std::vector<std::string>& args, const StartMpi& start_mpi) {
  if (args.size() < 2) return fail("'run' needs a case file: trackbed run CASE.prm");
  trackbed::cases::CaseParameters prm = trackbed::cases::read_case_file(args[1]);
  const std::string bad = parse_options(args, true, prm.mode, prm.threads, prm.output_folder);
  if (!bad.empty()) return fail(bad);
  return start_run(std::move(prm), start_mpi);
}

int main(int argc, char** argv) {
  const std::vector<std::string> args(argv + 1, argv + argc);
  // Declared before every run so that it outlives them: MPI ends after the last collective call.
  std::unique_ptr<trackbed::fem::MpiRuntime> mpi;
  const StartMpi start_mpi = [&] {
    if (!mpi) mpi = std::make_unique<trackbed::fem::MpiRuntime>(argc, argv);
    int rank = 0;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    return rank;
  };
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
    trackbed::cases::print_parameters(std::cout, args.size() > 1 && args[1] == "json");
    return 0;
  }
  if (args[0] != "run" && args[0] != "resume" && args[0] != "build-sample")
    return fail("unknown command '" + args[0] +
                "'; valid: run, resume, build-sample, --print-parameters, --help, --version");
  try {
    if (args[0] == "build-sample") return build_sample(args);
    if (args[0] == "resume") return resume(args, start_mpi);
    return run(args, start_mpi);
  } catch (const trackbed::InputError& e) {
    return fail(e.what());
  } catch (const std::exception& e) {
    return fail(e.what(), 1);
  }
}
