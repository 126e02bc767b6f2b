// Meshes of ElasticBody: built in code (box, track section, sleeper) or read from Gmsh.
#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_in.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/grid/tria.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <regex>
#include <sstream>

#include "common/number_text.h"
#include "fem/elastic_body_impl.h"
#include "fem/errors.h"

namespace trackbed::fem {

using namespace dealii;

namespace {

// Points 0 = x_0 < x_1 < ... covering [a, b] with steps no longer than h.
std::vector<double> steps(const double a, const double b, const double h) {
  const unsigned int n = std::max(1u, static_cast<unsigned int>(std::ceil((b - a) / h - 1e-9)));
  return std::vector<double>(n, (b - a) / n);
}

unsigned int count(const double length, const double h) {
  return std::max(1u, static_cast<unsigned int>(std::ceil(length / h - 1e-9)));
}

void require_positive(const std::string& where, const std::string& name, const double value) {
  if (!(value > 0.0 && std::isfinite(value)))
    throw InputError(where + ": '" + name + "' = " + std::to_string(value) +
                     " m is invalid; it must be > 0");
}

// The names of the physical groups of a Gmsh file ($PhysicalNames: dimension, tag, "name"), the
// same in format 2.2 and 4.1.
std::map<std::string, std::pair<int, unsigned int>> physical_names(const std::string& file) {
  std::ifstream in(file);
  std::map<std::string, std::pair<int, unsigned int>> names;
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("$PhysicalNames", 0) == 0) {
      std::size_t n = 0;
      in >> n;
      std::getline(in, line);
      for (std::size_t i = 0; i < n && std::getline(in, line); ++i) {
        std::istringstream entry(line);
        int dimension = 0;
        unsigned int tag = 0;
        std::string name;
        entry >> dimension >> tag;
        std::getline(entry >> std::ws, name);
        name.erase(std::remove(name.begin(), name.end(), '"'), name.end());
        names[name] = {dimension, tag};
      }
      break;
    }
  return names;
}

// The one useful line of a deal.II exception text: its "Additional information", else the
// violated condition.
std::string first_reason(const std::string& what) {
  std::istringstream in(what);
  std::string line, heading, information, condition;
  while (std::getline(in, line)) {
    line = std::regex_replace(line, std::regex("^\\s+|\\s+$"), "");
    if (line.rfind("Additional information:", 0) == 0 ||
        line.rfind("The violated condition was:", 0) == 0)
      heading = line;
    else if (!line.empty() && !heading.empty()) {
      (heading[0] == 'A' ? information : condition) = line;
      heading.clear();
    }
  }
  if (!information.empty()) return information;
  return condition.empty() ? "not a Gmsh mesh deal.II can read" : condition;
}

}  // namespace

void ElasticBody::make_box(const BoxGeometry& box) {
  Impl& d = *impl_;
  for (unsigned int c = 0; c < dim; ++c) {
    require_positive("box", "upper - lower", box.upper[c] - box.lower[c]);
    if (box.subdivisions[c] == 0) throw InputError("box: 'subdivisions' must be >= 1");
  }
  d.triangulation.clear();
  GridGenerator::subdivided_hyper_rectangle(
      d.triangulation, std::vector<unsigned int>(box.subdivisions.begin(), box.subdivisions.end()),
      to_point(box.lower), to_point(box.upper), true);
  for (const auto& cell : d.triangulation.active_cell_iterators()) {
    cell->set_material_id(0);
    const double z = cell->center()[2];
    for (const auto& layer : box.layers)
      if (z >= layer.z_min && z < layer.z_max) cell->set_material_id(layer.material_id);
  }
  d.boundary_names = {{"xmin", 0}, {"xmax", 1}, {"ymin", 2}, {"ymax", 3}, {"zmin", 4}, {"zmax", 5}};
  d.mesh_description = "the box mesh";
  d.is_set_up = false;
}

// The cross-section (x, z) is a structured grid of columns and rows. Inner columns span the
// embankment: at height z their nodes sit at x = xi b(z), xi in [-1, 1], where b(z) is the layer's
// half-width, so the outer columns follow the slopes. Outer columns exist only in the ground
// block. The section is extruded along y.
void ElasticBody::make_track_section(const TrackSection& s, const double element_size) {
  Impl& d = *impl_;
  const std::string where = "track section";
  for (const auto& [name, value] : std::vector<std::pair<std::string, double>>{
           {"sleeper length", s.sleeper_length},
           {"section length", s.length},
           {"sub-ballast thickness", s.sub_ballast_thickness},
           {"embankment height", s.embankment_height},
           {"ground depth", s.ground_depth},
           {"element size", element_size}})
    require_positive(where, name, value);
  if (s.lower_ballast_thickness < 0.0 || s.shoulder_width < 0.0 || s.depth_under_sleeper < 0.0 ||
      s.sleeper_height < 0.0 || s.slope < 0.0 || s.embankment_slope < 0.0)
    throw InputError(where + ": thicknesses, widths and slopes must be >= 0");

  const double h = element_size;
  // Rows: z levels from the bottom up, with the layer (material id) of each row.
  const double z_lower_ballast = -s.lower_ballast_thickness;
  const double z_sub_ballast = z_lower_ballast - s.sub_ballast_thickness;
  const double z_ground = z_sub_ballast - s.embankment_height;
  const double z_bottom = z_ground - s.ground_depth;
  std::vector<double> z_levels{z_bottom};
  std::vector<unsigned int> row_material;
  auto add_layer = [&](const double top, const unsigned int material_id) {
    const double bottom = z_levels.back();
    const unsigned int n = count(top - bottom, h);
    for (unsigned int i = 1; i <= n; ++i) {
      // The layer's top exactly (the formation at z = 0 is where the DEM base was).
      z_levels.push_back(i == n ? top : bottom + (top - bottom) * i / n);
      row_material.push_back(material_id);
    }
  };
  add_layer(z_ground, track_section::ground_id);
  const unsigned int n_ground_rows = row_material.size();
  add_layer(z_sub_ballast, track_section::subgrade_id);
  add_layer(z_lower_ballast, track_section::sub_ballast_id);
  if (s.lower_ballast_thickness > 0.0) add_layer(0.0, track_section::lower_ballast_id);

  // Half-width of the continuum at height z >= z_ground.
  const double b0 = s.half_base_width();
  const double b1 = b0 + s.lower_ballast_thickness * s.slope;
  auto half_width = [&](const double z) {
    return z >= z_lower_ballast ? b0 - z * s.slope
                                : b1 + (z_lower_ballast - z) * s.embankment_slope;
  };
  const double b_ground = half_width(z_ground);
  if (s.ground_half_width < b_ground + h)
    throw InputError(where + ": 'ground half width' = " + number_text(s.ground_half_width) +
                     " m does not reach one element size beyond the embankment base (half-width " +
                     number_text(b_ground) + " m); valid: >= " + number_text(b_ground + h) + " m");
  const unsigned int n_inner = 2 * count(b0, h);
  const unsigned int n_outer = count(s.ground_half_width - b_ground, 2.0 * h);
  const unsigned int nx = n_inner + 2 * n_outer;  // columns of cells
  const unsigned int nz = z_levels.size() - 1;
  const unsigned int ny = count(s.length, h);

  auto x_of = [&](const unsigned int ix, const unsigned int iz) {
    const double z = z_levels[iz];
    if (ix < n_outer) return -s.ground_half_width + (s.ground_half_width - b_ground) * ix / n_outer;
    if (ix > n_outer + n_inner)
      return b_ground + (s.ground_half_width - b_ground) * (ix - n_outer - n_inner) / n_outer;
    const double xi = -1.0 + 2.0 * (ix - n_outer) / n_inner;
    return xi * half_width(std::max(z, z_ground));
  };
  std::vector<Point<dim>> vertices((nx + 1) * (ny + 1) * (nz + 1));
  auto vertex = [&](unsigned int ix, unsigned int iy, unsigned int iz) {
    return (iz * (ny + 1) + iy) * (nx + 1) + ix;
  };
  for (unsigned int iz = 0; iz <= nz; ++iz)
    for (unsigned int iy = 0; iy <= ny; ++iy)
      for (unsigned int ix = 0; ix <= nx; ++ix)
        vertices[vertex(ix, iy, iz)] =
            Point<dim>(x_of(ix, iz), s.length * (double(iy) / ny - 0.5), z_levels[iz]);
  std::vector<CellData<dim>> cells;
  for (unsigned int iz = 0; iz < nz; ++iz)
    for (unsigned int iy = 0; iy < ny; ++iy)
      for (unsigned int ix = 0; ix < nx; ++ix) {
        const bool inner = ix >= n_outer && ix < n_outer + n_inner;
        if (!inner && iz >= n_ground_rows) continue;
        CellData<dim> cell;
        for (unsigned int k = 0; k < 2; ++k)
          for (unsigned int j = 0; j < 2; ++j)
            for (unsigned int i = 0; i < 2; ++i)
              cell.vertices[i + 2 * j + 4 * k] = vertex(ix + i, iy + j, iz + k);
        cell.material_id = row_material[iz];
        cells.push_back(cell);
      }
  SubCellData no_subcells;
  GridTools::delete_unused_vertices(vertices, cells, no_subcells);
  d.triangulation.clear();
  d.triangulation.create_triangulation(vertices, cells, no_subcells);

  const double tolerance = 1e-6 * h;
  for (const auto& cell : d.triangulation.active_cell_iterators())
    for (const auto& face : cell->face_iterators()) {
      if (!face->at_boundary()) continue;
      const Point<dim> c = face->center();
      if (std::abs(c[2]) < tolerance)
        face->set_boundary_id(0);
      else if (std::abs(std::abs(c[1]) - 0.5 * s.length) < tolerance)
        face->set_boundary_id(2);
      else if (std::abs(std::abs(c[0]) - s.ground_half_width) < tolerance)
        face->set_boundary_id(3);
      else if (std::abs(c[2] - z_bottom) < tolerance)
        face->set_boundary_id(4);
      else
        face->set_boundary_id(1);
    }
  d.boundary_names = {
      {"formation", 0}, {"free_surface", 1}, {"ends", 2}, {"sides", 3}, {"bottom", 4}};
  d.mesh_description = "the track section mesh";
  d.is_set_up = false;
}

// The sleeper's x-steps put cell boundaries at the rail seat edges, so the rail seats are exact.
void ElasticBody::make_sleeper(const SleeperGeometry& s) {
  Impl& d = *impl_;
  const std::string where = "sleeper";
  for (const auto& [name, value] :
       std::vector<std::pair<std::string, double>>{{"length", s.length},
                                                   {"width", s.width},
                                                   {"height", s.height},
                                                   {"rail seat width", s.rail_seat_width},
                                                   {"element size", s.element_size}})
    require_positive(where, name, value);
  const double seat_outer = 0.5 * (s.rail_seat_spacing + s.rail_seat_width);
  const double seat_inner = 0.5 * (s.rail_seat_spacing - s.rail_seat_width);
  if (!(seat_inner > 0.0 && seat_outer < 0.5 * s.length))
    throw InputError(where + ": 'rail seat spacing' = " + std::to_string(s.rail_seat_spacing) +
                     " m is invalid; both rail seats must lie on the sleeper, between its centre "
                     "and its ends");
  const double h = s.element_size, half = 0.5 * s.length;
  std::vector<double> x_steps;
  for (const auto& [a, b] : std::vector<std::pair<double, double>>{{-half, -seat_outer},
                                                                   {-seat_outer, -seat_inner},
                                                                   {-seat_inner, seat_inner},
                                                                   {seat_inner, seat_outer},
                                                                   {seat_outer, half}}) {
    const auto part = steps(a, b, h);
    x_steps.insert(x_steps.end(), part.begin(), part.end());
  }
  const Vector3& o = s.soffit_centre;
  d.triangulation.clear();
  GridGenerator::subdivided_hyper_rectangle(
      d.triangulation, {x_steps, steps(0.0, s.width, h), steps(0.0, s.height, h)},
      Point<dim>(o[0] - half, o[1] - 0.5 * s.width, o[2]),
      Point<dim>(o[0] + half, o[1] + 0.5 * s.width, o[2] + s.height), false);
  const double tolerance = 1e-6 * h;
  for (const auto& cell : d.triangulation.active_cell_iterators())
    for (const auto& face : cell->face_iterators()) {
      if (!face->at_boundary()) continue;
      const Point<dim> c = face->center();
      const double x = c[0] - o[0];
      face->set_boundary_id(0);
      if (std::abs(c[2] - o[2]) < tolerance) face->set_boundary_id(1);
      if (std::abs(c[2] - o[2] - s.height) < tolerance && std::abs(x) > seat_inner &&
          std::abs(x) < seat_outer)
        face->set_boundary_id(x < 0.0 ? 2 : 3);
    }
  d.boundary_names = {{"free", 0}, {"soffit", 1}, {"rail_seat_left", 2}, {"rail_seat_right", 3}};
  d.mesh_description = "the sleeper mesh";
  d.is_set_up = false;
}

// deal.II reads the file into a serial triangulation (the coarse mesh every process keeps), which
// is checked and then handed to p4est.
void ElasticBody::read_gmsh(const std::string& file_name) {
  Impl& d = *impl_;
  std::ifstream in(file_name);
  if (!in)
    throw InputError(file_name +
                     ": cannot open the mesh file; give the path of an ASCII Gmsh "
                     ".msh file (format 2.2 or 4.1)");
  Triangulation<dim> serial;
  GridIn<dim> grid_in(serial);
  try {
    grid_in.read_msh(in);
  } catch (const std::exception& failure) {
    throw InputError(file_name + ": malformed Gmsh mesh (" + first_reason(failure.what()) +
                     "); valid: an ASCII .msh file, format 2.2 or 4.1, of hexahedra with "
                     "physical groups");
  }
  if (serial.n_active_cells() == 0 || !serial.all_reference_cells_are_hyper_cube())
    throw InputError(file_name +
                     ": the mesh has no hexahedra or has other cell types; valid: "
                     "hexahedra only (in Gmsh: Mesh.RecombineAll = 1 and "
                     "Mesh.SubdivisionAlgorithm = 2)");
  d.triangulation.clear();
  d.triangulation.copy_triangulation(serial);
  d.boundary_names.clear();
  for (const auto& [name, group] : physical_names(file_name))
    if (group.first == dim - 1) d.boundary_names[name] = group.second;
  d.mesh_description = "mesh '" + file_name + "'";
  d.is_set_up = false;
}

void ElasticBody::refine_globally(const unsigned int times) {
  impl_->triangulation.refine_global(times);
  impl_->is_set_up = false;
}

// Faces of every level are marked, so the ids survive the (re)creation of children by p4est.
void ElasticBody::mark_boundary(const std::string& name, const unsigned int boundary_id,
                                const std::function<bool(const Vector3&)>& selects) {
  for (const auto& cell : impl_->triangulation.cell_iterators())
    for (const auto& face : cell->face_iterators())
      if (face->at_boundary() && selects(to_array(face->center())))
        face->set_boundary_id(boundary_id);
  impl_->boundary_names[name] = boundary_id;
  impl_->is_set_up = false;
}

unsigned int ElasticBody::boundary_id(const std::string& name) const {
  const auto found = impl_->boundary_names.find(name);
  if (found != impl_->boundary_names.end()) return found->second;
  std::string known;
  for (const auto& entry : impl_->boundary_names)
    known += (known.empty() ? "'" : ", '") + entry.first + "'";
  throw InputError("fem: " + impl_->mesh_description + " has no boundary named '" + name +
                   "'; boundaries: " + (known.empty() ? "none" : known));
}

}  // namespace trackbed::fem
