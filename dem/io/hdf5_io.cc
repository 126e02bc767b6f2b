#include "dem/io/hdf5_io.h"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "common/durable_rename.h"
#include "common/input_error.h"
#include "dem/io/atomic_file.h"

namespace trackbed::dem::hdf5 {

Handle::Handle(hid_t id, herr_t (*close)(hid_t), const std::string& what) : id_(id), close_(close) {
  if (id_ < 0) throw std::runtime_error("HDF5: " + what + " failed");
}

hid_t open_for_reading(const std::string& path, const std::string& what) {
  if (!std::filesystem::is_regular_file(path))
    throw InputError(path + ": no such file; valid: " + what);
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // errors are reported by us, in one line
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (file < 0) throw InputError(path + ": cannot open as HDF5; valid: " + what);
  return file;
}

namespace {

// A file built in memory (HDF5's core driver without a backing store), its bytes taken as the
// driver frees them when the file is closed: HDF5 never writes to the disk itself, so a full disk
// or a vanished folder is one failed write of ours, not a failed flush that leaves HDF5's state
// broken (its exit handler then crashed on the half-closed file). The image is taken at the close,
// not with H5Fget_file_image, whose copy of a 1.8-format superblock keeps a stale checksum.
struct FileImage {
  std::size_t size = 0;     // of the driver's buffer
  std::vector<char> bytes;  // the file, once closed
};

void* image_malloc(std::size_t size, H5FD_file_image_op_t, void* image) {
  static_cast<FileImage*>(image)->size = size;
  return std::calloc(size, 1);
}

void* image_memcpy(void* to, const void* from, std::size_t size, H5FD_file_image_op_t, void*) {
  return std::memcpy(to, from, size);
}

// Grows or shrinks the buffer; new bytes are zero, so the same file gives the same bytes.
void* image_realloc(void* buffer, std::size_t size, H5FD_file_image_op_t, void* image) {
  FileImage& f = *static_cast<FileImage*>(image);
  char* grown = static_cast<char*>(std::realloc(buffer, size));
  if (grown && size > f.size) std::memset(grown + f.size, 0, size - f.size);
  if (grown) f.size = size;
  return grown;
}

herr_t image_free(void* buffer, H5FD_file_image_op_t op, void* image) {
  FileImage& f = *static_cast<FileImage*>(image);
  if (op == H5FD_FILE_IMAGE_OP_FILE_CLOSE && buffer)
    f.bytes.assign(static_cast<char*>(buffer), static_cast<char*>(buffer) + f.size);
  std::free(buffer);
  return 0;
}

void* image_copy(void* image) {
  return image;
}

herr_t image_release(void*) {
  return 0;
}

// The 1.8 file format checksums the superblock and the object headers, so that a damaged file is
// refused when opened rather than read as numbers (the datasets carry their own checksums).
// Objects carry no timestamps, so that the same state gives the same bytes (reproducible runs and
// resumed runs compare file by file).
hid_t create_in_memory(const std::string& name, FileImage& image) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // errors are reported by us, in one line
  Handle access(H5Pcreate(H5P_FILE_ACCESS), H5Pclose, "file access list");
  H5Pset_libver_bounds(access, H5F_LIBVER_V18, H5F_LIBVER_V18);
  H5Pset_fapl_core(access, 1 << 16, false);
  H5FD_file_image_callbacks_t callbacks = {image_malloc, image_memcpy,  image_realloc, image_free,
                                           image_copy,   image_release, &image};
  H5Pset_file_image_callbacks(access, &callbacks);
  Handle creation(H5Pcreate(H5P_FILE_CREATE), H5Pclose, "file creation list");
  H5Pset_obj_track_times(creation, false);
  const hid_t f = H5Fcreate(name.c_str(), H5F_ACC_TRUNC, creation, access);
  if (f < 0) throw std::runtime_error("HDF5: create " + name + " in memory failed");
  return f;
}

}  // namespace

void write_file(const std::string& path, const std::string& what,
                const std::function<void(hid_t file)>& fill) {
  FileImage image;
  {
    Handle file(create_in_memory(path, image), H5Fclose, "create " + path);
    fill(file);
  }
  // The buffer grows by 64 KiB: the file ends with up to that much spare room (zeros), which
  // readers ignore.
  if (image.bytes.empty()) throw std::runtime_error("HDF5: " + path + ": no image when closed");
  const std::string tmp = path + ".part";
  std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
  out.write(image.bytes.data(), static_cast<std::streamsize>(image.bytes.size()));
  out.close();
  if (!out) {
    std::remove(tmp.c_str());
    throw std::runtime_error(path + ": writing the " + what + " failed" + kWriteFailedHint);
  }
  if (!durable_rename(tmp, path)) {
    std::remove(tmp.c_str());
    throw std::runtime_error(path + ": cannot move the finished " + what + " into place");
  }
}

hid_t create_group(hid_t parent, const char* name) {
  Handle creation(H5Pcreate(H5P_GROUP_CREATE), H5Pclose, "group creation list");
  H5Pset_obj_track_times(creation, false);
  const hid_t g = H5Gcreate2(parent, name, H5P_DEFAULT, creation, H5P_DEFAULT);
  if (g < 0) throw std::runtime_error(std::string("HDF5: create group ") + name + " failed");
  return g;
}

namespace {

// A group, dataset or attribute that exists but cannot be opened or read: HDF5 found its header
// or data damaged (their checksums fail).
InputError damaged(const std::string& file, const std::string& what) {
  return InputError(file + ": " + what +
                    " cannot be read (its checksum fails: the file is damaged); valid: a file "
                    "as trackbed wrote it");
}

// Opens a dataset of a file being read.
hid_t open_dataset(hid_t parent, const std::string& file, const char* name) {
  if (!exists(parent, name))
    throw InputError(file + ": dataset '" + name + "' is missing; valid: a trackbed file");
  const hid_t set = H5Dopen2(parent, name, H5P_DEFAULT);
  if (set < 0) throw damaged(file, std::string("dataset '") + name + "'");
  return set;
}

}  // namespace

hid_t open_group(hid_t parent, const std::string& file, const char* name) {
  if (!exists(parent, name))
    throw InputError(file + ": group '" + name + "' is missing; valid: a trackbed file");
  const hid_t g = H5Gopen2(parent, name, H5P_DEFAULT);
  if (g < 0) throw damaged(file, std::string("group '") + name + "'");
  return g;
}

namespace {

template <class T>
void write_array(hid_t parent, const char* name, hid_t type, const T* data, hsize_t rows,
                 hsize_t cols) {
  const hsize_t dims[2] = {rows, cols};
  Handle space(H5Screate_simple(cols == 1 ? 1 : 2, dims, nullptr), H5Sclose, "dataspace");
  // A Fletcher-32 checksum on every chunk: a flipped bit makes the read fail, never a wrong
  // number. Chunks of up to 65,536 rows (a chunk needs rows > 0; an empty dataset has no data).
  Handle create(H5Pcreate(H5P_DATASET_CREATE), H5Pclose, "dataset creation list");
  H5Pset_obj_track_times(create, false);
  if (rows > 0) {
    const hsize_t chunk[2] = {std::min<hsize_t>(rows, 65536), cols};
    H5Pset_chunk(create, cols == 1 ? 1 : 2, chunk);
    H5Pset_fletcher32(create);
  }
  Handle set(H5Dcreate2(parent, name, type, space, H5P_DEFAULT, create, H5P_DEFAULT), H5Dclose,
             std::string("create ") + name);
  if (rows > 0 && H5Dwrite(set, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0)
    throw std::runtime_error(std::string("HDF5: write ") + name + " failed");
}

template <class T>
std::vector<T> read_array(hid_t parent, const std::string& file, const char* name, hid_t type,
                          long expected) {
  Handle set(open_dataset(parent, file, name), H5Dclose, std::string("open ") + name);
  Handle space(H5Dget_space(set), H5Sclose, "dataspace");
  const hssize_t n = H5Sget_simple_extent_npoints(space);
  if (expected >= 0 && n != expected)
    throw InputError(file + ": dataset '" + name + "' has " + std::to_string(n) +
                     " values, the model needs " + std::to_string(expected) +
                     "; valid: a file written for the same model");
  std::vector<T> out(n);
  if (n > 0 && H5Dread(set, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()) < 0)
    throw damaged(file, std::string("dataset '") + name + "'");
  return out;
}

}  // namespace

void write_doubles(hid_t parent, const char* name, const double* data, hsize_t rows, hsize_t cols) {
  write_array(parent, name, H5T_NATIVE_DOUBLE, data, rows, cols);
}

void write_doubles(hid_t parent, const char* name, const std::vector<double>& v) {
  write_doubles(parent, name, v.data(), v.size(), 1);
}

void write_vectors(hid_t parent, const char* name, const std::vector<Vec3>& v) {
  std::vector<double> flat;
  flat.reserve(3 * v.size());
  for (const auto& x : v) flat.insert(flat.end(), {x.x(), x.y(), x.z()});
  write_doubles(parent, name, flat.data(), v.size(), 3);
}

void write_integers(hid_t parent, const char* name, const std::vector<std::int64_t>& v) {
  write_array(parent, name, H5T_NATIVE_INT64, v.data(), v.size(), 1);
}

bool exists(hid_t parent, const char* name) {
  return H5Lexists(parent, name, H5P_DEFAULT) > 0;
}

long dataset_size(hid_t parent, const std::string& file, const char* name) {
  Handle set(open_dataset(parent, file, name), H5Dclose, std::string("open ") + name);
  Handle space(H5Dget_space(set), H5Sclose, "dataspace");
  return static_cast<long>(H5Sget_simple_extent_npoints(space));
}

void write_quaternions(hid_t parent, const char* name, const std::vector<Quat>& q) {
  std::vector<double> flat;
  for (const auto& r : q) flat.insert(flat.end(), {r.w(), r.x(), r.y(), r.z()});
  write_doubles(parent, name, flat.data(), q.size(), 4);
}

std::vector<Quat> read_quaternions(hid_t parent, const std::string& file, const char* name,
                                   long expected) {
  const auto d = read_doubles(parent, file, name, expected < 0 ? -1 : 4 * expected);
  if (d.size() % 4 != 0)
    throw InputError(file + ": dataset '" + name + "' is not a list of quaternions");
  std::vector<Quat> out;
  for (std::size_t i = 0; i < d.size(); i += 4)
    out.emplace_back(d[i], d[i + 1], d[i + 2], d[i + 3]);
  return out;
}

std::vector<double> read_doubles(hid_t parent, const std::string& file, const char* name,
                                 long expected) {
  return read_array<double>(parent, file, name, H5T_NATIVE_DOUBLE, expected);
}

std::vector<Vec3> read_vectors(hid_t parent, const std::string& file, const char* name,
                               long expected) {
  const auto flat = read_doubles(parent, file, name, expected < 0 ? -1 : 3 * expected);
  if (flat.size() % 3 != 0)
    throw InputError(file + ": dataset '" + name + "' is not a list of 3-vectors");
  std::vector<Vec3> v(flat.size() / 3);
  for (std::size_t i = 0; i < v.size(); ++i)
    v[i] = Vec3(flat[3 * i], flat[3 * i + 1], flat[3 * i + 2]);
  return v;
}

std::vector<std::int64_t> read_integers(hid_t parent, const std::string& file, const char* name,
                                        long expected) {
  return read_array<std::int64_t>(parent, file, name, H5T_NATIVE_INT64, expected);
}

void write_string_attribute(hid_t object, const char* name, const std::string& value) {
  Handle type(H5Tcopy(H5T_C_S1), H5Tclose, "string type");
  H5Tset_size(type, value.empty() ? 1 : value.size());
  H5Tset_strpad(type, H5T_STR_NULLPAD);
  Handle space(H5Screate(H5S_SCALAR), H5Sclose, "dataspace");
  Handle attr(H5Acreate2(object, name, type, space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose,
              std::string("create attribute ") + name);
  const std::string stored = value.empty() ? std::string(1, '\0') : value;
  if (H5Awrite(attr, type, stored.data()) < 0)
    throw std::runtime_error(std::string("HDF5: write attribute ") + name + " failed");
}

std::string read_string_attribute(hid_t object, const std::string& file, const char* name) {
  if (H5Aexists(object, name) <= 0)
    throw InputError(file + ": attribute '" + name + "' is missing; valid: a trackbed file");
  const hid_t opened = H5Aopen(object, name, H5P_DEFAULT);
  if (opened < 0) throw damaged(file, std::string("attribute '") + name + "'");
  Handle attr(opened, H5Aclose, std::string("open ") + name);
  Handle type(H5Aget_type(attr), H5Tclose, "attribute type");
  if (H5Tget_class(type) != H5T_STRING)
    throw InputError(file + ": attribute '" + name + "' is not a string");
  const std::size_t size = H5Tget_size(type);
  std::string value(size, '\0');
  Handle memtype(H5Tcopy(H5T_C_S1), H5Tclose, "string type");
  H5Tset_size(memtype, size);
  H5Tset_strpad(memtype, H5T_STR_NULLPAD);
  if (H5Aread(attr, memtype, value.data()) < 0)
    throw InputError(file + ": cannot read attribute '" + name + "'");
  value.erase(value.find_last_not_of('\0') + 1);
  return value;
}

long read_integer_attribute(hid_t object, const std::string& file, const char* name, long lo,
                            long hi) {
  const std::string text = read_string_attribute(object, file, name);
  char* end = nullptr;
  errno = 0;
  const long value = std::strtol(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || errno != 0 || value < lo || value > hi)
    throw InputError(file + ": attribute '" + name + "' is '" + excerpt(text) +
                     "'; the file is damaged (valid: an integer in [" + std::to_string(lo) + ", " +
                     std::to_string(hi) + "])");
  return value;
}

bool has_format(hid_t file, const std::string& path, const std::string& format) {
  return H5Aexists(file, "format") > 0 && read_string_attribute(file, path, "format") == format;
}

void write_strings(hid_t object, const char* name, const std::vector<std::string>& values) {
  std::string joined;
  for (std::size_t i = 0; i < values.size(); ++i) joined += (i ? "\n" : "") + values[i];
  write_string_attribute(object, name, joined);
}

std::vector<std::string> read_strings(hid_t object, const std::string& file, const char* name) {
  const std::string joined = read_string_attribute(object, file, name);
  std::vector<std::string> out;
  if (joined.empty()) return out;
  std::size_t start = 0;
  while (true) {
    const std::size_t nl = joined.find('\n', start);
    out.push_back(joined.substr(start, nl == std::string::npos ? std::string::npos : nl - start));
    if (nl == std::string::npos) break;
    start = nl + 1;
  }
  return out;
}

}  // namespace trackbed::dem::hdf5
