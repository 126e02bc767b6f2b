#include "common/output_folder.h"

#include <filesystem>
#include <fstream>

#include "common/input_error.h"

namespace trackbed {

void create_output_folders(const std::string& folder, std::initializer_list<const char*> subfolders,
                           const std::string& where) {
  namespace fs = std::filesystem;
  const std::string valid = "; valid: a folder that can be created and written";
  std::error_code ec;
  fs::create_directories(folder, ec);
  if (ec) throw InputError(where + ": cannot be created: " + ec.message() + valid);
  for (const char* sub : subfolders) {
    fs::create_directories(fs::path(folder) / sub, ec);
    if (ec) throw InputError(where + ": cannot create " + sub + " in it: " + ec.message() + valid);
  }
  // A probe file: a read-only file system or a folder without write permission fails here, not
  // at the first output.
  const fs::path probe = fs::path(folder) / ".trackbed-write-probe";
  const bool written = static_cast<bool>(std::ofstream(probe) << "probe\n");
  fs::remove(probe, ec);
  if (!written) throw InputError(where + ": cannot write a file in it" + valid);
}

std::string output_folder_parameter(const std::string& file, const std::string& folder) {
  return file + ": output/folder = " + excerpt(folder);
}

}  // namespace trackbed
