// What the drivers' reports share: JSON strings and the plotting scripts in cases/reports/.
#pragma once

#include <string>

namespace trackbed::cases {

// One line of summary.json (key) and summary.txt (label, unit).
struct SummaryItem {
  std::string key, label, unit;
  double value;
};

// The string with '"' and '\' escaped and control characters replaced by spaces.
std::string json_escape(const std::string& s);
// Runs cases/reports/SCRIPT (matplotlib) on the results folder, its output in FOLDER/LOG. A missing
// python or matplotlib is a warning on stdout, not a failed run.
void run_plot_script(const std::string& script, const std::string& folder,
                     const std::string& log = "plot.log");

}  // namespace trackbed::cases
