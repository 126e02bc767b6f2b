// The coupling surface: boundary faces as triangles, consistent point loads, boundary motion.
#include "fem/boundary_interface.h"

#include <deal.II/base/qprojector.h>
#include <deal.II/base/quadrature.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/fe_values.h>

#include "fem/elastic_body_impl.h"
#include "fem/errors.h"

namespace trackbed::fem {

using namespace dealii;

struct BoundaryInterface::Data {
  std::vector<InterfaceTriangle> triangles;
  std::vector<CellIterator> cells;  // owning cell of each triangle
};

BoundaryInterface::BoundaryInterface(ElasticBody& body, const std::string& boundary_name)
    : body_(body), data_(std::make_unique<Data>()) {
  const ElasticBody::Impl& d = body.impl();
  const unsigned int id = body.boundary_id(boundary_name);
  if (!d.is_set_up)
    throw InputError(
        "fem interface '" + boundary_name +
        "': the body must be set up (ElasticBody::setup) before its interface is made");
  // A (p+1) x (p+1) grid of the face's support points, in face coordinates.
  const unsigned int p = d.degree;
  std::vector<Point<dim - 1>> grid;
  for (unsigned int j = 0; j <= p; ++j)
    for (unsigned int i = 0; i <= p; ++i) grid.emplace_back(double(i) / p, double(j) / p);
  const Quadrature<dim - 1> face_grid(grid);
  for (const auto& cell : d.dof_handler.active_cell_iterators()) {
    if (!cell->is_locally_owned()) continue;
    for (const unsigned int f : cell->face_indices()) {
      if (!cell->face(f)->at_boundary() || cell->face(f)->boundary_id() != id) continue;
      const Quadrature<dim> on_face =
          QProjector<dim>::project_to_face(ReferenceCells::Hexahedron, face_grid, f);
      auto corner = [&](unsigned int i, unsigned int j) { return on_face.point(j * (p + 1) + i); };
      const Point<dim> cell_centre = cell->center();
      for (unsigned int j = 0; j < p; ++j)
        for (unsigned int i = 0; i < p; ++i) {
          const std::array<std::array<Point<dim>, 3>, 2> halves{
              {{{corner(i, j), corner(i + 1, j), corner(i + 1, j + 1)}},
               {{corner(i, j), corner(i + 1, j + 1), corner(i, j + 1)}}}};
          for (auto unit : halves) {
            std::array<Point<dim>, 3> real;
            for (unsigned int k = 0; k < 3; ++k)
              real[k] = d.mapping.transform_unit_to_real_cell(cell, unit[k]);
            Tensor<1, dim> normal = cross_product_3d(real[1] - real[0], real[2] - real[0]);
            // Order the corners counter-clockwise seen from outside the body.
            if (normal * (real[0] - cell_centre) < 0.0) {
              std::swap(unit[1], unit[2]);
              std::swap(real[1], real[2]);
              normal = -normal;
            }
            InterfaceTriangle triangle;
            for (unsigned int k = 0; k < 3; ++k) {
              triangle.vertices[k] = to_array(real[k]);
              triangle.unit_cell_points[k] = to_array(unit[k]);
            }
            triangle.cell_id = cell->id().to_string();
            triangle.face_no = f;
            triangle.area = 0.5 * normal.norm();
            triangle.normal = to_array(normal / normal.norm());
            data_->triangles.push_back(triangle);
            data_->cells.push_back(cell);
          }
        }
    }
  }
}

BoundaryInterface::~BoundaryInterface() = default;

const std::vector<InterfaceTriangle>& BoundaryInterface::triangles() const {
  return data_->triangles;
}

const InterfaceTriangle& BoundaryInterface::triangle(const TrianglePoint& point) const {
  if (point.triangle >= data_->triangles.size())
    throw InputError("fem interface: triangle index " + std::to_string(point.triangle) +
                     " is out of range; valid: 0 to " +
                     std::to_string(static_cast<long>(data_->triangles.size()) - 1) +
                     " (this process's triangles)");
  return data_->triangles[point.triangle];
}

Vector3 BoundaryInterface::position(const TrianglePoint& point) const {
  const InterfaceTriangle& t = triangle(point);
  Vector3 x{};
  for (unsigned int k = 0; k < 3; ++k)
    for (unsigned int c = 0; c < dim; ++c) x[c] += point.barycentric[k] * t.vertices[k][c];
  return x;
}

std::vector<ShapeWeight> BoundaryInterface::shape_weights(const TrianglePoint& point) const {
  const ElasticBody::Impl& d = body_.impl();
  const InterfaceTriangle& t = triangle(point);
  Point<dim> unit;
  for (unsigned int k = 0; k < 3; ++k)
    unit += point.barycentric[k] * to_point(t.unit_cell_points[k]);
  std::vector<types::global_dof_index> dofs(d.fe.n_dofs_per_cell());
  data_->cells[point.triangle]->get_dof_indices(dofs);
  std::vector<ShapeWeight> weights;
  for (unsigned int i = 0; i < d.fe.n_dofs_per_cell(); ++i) {
    const double phi = d.fe.shape_value(i, unit);
    // Shape functions of nodes off the face vanish there; round-off is dropped.
    if (std::abs(phi) > 1e-14)
      weights.push_back({dofs[i], d.fe.system_to_component_index(i).first, phi});
  }
  return weights;
}

void BoundaryInterface::add_forces(const std::vector<PointForce>& forces) {
  ElasticBody::Impl& d = body_.impl();
  for (const PointForce& force : forces)
    for (const ShapeWeight& w : shape_weights(force.where))
      d.interface_load(w.dof) += w.weight * force.force[w.component];
  d.interface_load.compress(VectorOperation::add);
}

void BoundaryInterface::clear_forces() {
  body_.impl().interface_load = 0.0;
}

std::vector<std::array<Vector3, 2>> BoundaryInterface::motion(
    const std::vector<TrianglePoint>& points) const {
  const ElasticBody::Impl& d = body_.impl();
  std::vector<std::array<Vector3, 2>> result;
  for (const TrianglePoint& point : points) {
    std::array<Vector3, 2> motion{};
    for (const ShapeWeight& w : shape_weights(point)) {
      motion[0][w.component] += w.weight * d.ghosted_solution(w.dof);
      motion[1][w.component] += w.weight * d.ghosted_velocity(w.dof);
    }
    result.push_back(motion);
  }
  return result;
}

// Sum over the locally owned dofs of f_i e_ci and (x_i - x_ref) x f_i e_ci, then over processes.
LoadResultant ElasticBody::interface_load_resultant(const Vector3& reference) const {
  const Impl& d = *impl_;
  Tensor<1, dim> force, moment;
  for (unsigned int local = 0; local < d.owned_support_points.size(); ++local) {
    Tensor<1, dim> f;
    f[d.owned_components[local]] = d.interface_load(d.owned_dofs.nth_index_in_set(local));
    force += f;
    moment += cross_product_3d(d.owned_support_points[local] - to_point(reference), f);
  }
  LoadResultant result;
  for (unsigned int c = 0; c < dim; ++c) {
    result.force[c] = Utilities::MPI::sum(force[c], d.communicator);
    result.moment[c] = Utilities::MPI::sum(moment[c], d.communicator);
  }
  return result;
}

}  // namespace trackbed::fem
