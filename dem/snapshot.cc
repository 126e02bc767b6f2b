#include "dem/snapshot.h"

#include <hdf5.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <vector>

#include "dem/input_error.h"
#include "dem/simulation.h"

namespace trackbed::dem {

namespace {

// Owns an HDF5 identifier and closes it with the matching function.
class Handle {
 public:
  Handle(hid_t id, herr_t (*close)(hid_t), const std::string& what) : id_(id), close_(close) {
    if (id_ < 0) throw std::runtime_error("HDF5: " + what + " failed");
  }
  ~Handle() { close_(id_); }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  operator hid_t() const { return id_; }

 private:
  hid_t id_;
  herr_t (*close_)(hid_t);
};

void write_array(hid_t parent, const char* name, const double* data, hsize_t rows, hsize_t cols) {
  const hsize_t dims[2] = {rows, cols};
  Handle space(H5Screate_simple(cols == 1 ? 1 : 2, dims, nullptr), H5Sclose, "dataspace");
  Handle set(
      H5Dcreate2(parent, name, H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
      H5Dclose, std::string("create ") + name);
  if (rows > 0 && H5Dwrite(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0)
    throw std::runtime_error(std::string("HDF5: write ") + name + " failed");
}

std::vector<double> read_array(hid_t parent, const std::string& file, const char* name,
                               hsize_t expected) {
  if (H5Lexists(parent, name, H5P_DEFAULT) <= 0)
    throw InputError(file + ": dataset '" + name + "' is missing; valid: a trackbed snapshot");
  Handle set(H5Dopen2(parent, name, H5P_DEFAULT), H5Dclose, std::string("open ") + name);
  Handle space(H5Dget_space(set), H5Sclose, "dataspace");
  const hssize_t n = H5Sget_simple_extent_npoints(space);
  if (static_cast<hsize_t>(n) != expected)
    throw InputError(file + ": dataset '" + name + "' has " + std::to_string(n) +
                     " values, the model needs " + std::to_string(expected) +
                     "; valid: a snapshot of a model built from the same input");
  std::vector<double> out(expected);
  if (expected > 0 &&
      H5Dread(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()) < 0)
    throw InputError(file + ": cannot read dataset '" + name + "'");
  return out;
}

std::vector<double> pack3(const std::vector<Vec3>& v) {
  std::vector<double> out;
  out.reserve(3 * v.size());
  for (const auto& x : v) out.insert(out.end(), {x.x(), x.y(), x.z()});
  return out;
}

void unpack3(const std::vector<double>& d, std::vector<Vec3>& v) {
  for (std::size_t i = 0; i < v.size(); ++i) v[i] = Vec3(d[3 * i], d[3 * i + 1], d[3 * i + 2]);
}

// Opens a snapshot for reading by a tool that has no model to check it against.
Handle open_snapshot_file(const std::string& path) {
  if (!std::filesystem::is_regular_file(path))
    throw InputError(path + ": no such snapshot file; valid: an existing trackbed snapshot (.h5)");
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // errors are reported by us, in one line
  const hid_t raw = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (raw < 0) throw InputError(path + ": cannot open as HDF5; valid: a trackbed snapshot (.h5)");
  return Handle(raw, H5Fclose, "open " + path);
}

Handle open_group(hid_t file, const std::string& path, const char* name) {
  if (H5Lexists(file, name, H5P_DEFAULT) <= 0)
    throw InputError(path + ": group '" + name + "' is missing; valid: a trackbed snapshot");
  return Handle(H5Gopen2(file, name, H5P_DEFAULT), H5Gclose, std::string("group ") + name);
}

// Number of values in a dataset whose size the reader does not know beforehand.
hsize_t dataset_size(hid_t parent, const std::string& file, const char* name) {
  if (H5Lexists(parent, name, H5P_DEFAULT) <= 0)
    throw InputError(file + ": dataset '" + name + "' is missing; valid: a trackbed snapshot");
  Handle set(H5Dopen2(parent, name, H5P_DEFAULT), H5Dclose, std::string("open ") + name);
  Handle space(H5Dget_space(set), H5Sclose, "dataspace");
  return static_cast<hsize_t>(H5Sget_simple_extent_npoints(space));
}

// A dataset that must hold `per_item` values for each of `count` items (bodies, elements).
std::vector<double> read_per_item(hid_t parent, const std::string& file, const char* name,
                                  hsize_t count, hsize_t per_item, const char* items) {
  const hsize_t n = dataset_size(parent, file, name);
  if (n != count * per_item)
    throw InputError(file + ": dataset '" + name + "' has " + std::to_string(n) +
                     " values; valid: " + std::to_string(per_item) + " for each of the " +
                     std::to_string(count) + " " + items + " (a trackbed snapshot)");
  return read_array(parent, file, name, n);
}

SnapshotClock read_clock(hid_t file, const std::string& path) {
  const auto clock = read_array(file, path, "clock", 2);
  return {clock[0], static_cast<long>(clock[1])};
}

}  // namespace

void write_snapshot(const std::string& path, const Simulation& sim) {
  const std::string tmp = path + ".part";
  {
    const Particles& p = sim.particles();
    Handle file(H5Fcreate(tmp.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose,
                "create " + tmp);
    const double clock[2] = {sim.time(), static_cast<double>(sim.step_count())};
    write_array(file, "clock", clock, 2, 1);
    Handle bodies(H5Gcreate2(file, "bodies", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose,
                  "group bodies");
    const hsize_t nb = p.num_bodies(), ne = p.num_elements();
    std::vector<double> quat;
    for (const auto& q : p.q) quat.insert(quat.end(), {q.w(), q.x(), q.y(), q.z()});
    std::vector<double> mass(p.mass), id(p.id.begin(), p.id.end()),
        clump(p.is_clump.begin(), p.is_clump.end());
    write_array(bodies, "position", pack3(p.x).data(), nb, 3);
    write_array(bodies, "velocity", pack3(p.v).data(), nb, 3);
    write_array(bodies, "orientation_wxyz", quat.data(), nb, 4);
    write_array(bodies, "angular_velocity", pack3(p.w).data(), nb, 3);
    write_array(bodies, "angular_momentum", pack3(p.L).data(), nb, 3);
    write_array(bodies, "mass", mass.data(), nb, 1);
    write_array(bodies, "principal_inertia", pack3(p.inertia).data(), nb, 3);
    write_array(bodies, "id", id.data(), nb, 1);
    write_array(bodies, "is_clump", clump.data(), nb, 1);
    Handle elements(H5Gcreate2(file, "elements", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose,
                    "group elements");
    std::vector<double> body(p.body.begin(), p.body.end()),
        mat(p.material.begin(), p.material.end());
    write_array(elements, "position", pack3(p.pos).data(), ne, 3);
    write_array(elements, "radius", p.radius.data(), ne, 1);
    write_array(elements, "body", body.data(), ne, 1);
    write_array(elements, "material", mat.data(), ne, 1);
    Handle walls(H5Gcreate2(file, "walls", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose,
                 "group walls");
    std::vector<Vec3> points, forces, mx, mv, mw;
    std::vector<double> mq;
    for (const auto& w : sim.planes()) points.push_back(w.point), forces.push_back(w.force);
    for (const auto& m : sim.meshes()) {
      mx.push_back(m.x), mv.push_back(m.v), mw.push_back(m.w);
      mq.insert(mq.end(), {m.q.w(), m.q.x(), m.q.y(), m.q.z()});
    }
    write_array(walls, "plane_point", pack3(points).data(), points.size(), 3);
    write_array(walls, "plane_force", pack3(forces).data(), forces.size(), 3);
    write_array(walls, "mesh_position", pack3(mx).data(), mx.size(), 3);
    write_array(walls, "mesh_orientation_wxyz", mq.data(), mx.size(), 4);
    write_array(walls, "mesh_velocity", pack3(mv).data(), mx.size(), 3);
    write_array(walls, "mesh_angular_velocity", pack3(mw).data(), mx.size(), 3);
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0)
    throw std::runtime_error(path + ": cannot rename the finished snapshot into place");
}

void read_snapshot(const std::string& path, Simulation& sim) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // errors are reported by us, in one line
  const hid_t raw = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (raw < 0) throw InputError(path + ": cannot open as HDF5; valid: a trackbed snapshot (.h5)");
  Handle file(raw, H5Fclose, "open " + path);
  Particles& p = sim.particles();
  const hsize_t nb = p.num_bodies();
  const auto clock = read_array(file, path, "clock", 2);
  Handle bodies(H5Gopen2(file, "bodies", H5P_DEFAULT), H5Gclose, "group bodies");
  unpack3(read_array(bodies, path, "position", 3 * nb), p.x);
  unpack3(read_array(bodies, path, "velocity", 3 * nb), p.v);
  unpack3(read_array(bodies, path, "angular_velocity", 3 * nb), p.w);
  unpack3(read_array(bodies, path, "angular_momentum", 3 * nb), p.L);
  const auto q = read_array(bodies, path, "orientation_wxyz", 4 * nb);
  for (hsize_t b = 0; b < nb; ++b)
    p.q[b] = Quat(q[4 * b], q[4 * b + 1], q[4 * b + 2], q[4 * b + 3]);
  Handle walls(H5Gopen2(file, "walls", H5P_DEFAULT), H5Gclose, "group walls");
  std::vector<Vec3> points(sim.planes().size());
  unpack3(read_array(walls, path, "plane_point", 3 * points.size()), points);
  for (std::size_t w = 0; w < points.size(); ++w) sim.planes()[w].point = points[w];
  const std::size_t nm = sim.meshes().size();
  std::vector<Vec3> mx(nm), mv(nm), mw(nm);
  unpack3(read_array(walls, path, "mesh_position", 3 * nm), mx);
  unpack3(read_array(walls, path, "mesh_velocity", 3 * nm), mv);
  unpack3(read_array(walls, path, "mesh_angular_velocity", 3 * nm), mw);
  const auto mq = read_array(walls, path, "mesh_orientation_wxyz", 4 * nm);
  for (std::size_t m = 0; m < nm; ++m) {
    MeshBody& body = sim.meshes()[m];
    body.x = mx[m], body.v = mv[m], body.w = mw[m];
    body.q = Quat(mq[4 * m], mq[4 * m + 1], mq[4 * m + 2], mq[4 * m + 3]);
    body.update_world_mesh();
  }
  p.update_element_positions();
  sim.set_time(clock[0], static_cast<long>(clock[1]));
}

SnapshotClock read_snapshot_clock(const std::string& path) {
  Handle file = open_snapshot_file(path);
  return read_clock(file, path);
}

SnapshotBodies read_snapshot_bodies(const std::string& path) {
  Handle file = open_snapshot_file(path);
  SnapshotBodies out;
  const SnapshotClock clock = read_clock(file, path);
  out.time = clock.time, out.step = clock.step;
  Handle bodies = open_group(file, path, "bodies");
  const hsize_t nb = dataset_size(bodies, path, "id");
  const auto id = read_array(bodies, path, "id", nb);
  out.id.assign(id.begin(), id.end());
  out.position.resize(nb);
  unpack3(read_per_item(bodies, path, "position", nb, 3, "bodies"), out.position);
  Handle elements = open_group(file, path, "elements");
  const hsize_t ne = dataset_size(elements, path, "radius");
  const auto radius = read_array(elements, path, "radius", ne);
  const auto body = read_per_item(elements, path, "body", ne, 1, "elements");
  std::vector<Vec3> pos(ne);
  unpack3(read_per_item(elements, path, "position", ne, 3, "elements"), pos);
  out.bounding_radius.assign(nb, 0.0);
  for (hsize_t e = 0; e < ne; ++e) {
    const double b = body[e];
    if (!(b >= 0 && b < static_cast<double>(nb)) || b != static_cast<double>(static_cast<long>(b)))
      throw InputError(path + ": element " + std::to_string(e) + " belongs to body " +
                       std::to_string(b) + "; valid: the index of one of the file's " +
                       std::to_string(nb) + " bodies");
    double& r = out.bounding_radius[static_cast<std::size_t>(b)];
    r = std::max(r, (pos[e] - out.position[static_cast<std::size_t>(b)]).norm() + radius[e]);
  }
  Handle walls = open_group(file, path, "walls");
  const hsize_t nm3 = dataset_size(walls, path, "mesh_position");
  if (nm3 % 3 != 0)
    throw InputError(path + ": dataset 'mesh_position' has " + std::to_string(nm3) +
                     " values; valid: three per mesh body");
  out.mesh_position.resize(nm3 / 3);
  unpack3(read_array(walls, path, "mesh_position", nm3), out.mesh_position);
  return out;
}

}  // namespace trackbed::dem
