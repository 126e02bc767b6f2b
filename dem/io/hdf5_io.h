// Small helpers over the HDF5 C API shared by the engine's HDF5 files (snapshots, samples):
// owned identifiers, 1-D/2-D double and integer datasets, string attributes. Errors: a failed
// HDF5 call throws std::runtime_error; a dataset a reader needs but the file lacks, or of the
// wrong size, throws InputError naming the file and what is valid.
#pragma once

#include <hdf5.h>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "dem/engine/types.h"

namespace trackbed::dem::hdf5 {

// Owns an HDF5 identifier and closes it with the matching function.
class Handle {
 public:
  Handle(hid_t id, herr_t (*close)(hid_t), const std::string& what);
  ~Handle() { close_(id_); }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  operator hid_t() const { return id_; }

 private:
  hid_t id_;
  herr_t (*close_)(hid_t);
};

// Opens a file for reading with HDF5's own error printing off; InputError naming `what` (what
// would be valid) if it does not exist or is not an HDF5 file.
hid_t open_for_reading(const std::string& path, const std::string& what);
hid_t create_group(hid_t parent, const char* name);
// Writes a whole file: `fill` writes into a file built in memory, whose bytes are then written to
// PATH.part and renamed to PATH durably, so that no reader (and no crash or power cut) sees it
// half-written. A failed write (a full disk) removes PATH.part and throws std::runtime_error
// naming the file (`what` says which kind it is).
void write_file(const std::string& path, const std::string& what,
                const std::function<void(hid_t file)>& fill);
// InputError if the group is missing.
hid_t open_group(hid_t parent, const std::string& file, const char* name);

// rows x cols doubles (cols == 1: a 1-D dataset).
void write_doubles(hid_t parent, const char* name, const double* data, hsize_t rows, hsize_t cols);
// A 1-D dataset.
void write_doubles(hid_t parent, const char* name, const std::vector<double>& v);
void write_vectors(hid_t parent, const char* name, const std::vector<Vec3>& v);
// Quaternions as (w, x, y, z) rows.
void write_quaternions(hid_t parent, const char* name, const std::vector<Quat>& q);
void write_integers(hid_t parent, const char* name, const std::vector<std::int64_t>& v);

bool exists(hid_t parent, const char* name);
// The number of values of a dataset (InputError if it is missing).
long dataset_size(hid_t parent, const std::string& file, const char* name);
// Exactly `expected` values (all of them if expected < 0).
std::vector<double> read_doubles(hid_t parent, const std::string& file, const char* name,
                                 long expected = -1);
std::vector<Vec3> read_vectors(hid_t parent, const std::string& file, const char* name,
                               long expected = -1);
std::vector<Quat> read_quaternions(hid_t parent, const std::string& file, const char* name,
                                   long expected = -1);
std::vector<std::int64_t> read_integers(hid_t parent, const std::string& file, const char* name,
                                        long expected = -1);

void write_string_attribute(hid_t object, const char* name, const std::string& value);
// InputError if the attribute is missing.
std::string read_string_attribute(hid_t object, const std::string& file, const char* name);
// A string attribute holding an integer in [lo, hi]; InputError naming the file otherwise.
long read_integer_attribute(hid_t object, const std::string& file, const char* name, long lo,
                            long hi);
// Whether `file`'s attribute `format` is `format` (false if it has none): the check by which
// each reader refuses another kind of file, or another version.
bool has_format(hid_t file, const std::string& path, const std::string& format);
// A list of strings as one attribute, joined by newlines (names never contain one).
void write_strings(hid_t object, const char* name, const std::vector<std::string>& values);
std::vector<std::string> read_strings(hid_t object, const std::string& file, const char* name);

}  // namespace trackbed::dem::hdf5
