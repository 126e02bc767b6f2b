// The one spelling of a file's path that checkpoints, start records and summaries hold: absolute
// and normalised, so that a run resumed from another folder reports the same path.
#pragma once

#include <filesystem>
#include <string>

namespace trackbed {

inline std::string absolute_path(const std::string& file) {
  return std::filesystem::absolute(file).lexically_normal().string();
}

}  // namespace trackbed
