#include "dem/io/vtu_writer.h"

#include <cstring>
#include <iomanip>

#include "dem/engine/simulation.h"
#include "dem/io/atomic_file.h"

namespace trackbed::dem {

namespace {

// Appended raw binary: every array is a UInt64 byte count followed by the bytes.
class Appended {
 public:
  template <class T>
  std::size_t add(const std::vector<T>& data) {
    const std::size_t at = bytes_.size();
    const std::uint64_t n = data.size() * sizeof(T);
    append(&n, sizeof n);
    append(data.data(), n);
    return at;
  }
  const std::string& bytes() const { return bytes_; }

 private:
  void append(const void* p, std::size_t n) { bytes_.append(static_cast<const char*>(p), n); }
  std::string bytes_;
};

const char* vtk_type(double) {
  return "Float64";
}
const char* vtk_type(std::int64_t) {
  return "Int64";
}
const char* vtk_type(std::uint8_t) {
  return "UInt8";
}

template <class T>
void array_tag(std::ostream& os, Appended& app, const std::string& name, int components,
               const std::vector<T>& data) {
  os << "<DataArray type=\"" << vtk_type(T()) << "\" Name=\"" << name << "\" NumberOfComponents=\""
     << components << "\" format=\"appended\" offset=\"" << app.add(data) << "\"/>\n";
}

std::vector<double> flatten(const std::vector<Vec3>& v) {
  std::vector<double> out(3 * v.size());
  for (std::size_t i = 0; i < v.size(); ++i)
    for (int k = 0; k < 3; ++k) out[3 * i + k] = v[i][k];
  return out;
}

}  // namespace

void VtuGrid::write(const std::string& path) const {
  AtomicFile file(path, std::ios::out | std::ios::binary);
  std::ostream& os = file.stream();
  Appended app;
  os << "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" "
        "byte_order=\"LittleEndian\" header_type=\"UInt64\">\n<UnstructuredGrid>\n"
     << "<Piece NumberOfPoints=\"" << points.size() << "\" NumberOfCells=\"" << types.size()
     << "\">\n<Points>\n";
  array_tag(os, app, "Points", 3, flatten(points));
  os << "</Points>\n<Cells>\n";
  array_tag(os, app, "connectivity", 1, connectivity);
  array_tag(os, app, "offsets", 1, offsets);
  array_tag(os, app, "types", 1, types);
  os << "</Cells>\n<PointData>\n";
  for (const auto& f : point_data) array_tag(os, app, f.name, f.components, f.values);
  os << "</PointData>\n<CellData>\n";
  for (const auto& f : cell_data) array_tag(os, app, f.name, f.components, f.values);
  os << "</CellData>\n</Piece>\n</UnstructuredGrid>\n<AppendedData encoding=\"raw\">\n_";
  os.write(app.bytes().data(), static_cast<std::streamsize>(app.bytes().size()));
  os << "\n</AppendedData>\n</VTKFile>\n";
  file.commit();
}

VtuGrid particles_grid(const Simulation& sim, const std::vector<Vec3>* reference) {
  const Particles& p = sim.particles();
  const int n = p.num_elements();
  VtuGrid g;
  g.points = p.pos;
  std::vector<double> radius(n), body(n), material(n), clump(n), id(n);
  std::vector<Vec3> vel(n), omega(n), disp(n, Vec3::Zero());
  for (int e = 0; e < n; ++e) {
    const int b = p.body[e];
    radius[e] = p.radius[e];
    body[e] = b;
    id[e] = static_cast<double>(p.id[b]);
    material[e] = p.material[e];
    clump[e] = p.is_clump[b];
    vel[e] = p.v[b] + p.w[b].cross(p.pos[e] - p.x[b]);
    omega[e] = p.w[b];
    if (reference) disp[e] = p.pos[e] - (*reference)[e];
  }
  for (int e = 0; e < n; ++e) {
    g.connectivity.push_back(e);
    g.offsets.push_back(e + 1);
    g.types.push_back(1);
  }
  g.point_data = {{"radius", 1, radius},
                  {"velocity", 3, flatten(vel)},
                  {"angular_velocity", 3, flatten(omega)},
                  {"body", 1, body},
                  {"id", 1, id},
                  {"material", 1, material},
                  {"clump", 1, clump}};
  if (reference) g.point_data.push_back({"displacement", 3, flatten(disp)});
  return g;
}

VtuGrid contacts_grid(const Simulation& sim) {
  const Particles& p = sim.particles();
  VtuGrid g;
  std::vector<Vec3> force;
  std::vector<double> magnitude, kind;
  sim.for_each_contact([&](const ContactRecord& c) {
    const auto base = static_cast<std::int64_t>(g.points.size());
    g.points.push_back(c.element_i >= 0 ? p.pos[c.element_i] : c.point);
    g.points.push_back(p.pos[c.element_j]);
    g.connectivity.push_back(base);
    g.connectivity.push_back(base + 1);
    g.offsets.push_back(base + 2);
    g.types.push_back(3);
    force.push_back(c.force);
    magnitude.push_back(c.force.norm());
    kind.push_back(c.wall < 0 ? 0 : 1);
  });
  g.cell_data = {
      {"force", 3, flatten(force)}, {"force_magnitude", 1, magnitude}, {"wall_contact", 1, kind}};
  return g;
}

VtuGrid walls_grid(const Simulation& sim) {
  VtuGrid g;
  std::vector<double> wall, force_mag;
  const Particles& p = sim.particles();
  Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();
  if (p.num_elements() > 0) {
    lo = hi = p.pos[0];
    for (const auto& x : p.pos) lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
  }
  const Vec3 centre = 0.5 * (lo + hi);
  const double half = 0.5 * (hi - lo).norm() + 0.1;
  int w = 0;
  auto add_triangle = [&](const Vec3& a, const Vec3& b, const Vec3& c, double f) {
    const auto base = static_cast<std::int64_t>(g.points.size());
    g.points.insert(g.points.end(), {a, b, c});
    g.connectivity.insert(g.connectivity.end(), {base, base + 1, base + 2});
    g.offsets.push_back(base + 3);
    g.types.push_back(5);
    wall.push_back(w);
    force_mag.push_back(f);
  };
  for (const auto& plane : sim.planes()) {
    const Vec3 o = centre - plane.distance(centre) * plane.normal;
    const Vec3 u = plane.normal.unitOrthogonal() * half;
    const Vec3 v = plane.normal.cross(u);
    const double f = plane.force.norm();
    add_triangle(o - u - v, o + u - v, o + u + v, f);
    add_triangle(o - u - v, o + u + v, o - u + v, f);
    ++w;
  }
  for (const auto& m : sim.meshes()) {
    for (const auto& t : m.world.triangles)
      add_triangle(m.world.vertices[t[0]], m.world.vertices[t[1]], m.world.vertices[t[2]],
                   m.contact_force.norm());
    ++w;
  }
  g.cell_data = {{"wall", 1, wall}, {"wall_force_magnitude", 1, force_mag}};
  return g;
}

void PvdCollection::add(double time, const std::string& relative_file) {
  entries_.emplace_back(time, relative_file);
  AtomicFile file(path_);
  auto& os = file.stream();
  os << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n<Collection>\n"
     << std::setprecision(10);
  for (const auto& [t, f] : entries_)
    os << "<DataSet timestep=\"" << t << "\" part=\"0\" file=\"" << f << "\"/>\n";
  os << "</Collection>\n</VTKFile>\n";
  file.commit();
}

}  // namespace trackbed::dem
