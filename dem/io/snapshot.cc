#include "dem/io/snapshot.h"

#include <algorithm>
#include <vector>

#include "common/input_error.h"
#include "dem/engine/simulation.h"
#include "dem/io/hdf5_io.h"

namespace trackbed::dem {

namespace {

using hdf5::Handle;

constexpr const char* kWhat = "a trackbed snapshot (.h5)";

// A dataset that must hold `per_item` values for each of `count` items (bodies, elements).
std::vector<double> read_per_item(hid_t parent, const std::string& file, const char* name,
                                  long count, long per_item, const char* items) {
  const long n = hdf5::dataset_size(parent, file, name);
  if (n != count * per_item)
    throw InputError(file + ": dataset '" + name + "' has " + std::to_string(n) +
                     " values; valid: " + std::to_string(per_item) + " for each of the " +
                     std::to_string(count) + " " + items + " (a trackbed snapshot)");
  return hdf5::read_doubles(parent, file, name, n);
}

SnapshotClock read_clock(hid_t file, const std::string& path) {
  const auto clock = hdf5::read_doubles(file, path, "clock", 2);
  return {clock[0], static_cast<long>(clock[1])};
}

template <class T>
std::vector<double> as_doubles(const std::vector<T>& v) {
  return std::vector<double>(v.begin(), v.end());
}

}  // namespace

void write_snapshot(const std::string& path, const Simulation& sim) {
  hdf5::write_file(path, "snapshot", [&](hid_t file) {
    const Particles& p = sim.particles();
    hdf5::write_doubles(file, "clock", {sim.time(), static_cast<double>(sim.step_count())});
    Handle bodies(hdf5::create_group(file, "bodies"), H5Gclose, "group bodies");
    hdf5::write_vectors(bodies, "position", p.x);
    hdf5::write_vectors(bodies, "velocity", p.v);
    hdf5::write_quaternions(bodies, "orientation_wxyz", p.q);
    hdf5::write_vectors(bodies, "angular_velocity", p.w);
    hdf5::write_vectors(bodies, "angular_momentum", p.L);
    hdf5::write_doubles(bodies, "mass", p.mass);
    hdf5::write_vectors(bodies, "principal_inertia", p.inertia);
    hdf5::write_doubles(bodies, "id", as_doubles(p.id));
    hdf5::write_doubles(bodies, "is_clump", as_doubles(p.is_clump));
    Handle elements(hdf5::create_group(file, "elements"), H5Gclose, "group elements");
    hdf5::write_vectors(elements, "position", p.pos);
    hdf5::write_doubles(elements, "radius", p.radius);
    hdf5::write_doubles(elements, "body", as_doubles(p.body));
    hdf5::write_doubles(elements, "material", as_doubles(p.material));
    Handle walls(hdf5::create_group(file, "walls"), H5Gclose, "group walls");
    std::vector<Vec3> points, forces, mx, mv, mw;
    std::vector<Quat> mq;
    for (const auto& w : sim.planes()) points.push_back(w.point), forces.push_back(w.force);
    for (const auto& m : sim.meshes())
      mx.push_back(m.x), mv.push_back(m.v), mw.push_back(m.w), mq.push_back(m.q);
    hdf5::write_vectors(walls, "plane_point", points);
    hdf5::write_vectors(walls, "plane_force", forces);
    hdf5::write_vectors(walls, "mesh_position", mx);
    hdf5::write_quaternions(walls, "mesh_orientation_wxyz", mq);
    hdf5::write_vectors(walls, "mesh_velocity", mv);
    hdf5::write_vectors(walls, "mesh_angular_velocity", mw);
  });
}

void read_snapshot(const std::string& path, Simulation& sim) {
  Handle file(hdf5::open_for_reading(path, kWhat), H5Fclose, "open " + path);
  Particles& p = sim.particles();
  const long nb = p.num_bodies();
  const SnapshotClock clock = read_clock(file, path);
  Handle bodies(hdf5::open_group(file, path, "bodies"), H5Gclose, "group bodies");
  p.x = hdf5::read_vectors(bodies, path, "position", nb);
  p.v = hdf5::read_vectors(bodies, path, "velocity", nb);
  p.w = hdf5::read_vectors(bodies, path, "angular_velocity", nb);
  p.L = hdf5::read_vectors(bodies, path, "angular_momentum", nb);
  p.q = hdf5::read_quaternions(bodies, path, "orientation_wxyz", nb);
  Handle walls(hdf5::open_group(file, path, "walls"), H5Gclose, "group walls");
  const auto points = hdf5::read_vectors(walls, path, "plane_point", sim.planes().size());
  for (std::size_t w = 0; w < points.size(); ++w) sim.planes()[w].point = points[w];
  const long nm = static_cast<long>(sim.meshes().size());
  const auto mx = hdf5::read_vectors(walls, path, "mesh_position", nm);
  const auto mv = hdf5::read_vectors(walls, path, "mesh_velocity", nm);
  const auto mw = hdf5::read_vectors(walls, path, "mesh_angular_velocity", nm);
  const auto mq = hdf5::read_quaternions(walls, path, "mesh_orientation_wxyz", nm);
  for (long m = 0; m < nm; ++m) {
    MeshBody& body = sim.meshes()[m];
    body.x = mx[m], body.v = mv[m], body.w = mw[m], body.q = mq[m];
    body.update_world_mesh();
  }
  p.update_element_positions();
  sim.set_time(clock.time, clock.step);
}

SnapshotClock read_snapshot_clock(const std::string& path) {
  Handle file(hdf5::open_for_reading(path, kWhat), H5Fclose, "open " + path);
  return read_clock(file, path);
}

SnapshotBodies read_snapshot_bodies(const std::string& path) {
  Handle file(hdf5::open_for_reading(path, kWhat), H5Fclose, "open " + path);
  SnapshotBodies out;
  const SnapshotClock clock = read_clock(file, path);
  out.time = clock.time, out.step = clock.step;
  Handle bodies(hdf5::open_group(file, path, "bodies"), H5Gclose, "group bodies");
  const long nb = hdf5::dataset_size(bodies, path, "id");
  const auto id = hdf5::read_doubles(bodies, path, "id", nb);
  out.id.assign(id.begin(), id.end());
  const auto position = read_per_item(bodies, path, "position", nb, 3, "bodies");
  for (long b = 0; b < nb; ++b)
    out.position.emplace_back(position[3 * b], position[3 * b + 1], position[3 * b + 2]);
  Handle elements(hdf5::open_group(file, path, "elements"), H5Gclose, "group elements");
  const long ne = hdf5::dataset_size(elements, path, "radius");
  const auto radius = hdf5::read_doubles(elements, path, "radius", ne);
  const auto body = read_per_item(elements, path, "body", ne, 1, "elements");
  const auto pos = read_per_item(elements, path, "position", ne, 3, "elements");
  out.bounding_radius.assign(nb, 0.0);
  for (long e = 0; e < ne; ++e) {
    const double b = body[e];
    if (!(b >= 0 && b < static_cast<double>(nb)) || b != static_cast<double>(static_cast<long>(b)))
      throw InputError(path + ": element " + std::to_string(e) + " belongs to body " +
                       std::to_string(b) + "; valid: the index of one of the file's " +
                       std::to_string(nb) + " bodies");
    const Vec3 x(pos[3 * e], pos[3 * e + 1], pos[3 * e + 2]);
    double& r = out.bounding_radius[static_cast<std::size_t>(b)];
    r = std::max(r, (x - out.position[static_cast<std::size_t>(b)]).norm() + radius[e]);
  }
  Handle walls(hdf5::open_group(file, path, "walls"), H5Gclose, "group walls");
  const long nm3 = hdf5::dataset_size(walls, path, "mesh_position");
  if (nm3 % 3 != 0)
    throw InputError(path + ": dataset 'mesh_position' has " + std::to_string(nm3) +
                     " values; valid: three per mesh body");
  out.mesh_position = hdf5::read_vectors(walls, path, "mesh_position", nm3 / 3);
  return out;
}

}  // namespace trackbed::dem
