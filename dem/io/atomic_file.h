// Output written under a temporary name and renamed into place on commit(), durably, so a reader
// (or a crash, or a power cut) never sees a half-written file under the final name.
#pragma once

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

#include "common/durable_rename.h"
#include "common/input_error.h"

namespace trackbed::dem {

// What a failed write of an output file suggests (its errno is lost in a buffered stream).
inline constexpr const char* kWriteFailedHint = " (disk full, or a file system read-only?)";

class AtomicFile {
 public:
  explicit AtomicFile(std::string path, std::ios::openmode mode = std::ios::out)
      : path_(std::move(path)), tmp_(path_ + ".part"), out_(tmp_, mode | std::ios::trunc) {
    if (!out_) throw std::runtime_error(tmp_ + ": cannot open for writing (check the folder)");
  }
  // Continues the file an interrupted run was writing (a resumed run): its first `keep` bytes, from
  // the temporary file (a run that was killed) or else from the file itself (one that ended
  // interrupted and renamed it), are written again and writing goes on after them. InputError if
  // neither holds that many bytes.
  AtomicFile(const std::string& path, std::streamoff keep)
      : AtomicFile(path, std::ios::out, written_head(path, keep)) {}
  ~AtomicFile() {
    if (!committed_) {
      out_.close();
      std::remove(tmp_.c_str());
    }
  }
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  std::ofstream& stream() { return out_; }
  const std::string& temporary_path() const { return tmp_; }
  // Bytes written so far, all of them handed to the file system (a checkpoint's count).
  std::streamoff flushed_size() {
    out_.flush();
    return out_.tellp();
  }
  void commit() {
    out_.close();
    if (!out_ || !durable_rename(tmp_, path_))
      throw std::runtime_error(path_ + ": writing failed" + kWriteFailedHint);
    committed_ = true;
  }
  // Whether every write so far has succeeded.
  bool written() const { return static_cast<bool>(out_); }
  // Throws as commit() would when a write has failed already: a file written all through a run (a
  // history), checked at each row, stops the run at the failure, not at its end.
  void require_written() const {
    if (!written()) throw std::runtime_error(path_ + ": writing failed" + kWriteFailedHint);
  }

 private:
  AtomicFile(std::string path, std::ios::openmode mode, const std::string& head)
      : AtomicFile(std::move(path), mode) {
    out_ << head;
  }
  static std::string written_head(const std::string& path, std::streamoff keep) {
    namespace fs = std::filesystem;
    for (const std::string& f : {path + ".part", path})
      if (fs::is_regular_file(f) && static_cast<std::streamoff>(fs::file_size(f)) >= keep) {
        std::ifstream in(f, std::ios::binary);
        std::string head(static_cast<std::size_t>(keep), '\0');
        if (in.read(head.data(), keep)) return head;
      }
    throw InputError(path + ": the checkpoint counts " + std::to_string(keep) +
                     " bytes written, but neither this file nor its .part holds them; valid: "
                     "the results folder as the interrupted run left it");
  }

  std::string path_, tmp_;
  std::ofstream out_;
  bool committed_ = false;
};

}  // namespace trackbed::dem
