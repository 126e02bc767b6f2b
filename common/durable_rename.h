// Moves a finished file into place so that it survives a power loss: its data is flushed to the
// disk (fsync) before the rename, and the folder's entry after it. A reader, a crash or a power
// cut then finds under the final name either the previous file or the whole new one, never an
// empty or partial one (ext4 and xfs may otherwise commit the rename before the data).
#pragma once

#include <string>

namespace trackbed {

// Renames `temporary` to `final_name` durably; false (errno set) where a step failed, the
// temporary file then left as it is for the caller to remove or report.
bool durable_rename(const std::string& temporary, const std::string& final_name);

}  // namespace trackbed
