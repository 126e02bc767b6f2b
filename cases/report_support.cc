#include "cases/report_support.h"

#include <cstdlib>
#include <filesystem>
#include <iostream>

namespace trackbed::cases {

std::string json_escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += static_cast<unsigned char>(c) < 0x20 ? ' ' : c;
  }
  return out;
}

void run_plot_script(const std::string& script, const std::string& folder, const std::string& log) {
  namespace fs = std::filesystem;
  // Debian's python3 is the one with python3-matplotlib (a python first on the user's PATH may
  // lack it).
  const fs::path path = fs::path(TRACKBED_SOURCE_DIR) / "cases" / script;
  const std::string python = fs::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
  const std::string cmd =
      python + " '" + path.string() + "' '" + folder + "' > '" + folder + "/" + log + "' 2>&1";
  if (std::system(cmd.c_str()) != 0)
    std::cout << "trackbed: warning: the plot failed (see " << folder << "/" << log << ")"
              << std::endl;
}

}  // namespace trackbed::cases
