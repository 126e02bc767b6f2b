// h5_edit: edits trackbed's HDF5 files the way a damaged or hand-edited file would differ from
// a written one, for the reliability suite (fuzz-inputs). Every edit goes through the HDF5
// library, so the file stays readable as HDF5 and its checksums stay valid: only trackbed's own
// checks stand between the edit and the engine.
//   h5_edit FILE list                        datasets ("dataset PATH f|i VALUES") and string
//                                            attributes ("attribute OBJECT NAME")
//   h5_edit FILE set DATASET INDEX VALUE     one value (in row-major order) set to VALUE; exit 3
//                                            and "unchanged" when it holds VALUE already
//   h5_edit FILE attr OBJECT NAME VALUE      a string attribute set to VALUE; exit 3 and
//                                            "unchanged" when it holds VALUE already
//   h5_edit FILE shrink DATASET              the dataset one row shorter (one value if 1-D)
//   h5_edit FILE drop DATASET                the dataset removed
// Exit 0 on success, 3 when a set or attr would change nothing, 1 with a line on standard error
// otherwise.
#include <hdf5.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <string>
#include <vector>

namespace {

[[noreturn]] void fail(const std::string& what) {
  std::cerr << "h5_edit: " << what << std::endl;
  std::exit(1);
}

herr_t list_object(hid_t, const char* name, const H5O_info_t* info, void*);

herr_t list_attribute(hid_t object, const char* name, const H5A_info_t*, void* path) {
  const hid_t a = H5Aopen(object, name, H5P_DEFAULT);
  const hid_t t = H5Aget_type(a);
  if (H5Tget_class(t) == H5T_STRING)
    std::cout << "attribute " << *static_cast<std::string*>(path) << " " << name << "\n";
  H5Tclose(t);
  H5Aclose(a);
  return 0;
}

herr_t list_object(hid_t root, const char* name, const H5O_info_t* info, void*) {
  std::string path = name;
  const hid_t o = H5Oopen(root, name, H5P_DEFAULT);
  H5Aiterate2(o, H5_INDEX_NAME, H5_ITER_INC, nullptr, list_attribute, &path);
  if (info->type == H5O_TYPE_DATASET) {
    const hid_t t = H5Dget_type(o), s = H5Dget_space(o);
    const char kind = H5Tget_class(t) == H5T_FLOAT ? 'f' : 'i';
    std::cout << "dataset " << path << " " << kind << " " << H5Sget_simple_extent_npoints(s)
              << "\n";
    H5Tclose(t);
    H5Sclose(s);
  }
  H5Oclose(o);
  return 0;
}

// The dataset's dimensions (1-D or 2-D) and whether it holds floating-point numbers.
std::vector<hsize_t> dims_of(hid_t set, bool& floating) {
  const hid_t t = H5Dget_type(set), s = H5Dget_space(set);
  floating = H5Tget_class(t) == H5T_FLOAT;
  std::vector<hsize_t> dims(H5Sget_simple_extent_ndims(s));
  H5Sget_simple_extent_dims(s, dims.data(), nullptr);
  H5Tclose(t);
  H5Sclose(s);
  return dims;
}

// Sets one element; false (and nothing written) when it holds that value already (an edit that
// changes nothing is no malformed input).
bool set_value(hid_t file, const std::string& name, long index, const std::string& value) {
  const hid_t set = H5Dopen2(file, name.c_str(), H5P_DEFAULT);
  if (set < 0) fail("no dataset " + name);
  bool floating = false;
  const std::vector<hsize_t> dims = dims_of(set, floating);
  const hsize_t cols = dims.size() > 1 ? dims[1] : 1, rows = dims.empty() ? 0 : dims[0];
  if (index < 0 || static_cast<hsize_t>(index) >= rows * cols) fail("index out of range");
  const hsize_t start[2] = {index / cols, index % cols}, count[2] = {1, 1};
  const hid_t file_space = H5Dget_space(set), one = H5Screate_simple(1, count, nullptr);
  H5Sselect_hyperslab(file_space, H5S_SELECT_SET, start, nullptr, count, nullptr);
  herr_t status = 0;
  bool changed = true;
  if (floating) {
    const double v = std::strtod(value.c_str(), nullptr);
    double old = 0;
    H5Dread(set, H5T_NATIVE_DOUBLE, one, file_space, H5P_DEFAULT, &old);
    changed = !(old == v || (std::isnan(old) && std::isnan(v)));
    if (changed) status = H5Dwrite(set, H5T_NATIVE_DOUBLE, one, file_space, H5P_DEFAULT, &v);
  } else {
    const std::int64_t v = std::strtoll(value.c_str(), nullptr, 10);
    std::int64_t old = 0;
    H5Dread(set, H5T_NATIVE_INT64, one, file_space, H5P_DEFAULT, &old);
    changed = old != v;
    if (changed) status = H5Dwrite(set, H5T_NATIVE_INT64, one, file_space, H5P_DEFAULT, &v);
  }
  if (status < 0) fail("write failed");
  H5Sclose(one);
  H5Sclose(file_space);
  H5Dclose(set);
  return changed;
}

// The string attribute `name` of `object`, "" when it has none.
std::string attribute_text(hid_t o, const std::string& name) {
  if (H5Aexists(o, name.c_str()) <= 0) return "";
  const hid_t a = H5Aopen(o, name.c_str(), H5P_DEFAULT), t = H5Aget_type(a);
  std::string text(H5Tget_size(t), '\0');
  if (H5Tget_class(t) != H5T_STRING || H5Tis_variable_str(t) > 0 || H5Aread(a, t, text.data()) < 0)
    text = "\x01(not a fixed-length string)";
  H5Tclose(t);
  H5Aclose(a);
  return text.substr(0, text.find('\0'));
}

// Sets a string attribute; false (and nothing written) when it holds that text already.
bool set_attribute(hid_t file, const std::string& object, const std::string& name,
                   const std::string& value) {
  const hid_t o = H5Oopen(file, object.c_str(), H5P_DEFAULT);
  if (o < 0) fail("no object " + object);
  if (attribute_text(o, name) == value && H5Aexists(o, name.c_str()) > 0) {
    H5Oclose(o);
    return false;
  }
  if (H5Aexists(o, name.c_str()) > 0) H5Adelete(o, name.c_str());
  const hid_t t = H5Tcopy(H5T_C_S1), s = H5Screate(H5S_SCALAR);
  H5Tset_size(t, value.empty() ? 1 : value.size());
  const hid_t a = H5Acreate2(o, name.c_str(), t, s, H5P_DEFAULT, H5P_DEFAULT);
  const std::string stored = value.empty() ? std::string(1, '\0') : value;
  if (a < 0 || H5Awrite(a, t, stored.data()) < 0) fail("attribute write failed");
  H5Aclose(a);
  H5Sclose(s);
  H5Tclose(t);
  H5Oclose(o);
  return true;
}

void shrink(hid_t file, const std::string& name) {
  const hid_t set = H5Dopen2(file, name.c_str(), H5P_DEFAULT);
  if (set < 0) fail("no dataset " + name);
  bool floating = false;
  std::vector<hsize_t> dims = dims_of(set, floating);
  if (dims.empty() || dims[0] == 0) fail("nothing to shrink");
  const hsize_t cols = dims.size() > 1 ? dims[1] : 1;
  const hid_t type = floating ? H5T_NATIVE_DOUBLE : H5T_NATIVE_INT64;
  std::vector<double> data(dims[0] * cols);  // 8 bytes a value either way
  H5Dread(set, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data());
  H5Dclose(set);
  H5Ldelete(file, name.c_str(), H5P_DEFAULT);
  dims[0] -= 1;
  const hid_t space = H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr);
  const hid_t made =
      H5Dcreate2(file, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  if (made < 0) fail("create failed");
  if (dims[0] > 0) H5Dwrite(made, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data());
  H5Dclose(made);
  H5Sclose(space);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) fail("usage: h5_edit FILE list|set|attr|shrink|drop ...");
  const std::string command = argv[2];
  const hid_t file =
      H5Fopen(argv[1], command == "list" ? H5F_ACC_RDONLY : H5F_ACC_RDWR, H5P_DEFAULT);
  if (file < 0) fail(std::string("cannot open ") + argv[1]);
  if (command == "list") {
    std::string root = "/";
    H5Aiterate2(file, H5_INDEX_NAME, H5_ITER_INC, nullptr, list_attribute, &root);
    H5Ovisit(file, H5_INDEX_NAME, H5_ITER_INC, list_object, nullptr);
  } else if (command == "set" && argc == 6) {
    if (!set_value(file, argv[3], std::atol(argv[4]), argv[5])) {
      H5Fclose(file);
      std::puts("unchanged");
      return 3;
    }
  } else if (command == "attr" && argc == 6) {
    if (!set_attribute(file, argv[3], argv[4], argv[5])) {
      H5Fclose(file);
      std::puts("unchanged");
      return 3;
    }
  } else if (command == "shrink" && argc == 4) {
    shrink(file, argv[3]);
  } else if (command == "drop" && argc == 4) {
    if (H5Ldelete(file, argv[3], H5P_DEFAULT) < 0) fail(std::string("no object ") + argv[3]);
  } else {
    fail("unknown command or arguments: " + command);
  }
  H5Fclose(file);
  return 0;
}
