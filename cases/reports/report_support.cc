#include "cases/reports/report_support.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <filesystem>
#include <iostream>
#include <vector>

extern char** environ;

namespace trackbed::cases {

std::string json_escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += static_cast<unsigned char>(c) < 0x20 ? ' ' : c;
  }
  return out;
}

namespace {

// Runs argv[0] (a path) with the arguments argv, its standard output and error written to
// `log`; no shell, so no path needs quoting. True when it ran and exited 0.
bool run_logged(const std::vector<std::string>& argv, const std::string& log) {
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log.c_str(),
                                   O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  pid_t pid = 0;
  const int spawned = posix_spawnp(&pid, args[0], &actions, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (spawned != 0) return false;
  int status = 0;
  while (waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) return false;
  return WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

}  // namespace

void run_plot_script(const std::string& script, const std::string& folder, const std::string& log) {
  namespace fs = std::filesystem;
  // Debian's python3 is the one with python3-matplotlib (a python first on the user's PATH may
  // lack it).
  const fs::path path = fs::path(TRACKBED_SOURCE_DIR) / "cases" / "reports" / script;
  const std::string python = fs::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
  const std::string log_path = (fs::path(folder) / log).string();
  if (!run_logged({python, path.string(), folder}, log_path))
    std::cout << "trackbed: warning: the plot failed (see " << log_path << ")" << std::endl;
}

}  // namespace trackbed::cases
