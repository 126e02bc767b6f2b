#include "common/durable_rename.h"

#include <fcntl.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>

namespace trackbed {

namespace {

// fsync of the file or folder at `path` (a read-only descriptor flushes the file's data too).
bool sync_path(const std::string& path, int flags) {
  const int fd = ::open(path.c_str(), flags | O_CLOEXEC);
  if (fd < 0) return false;
  const bool synced = ::fsync(fd) == 0;
  return ::close(fd) == 0 && synced;
}

}  // namespace

bool durable_rename(const std::string& temporary, const std::string& final_name) {
  if (!sync_path(temporary, O_RDONLY)) return false;
  if (std::rename(temporary.c_str(), final_name.c_str()) != 0) return false;
  const std::filesystem::path folder = std::filesystem::path(final_name).parent_path();
  return sync_path(folder.empty() ? "." : folder.string(), O_RDONLY | O_DIRECTORY);
}

}  // namespace trackbed
