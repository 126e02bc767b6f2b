#include "dem/io/sample.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <unordered_map>

#include "common/input_error.h"
#include "dem/engine/value_checks.h"
#include "dem/io/hdf5_io.h"

namespace trackbed::dem {

namespace {

constexpr const char* kFormat = "trackbed sample 1";

template <class T>
std::vector<std::int64_t> to_int64(const std::vector<T>& v) {
  return std::vector<std::int64_t>(v.begin(), v.end());
}

void write_bodies(hid_t file, const Sample& s) {
  const Particles& p = s.particles;
  hdf5::Handle g(hdf5::create_group(file, "bodies"), H5Gclose, "group bodies");
  hdf5::write_vectors(g, "position", p.x);
  hdf5::write_vectors(g, "velocity", p.v);
  hdf5::write_vectors(g, "angular_velocity", p.w);
  hdf5::write_quaternions(g, "orientation_wxyz", p.q);
  hdf5::write_doubles(g, "mass", p.mass.data(), p.mass.size(), 1);
  hdf5::write_vectors(g, "principal_inertia", p.inertia);
  hdf5::write_integers(g, "id", to_int64(p.id));
  hdf5::write_integers(g, "is_clump", to_int64(p.is_clump));
  hdf5::write_integers(g, "material", to_int64(p.body_material));
  hdf5::write_integers(g, "first_element", to_int64(p.first_element));
  hdf5::write_integers(g, "shape", to_int64(s.shape));
  hdf5::write_doubles(g, "sieve_size", s.sieve_size.data(), s.sieve_size.size(), 1);
  hdf5::write_strings(g, "shape_names", s.shapes);
  hdf5::Handle e(hdf5::create_group(file, "elements"), H5Gclose, "group elements");
  hdf5::write_vectors(e, "offset", p.offset);
  hdf5::write_doubles(e, "radius", p.radius.data(), p.radius.size(), 1);
  hdf5::write_integers(e, "material", to_int64(p.material));
}

void write_walls(hid_t file, const Sample& s) {
  hdf5::Handle g(hdf5::create_group(file, "planes"), H5Gclose, "group planes");
  std::vector<std::string> names;
  std::vector<Vec3> point, normal, velocity;
  std::vector<std::int64_t> material;
  for (const auto& w : s.planes) {
    names.push_back(w.name), point.push_back(w.point), normal.push_back(w.normal);
    velocity.push_back(w.velocity), material.push_back(w.material);
  }
  hdf5::write_strings(g, "names", names);
  hdf5::write_vectors(g, "point", point);
  hdf5::write_vectors(g, "normal", normal);
  hdf5::write_vectors(g, "velocity", velocity);
  hdf5::write_integers(g, "material", material);

  hdf5::Handle m(hdf5::create_group(file, "meshes"), H5Gclose, "group meshes");
  hdf5::write_string_attribute(m, "count", std::to_string(s.meshes.size()));
  for (std::size_t k = 0; k < s.meshes.size(); ++k) {
    const MeshBody& b = s.meshes[k];
    const std::string name = std::to_string(k);
    hdf5::Handle g2(hdf5::create_group(m, name.c_str()), H5Gclose, "group mesh");
    hdf5::write_string_attribute(g2, "name", b.name);
    hdf5::write_strings(g2, "part_names", b.local.part_names);
    hdf5::write_vectors(g2, "local_vertices", b.local.vertices);
    std::vector<std::int64_t> tri, part;
    for (const auto& t : b.local.triangles) tri.insert(tri.end(), t.begin(), t.end());
    for (int p : b.local.triangle_part) part.push_back(p);
    hdf5::write_integers(g2, "triangles", tri);
    hdf5::write_integers(g2, "triangle_part", part);
    const double pose[7] = {b.x.x(), b.x.y(), b.x.z(), b.q.w(), b.q.x(), b.q.y(), b.q.z()};
    hdf5::write_doubles(g2, "position_orientation_wxyz", pose, 7, 1);
    hdf5::write_doubles(g2, "mass", &b.mass, 1, 1);
    hdf5::write_doubles(g2, "inertia", b.inertia.data(), 3, 3);
    hdf5::write_integers(g2, "material", {b.material});
  }
}

void write_contacts(hid_t file, const ContactState& c) {
  hdf5::Handle g(hdf5::create_group(file, "contacts"), H5Gclose, "group contacts");
  std::vector<std::int64_t> pair_keys, wall_keys;
  std::vector<Vec3> pair_shear, pair_roll, wall_shear, wall_roll, wall_normal;
  for (const auto& p : c.pairs) {
    pair_keys.insert(pair_keys.end(), {p.i.body_id, p.i.rank, p.j.body_id, p.j.rank});
    pair_shear.push_back(p.shear), pair_roll.push_back(p.roll);
  }
  for (const auto& w : c.walls) {
    wall_keys.insert(wall_keys.end(), {w.wall, w.slot, w.element.body_id, w.element.rank});
    wall_shear.push_back(w.shear), wall_roll.push_back(w.roll), wall_normal.push_back(w.normal);
  }
  hdf5::write_integers(g, "pair_keys", pair_keys);
  hdf5::write_vectors(g, "pair_shear", pair_shear);
  hdf5::write_vectors(g, "pair_roll", pair_roll);
  hdf5::write_integers(g, "wall_keys", wall_keys);
  hdf5::write_vectors(g, "wall_shear", wall_shear);
  hdf5::write_vectors(g, "wall_roll", wall_roll);
  hdf5::write_vectors(g, "wall_normal", wall_normal);
}

// Throws InputError unless every value of `dataset` (at `what`) is an index in [0, n): checked
// before the values are narrowed to int.
void require_indices(const std::vector<std::int64_t>& dataset, std::int64_t n,
                     const std::string& path, const std::string& what) {
  for (std::int64_t i : dataset)
    if (i < 0 || i >= n)
      throw InputError(path + ": " + what + " holds " + std::to_string(i) +
                       ", not an index in [0, " + std::to_string(n) + "); the file is damaged");
}

Particles read_particles(hid_t file, const std::string& path, Sample& s) {
  hdf5::Handle g(hdf5::open_group(file, path, "bodies"), H5Gclose, "group bodies");
  const auto x = hdf5::read_vectors(g, path, "position");
  const long nb = static_cast<long>(x.size());
  const auto v = hdf5::read_vectors(g, path, "velocity", nb);
  const auto w = hdf5::read_vectors(g, path, "angular_velocity", nb);
  const auto q = hdf5::read_quaternions(g, path, "orientation_wxyz", nb);
  const auto mass = hdf5::read_doubles(g, path, "mass", nb);
  const auto inertia = hdf5::read_vectors(g, path, "principal_inertia", nb);
  const auto id = hdf5::read_integers(g, path, "id", nb);
  const auto clump = hdf5::read_integers(g, path, "is_clump", nb);
  for (std::int64_t k : clump)
    if (k != 0 && k != 1)
      throw InputError(path + ": bodies/is_clump holds " + std::to_string(k) +
                       "; the file is damaged (valid: 0 or 1)");
  const auto material = hdf5::read_integers(g, path, "material", nb);
  const auto first = hdf5::read_integers(g, path, "first_element", nb + 1);
  const auto shape = hdf5::read_integers(g, path, "shape", nb);
  s.sieve_size = hdf5::read_doubles(g, path, "sieve_size", nb);
  s.shapes = hdf5::read_strings(g, path, "shape_names");
  s.shape.assign(shape.begin(), shape.end());
  hdf5::Handle e(hdf5::open_group(file, path, "elements"), H5Gclose, "group elements");
  const long ne = first.empty() ? 0 : static_cast<long>(first.back());
  const auto offset = hdf5::read_vectors(e, path, "offset", ne);
  const auto radius = hdf5::read_doubles(e, path, "radius", ne);
  const auto el_material = hdf5::read_integers(e, path, "material", ne);
  // Indices are narrowed to int below: out-of-range values are refused first.
  const auto nmat = static_cast<std::int64_t>(s.materials.size());
  require_indices(material, nmat, path, "bodies/material");
  require_indices(el_material, nmat, path, "elements/material");

  Particles p;
  for (long b = 0; b < nb; ++b) {
    if (first[b] < 0 || first[b] >= first[b + 1] || first[b + 1] > ne)
      throw InputError(path + ": bodies/first_element is not increasing; the file is damaged");
    // add_body_with_elements normalises: a damaged orientation is refused before it does.
    if (!unit_norm(q[b]))
      throw InputError(path + ": body " + std::to_string(b) +
                       " has an orientation quaternion of norm " + std::to_string(q[b].norm()) +
                       "; the file is damaged");
    std::vector<SphereShape> elements;
    for (long k = first[b]; k < first[b + 1]; ++k) elements.push_back({offset[k], radius[k]});
    const int i =
        p.add_body_with_elements(x[b], q[b], mass[b], inertia[b], static_cast<int>(material[b]),
                                 clump[b] != 0, id[b], elements);
    p.v[i] = v[b], p.w[i] = w[b];
    for (long k = first[b]; k < first[b + 1]; ++k) p.material[k] = static_cast<int>(el_material[k]);
  }
  return p;
}

void read_walls(hid_t file, const std::string& path, Sample& s) {
  hdf5::Handle g(hdf5::open_group(file, path, "planes"), H5Gclose, "group planes");
  const auto names = hdf5::read_strings(g, path, "names");
  const long n = static_cast<long>(names.size());
  const auto point = hdf5::read_vectors(g, path, "point", n);
  const auto normal = hdf5::read_vectors(g, path, "normal", n);
  const auto velocity = hdf5::read_vectors(g, path, "velocity", n);
  const auto material = hdf5::read_integers(g, path, "material", n);
  require_indices(material, static_cast<std::int64_t>(s.materials.size()), path, "planes/material");
  for (long k = 0; k < n; ++k) {
    PlaneWall w;
    w.name = names[k], w.point = point[k], w.normal = normal[k], w.velocity = velocity[k];
    w.material = static_cast<int>(material[k]);
    s.planes.push_back(w);
  }

  hdf5::Handle m(hdf5::open_group(file, path, "meshes"), H5Gclose, "group meshes");
  const std::string count_text = hdf5::read_string_attribute(m, path, "count");
  const int count = count_text == "0" ? 0 : std::atoi(count_text.c_str());
  if (!(count > 0 && count <= 1024) && count_text != "0")
    throw InputError(path + ": meshes/count is '" + excerpt(count_text) +
                     "'; the file is damaged (valid: 0 to 1024)");
  for (int k = 0; k < count; ++k) {
    const std::string name = std::to_string(k);
    hdf5::Handle g2(hdf5::open_group(m, path, name.c_str()), H5Gclose, "group mesh");
    MeshBody b;
    b.name = hdf5::read_string_attribute(g2, path, "name");
    TriangleMesh mesh;
    mesh.part_names = hdf5::read_strings(g2, path, "part_names");
    mesh.vertices = hdf5::read_vectors(g2, path, "local_vertices");
    const auto tri = hdf5::read_integers(g2, path, "triangles");
    require_indices(tri, static_cast<std::int64_t>(mesh.vertices.size()), path,
                    "meshes/" + name + "/triangles");
    for (std::size_t t = 0; t + 2 < tri.size(); t += 3)
      mesh.triangles.push_back(
          {static_cast<int>(tri[t]), static_cast<int>(tri[t + 1]), static_cast<int>(tri[t + 2])});
    const auto part = hdf5::read_integers(g2, path, "triangle_part", mesh.triangles.size());
    require_indices(part, static_cast<std::int64_t>(mesh.part_names.size()), path,
                    "meshes/" + name + "/triangle_part");
    for (auto p : part) mesh.triangle_part.push_back(static_cast<int>(p));
    try {
      mesh.finalize();
    } catch (const std::exception& e) {
      throw InputError(path + ": mesh '" + b.name + "': " + e.what());
    }
    const auto pose = hdf5::read_doubles(g2, path, "position_orientation_wxyz", 7);
    b.x = Vec3(pose[0], pose[1], pose[2]);
    b.q = Quat(pose[3], pose[4], pose[5], pose[6]);
    b.mass = hdf5::read_doubles(g2, path, "mass", 1)[0];
    const auto inertia = hdf5::read_doubles(g2, path, "inertia", 9);
    b.inertia = Eigen::Map<const Mat3>(inertia.data());
    const std::int64_t material = hdf5::read_integers(g2, path, "material", 1)[0];
    if (!(material >= 0 && material < static_cast<std::int64_t>(s.materials.size())) ||
        !all_finite(pose) || !unit_norm(b.q) || !(b.mass >= 0 && std::isfinite(b.mass)) ||
        !b.inertia.allFinite())
      throw InputError(path + ": mesh '" + excerpt(b.name) +
                       "' has a material index, pose, mass or inertia out of range; the file is "
                       "damaged");
    b.material = static_cast<int>(material);
    b.local = mesh;
    b.world = mesh;
    b.update_world_mesh();
    s.meshes.push_back(std::move(b));
  }
}

ContactState read_contacts(hid_t file, const std::string& path) {
  hdf5::Handle g(hdf5::open_group(file, path, "contacts"), H5Gclose, "group contacts");
  ContactState c;
  const auto pk = hdf5::read_integers(g, path, "pair_keys");
  const long np = static_cast<long>(pk.size() / 4);
  const auto ps = hdf5::read_vectors(g, path, "pair_shear", np);
  const auto pr = hdf5::read_vectors(g, path, "pair_roll", np);
  for (long k = 0; k < np; ++k)
    c.pairs.push_back({{pk[4 * k], static_cast<int>(pk[4 * k + 1])},
                       {pk[4 * k + 2], static_cast<int>(pk[4 * k + 3])},
                       ps[k],
                       pr[k]});
  const auto wk = hdf5::read_integers(g, path, "wall_keys");
  // Walls, slots and element ranks are ints >= 0 (a body id may be any int64).
  for (const auto* keys : {&pk, &wk})
    for (std::size_t k = 0; k < keys->size(); ++k)
      if ((keys == &pk ? k % 2 == 1 : k % 4 != 2) &&
          ((*keys)[k] < 0 || (*keys)[k] > std::numeric_limits<int>::max()))
        throw InputError(path + ": contacts/" + (keys == &pk ? "pair_keys" : "wall_keys") +
                         " holds " + std::to_string((*keys)[k]) +
                         " where an index >= 0 belongs; the file is damaged");
  const long nw = static_cast<long>(wk.size() / 4);
  const auto ws = hdf5::read_vectors(g, path, "wall_shear", nw);
  const auto wr = hdf5::read_vectors(g, path, "wall_roll", nw);
  const auto wn = hdf5::read_vectors(g, path, "wall_normal", nw);
  auto finite = [](const std::vector<Vec3>& v) {
    return std::all_of(v.begin(), v.end(), [](const Vec3& a) { return a.allFinite(); });
  };
  if (!finite(ps) || !finite(pr) || !finite(ws) || !finite(wr) || !finite(wn))
    throw InputError(path + ": a contact spring or normal is not finite; the file is damaged");
  for (long k = 0; k < nw; ++k)
    c.walls.push_back({static_cast<int>(wk[4 * k]),
                       static_cast<int>(wk[4 * k + 1]),
                       {wk[4 * k + 2], static_cast<int>(wk[4 * k + 3])},
                       ws[k],
                       wr[k],
                       wn[k]});
  return c;
}

// Whether the saved contacts name elements and walls of this sample ("" when they all do).
std::string contacts_defect(const Sample& s) {
  const Particles& p = s.particles;
  std::unordered_map<std::int64_t, int> body_of_id;
  for (int b = 0; b < p.num_bodies(); ++b) body_of_id[p.id[b]] = b;
  auto known = [&](const ElementKey& k) {
    const auto it = body_of_id.find(k.body_id);
    return it != body_of_id.end() && k.rank >= 0 &&
           k.rank < p.first_element[it->second + 1] - p.first_element[it->second];
  };
  for (const SavedPairContact& c : s.contacts.pairs)
    if (!known(c.i) || !known(c.j))
      return "a contact names element " + std::to_string(c.i.rank) + " of body id " +
             std::to_string(c.i.body_id) + " or " + std::to_string(c.j.rank) + " of " +
             std::to_string(c.j.body_id) + ", not in the sample";
  const int walls = static_cast<int>(s.planes.size() + s.meshes.size());
  for (const SavedWallContact& c : s.contacts.walls)
    if (!known(c.element) || c.wall < 0 || c.wall >= walls || c.slot < 0)
      return "a wall contact names wall " + std::to_string(c.wall) + ", slot " +
             std::to_string(c.slot) + " or an element not in the sample";
  return "";
}

}  // namespace

std::string Sample::info_value(const std::string& key) const {
  for (const auto& [k, v] : info)
    if (k == key) return v;
  return "";
}

void write_sample(const std::string& path, const Sample& sample) {
  hdf5::write_file(path, "sample", [&](hid_t file) {
    hdf5::write_string_attribute(file, "format", kFormat);
    hdf5::write_strings(file, "materials", sample.materials);
    std::vector<std::string> info;
    for (const auto& [k, v] : sample.info) info.push_back(k + " = " + v);
    hdf5::write_strings(file, "info", info);
    write_bodies(file, sample);
    write_walls(file, sample);
    write_contacts(file, sample.contacts);
  });
}

Sample read_sample(const std::string& path) {
  hdf5::Handle file(hdf5::open_for_reading(path, "a trackbed sample (.h5)"), H5Fclose,
                    "open " + path);
  if (!hdf5::has_format(file, path, kFormat))
    throw InputError(path + ": not a trackbed sample (no 'format = " + kFormat +
                     "' attribute); valid: a file written by 'trackbed build-sample'");
  Sample s;
  s.materials = hdf5::read_strings(file, path, "materials");
  for (const auto& line : hdf5::read_strings(file, path, "info")) {
    const auto eq = line.find(" = ");
    if (eq == std::string::npos)
      throw InputError(path + ": info line '" + excerpt(line) +
                       "' is not 'key = value'; the file is damaged");
    s.info.emplace_back(line.substr(0, eq), line.substr(eq + 3));
  }
  s.particles = read_particles(file, path, s);
  read_walls(file, path, s);
  s.contacts = read_contacts(file, path);
  const int nmat = static_cast<int>(s.materials.size());
  std::string defect = s.particles.defect(nmat);
  for (std::size_t b = 0; b < s.shape.size() && defect.empty(); ++b)
    if (s.shape[b] < -1 || s.shape[b] >= static_cast<int>(s.shapes.size()) ||
        !positive_finite(s.sieve_size[b]))
      defect = "body " + std::to_string(b) + " has a shape index or sieve size out of range";
  for (const PlaneWall& w : s.planes)
    if (defect.empty() && (!w.point.allFinite() || !w.velocity.allFinite() ||
                           !unit_norm(w.normal) || w.material < 0 || w.material >= nmat))
      defect = "plane wall '" + w.name +
               "' has a non-finite point or velocity, a normal not of "
               "unit length or a material index out of range";
  if (defect.empty()) defect = contacts_defect(s);
  if (!defect.empty()) throw InputError(path + ": " + defect + "; the file is damaged");
  return s;
}

}  // namespace trackbed::dem
