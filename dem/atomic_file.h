// Output written under a temporary name and renamed into place on commit(), so a reader (or a
// crash) never sees a half-written file under the final name.
#pragma once

#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <string>

namespace trackbed::dem {

class AtomicFile {
 public:
  explicit AtomicFile(std::string path, std::ios::openmode mode = std::ios::out)
      : path_(std::move(path)), tmp_(path_ + ".part"), out_(tmp_, mode | std::ios::trunc) {
    if (!out_) throw std::runtime_error(tmp_ + ": cannot open for writing (check the folder)");
  }
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
  void commit() {
    out_.close();
    if (!out_ || std::rename(tmp_.c_str(), path_.c_str()) != 0)
      throw std::runtime_error(path_ + ": writing failed (disk full or folder not writable?)");
    committed_ = true;
  }

 private:
  std::string path_, tmp_;
  std::ofstream out_;
  bool committed_ = false;
};

}  // namespace trackbed::dem
