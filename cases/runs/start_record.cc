#include "cases/runs/start_record.h"

#include <filesystem>
#include <fstream>
#include <sstream>

#include "cases/runs/run_checkpoint.h"
#include "common/input_error.h"
#include "common/output_folder.h"
#include "dem/io/atomic_file.h"

namespace trackbed::cases {

namespace fs = std::filesystem;

namespace {

constexpr const char* kHeader = "trackbed start 1";

}  // namespace

bool begin_fresh(const std::string& folder, const StartRecord& r, const std::string& where) {
  std::error_code ec;  // a name the system refuses is said by create_output_folders
  const bool created = !fs::exists(folder, ec);
  create_output_folders(folder, {}, where);
  fs::remove(fs::path(folder) / kCheckpointFile);
  dem::AtomicFile file((fs::path(folder) / kStartFile).string());
  file.stream() << kHeader << "\ncommand = " << r.command << "\nfile = " << r.file
                << "\nmode = " << r.mode << "\nthreads = " << r.threads << "\nfingerprint:\n"
                << r.fingerprint;
  file.commit();
  return created;
}

void abandon_fresh(const std::string& folder, bool created) {
  remove_start_record(folder);
  if (!created) return;
  for (const auto& e : fs::recursive_directory_iterator(folder))
    if (!e.is_directory()) return;
  fs::remove_all(folder);
}

std::optional<StartRecord> read_start_record(const std::string& folder) {
  const std::string path = (fs::path(folder) / kStartFile).string();
  if (!fs::is_regular_file(path)) return std::nullopt;
  std::ifstream in(path);
  std::string header, line;
  std::getline(in, header);
  StartRecord r;
  bool fingerprint = false, threads = false;
  while (!fingerprint && std::getline(in, line)) {
    const auto eq = line.find(" = ");
    const std::string key = line.substr(0, eq),
                      value = eq == std::string::npos ? "" : line.substr(eq + 3);
    if (line == "fingerprint:") {
      fingerprint = true;
    } else if (key == "command") {
      r.command = value;
    } else if (key == "file") {
      r.file = value;
    } else if (key == "mode") {
      r.mode = value;
    } else if (key == "threads") {
      std::istringstream s(value);
      threads = static_cast<bool>(s >> r.threads) && s.eof() && r.threads >= 0;
    }
  }
  std::ostringstream rest;
  rest << in.rdbuf();
  r.fingerprint = rest.str();
  const bool command_ok = (r.command == "run" && (r.mode == "dem" || r.mode == "coupled")) ||
                          (r.command == "build-sample" && r.mode.empty());
  if (header != kHeader || !fingerprint || !threads || !command_ok ||
      !fs::path(r.file).is_absolute())
    throw InputError(path + ": not a start record as trackbed writes it ('" + kHeader +
                     "', command, file, mode, threads, fingerprint); the file is damaged");
  return r;
}

void remove_start_record(const std::string& folder) {
  fs::remove(fs::path(folder) / kStartFile);
}

}  // namespace trackbed::cases
