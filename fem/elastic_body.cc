// Setup, assembly and the quasi-static solve of ElasticBody.
//
// The weak form (Hughes, "The Finite Element Method", 2000, ch. 2; deal.II step-8): find u in V
// with u = g on Gamma_D such that for all v
//   int_Omega lambda (div u)(div v) + 2 mu eps(u) : eps(v) dx
//     = int_Omega (rho g + f) . v dx + int_Gamma_N t . v ds + sum_p F_p . v(x_p).
#include <deal.II/base/function.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/base/timer.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/lac/solver_cg.h>
#include <deal.II/lac/solver_control.h>
#include <deal.II/lac/trilinos_sparsity_pattern.h>
#include <deal.II/numerics/vector_tools.h>

#include <Teuchos_ParameterList.hpp>

#include <sstream>

#include "fem/elastic_body_impl.h"
#include "fem/errors.h"

namespace trackbed::fem {

using namespace dealii;

namespace {

// A VectorField as a deal.II Function, for interpolate_boundary_values.
class FieldFunction : public Function<dim> {
 public:
  explicit FieldFunction(const VectorField& field) : Function<dim>(dim), field_(field) {}
  double value(const Point<dim>& p, const unsigned int component) const override {
    return field_(to_array(p))[component];
  }

 private:
  const VectorField& field_;
};

std::string list_ids(const std::set<unsigned int>& ids) {
  std::ostringstream out;
  for (auto id = ids.begin(); id != ids.end(); ++id) out << (id == ids.begin() ? "" : ", ") << *id;
  return ids.empty() ? "none" : out.str();
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// LinearSolver

void LinearSolver::initialize(const Matrix& matrix, const SolverParameters& parameters,
                              const bool higher_order,
                              const std::vector<Point<dim>>& support_points,
                              const std::vector<unsigned int>& components) {
  matrix_ = &matrix;
  parameters_ = parameters;
  if (parameters.method == SolverParameters::Method::direct) {
    direct_control_ = std::make_unique<SolverControl>(1, 0.0);
    direct_ = std::make_unique<TrilinosWrappers::SolverDirect>(*direct_control_);
    direct_->initialize(matrix);
    return;
  }
  // Smoothed aggregation tuned for elliptic systems (Chebyshev smoother), as in deal.II step-31
  // and step-42. The near-null space of elasticity is spanned by the rigid-body modes: the three
  // translations and the three rotations r_k(x) = e_k x (x - x_c) (Vanek, Mandel & Brezina,
  // Computing 56, 1996); giving ML the rotations is what keeps the iteration count independent
  // of the mesh size.
  TrilinosWrappers::PreconditionAMG::AdditionalData data;
  data.elliptic = true;
  data.higher_order_elements = higher_order;
  // Chebyshev of degree 2 and threshold 0.02 took the fewest seconds on a 116k-dof Q1 subgrade
  // (degree 1: 22 iterations, degree 3: slower per iteration; threshold 0.1: 28 iterations;
  // symmetric Gauss-Seidel: 40 % slower; Jacobi: no convergence).
  data.smoother_sweeps = 2;
  data.aggregation_threshold = 0.02;
  Teuchos::ParameterList list;
  std::unique_ptr<Epetra_MultiVector> unused_constant_modes;
  data.set_parameters(list, unused_constant_modes, matrix);

  const Epetra_Map& map = matrix.trilinos_matrix().DomainMap();
  Point<dim> centroid;
  for (const auto& p : support_points) centroid += p;
  const double n_global = Utilities::MPI::sum(static_cast<double>(support_points.size()),
                                              matrix.get_mpi_communicator());
  for (unsigned int d = 0; d < dim; ++d)
    centroid[d] = Utilities::MPI::sum(centroid[d], matrix.get_mpi_communicator()) / n_global;
  rigid_body_modes_ = std::make_unique<Epetra_MultiVector>(map, 6);
  for (unsigned int i = 0; i < support_points.size(); ++i) {
    const Tensor<1, dim> x = support_points[i] - centroid;
    const unsigned int c = components[i];
    (*rigid_body_modes_)[c][i] = 1.0;  // translation along c
    // Rotation about axis k: u = e_k x x, component c of it.
    const double rotation[3][3] = {{0.0, -x[2], x[1]}, {x[2], 0.0, -x[0]}, {-x[1], x[0], 0.0}};
    for (unsigned int k = 0; k < dim; ++k) (*rigid_body_modes_)[3 + k][i] = rotation[k][c];
  }
  list.set("PDE equations", 3);
  list.set("null space: type", "pre-computed");
  list.set("null space: dimension", rigid_body_modes_->NumVectors());
  list.set("null space: vectors", rigid_body_modes_->Values());
  amg_.initialize(matrix, list);
}

void LinearSolver::solve(DistributedVector& x, const DistributedVector& b,
                         SolveReport& report) const {
  Timer timer;
  if (direct_) {
    direct_->solve(x, b);
    report.iterations = 0;
    report.residual = 0.0;
  } else {
    const double b_norm = b.l2_norm();
    if (b_norm == 0.0) {
      x = 0.0;
      report.iterations = 0;
      report.residual = 0.0;
    } else {
      SolverControl control(parameters_.max_iterations, parameters_.relative_tolerance * b_norm,
                            false, false);
      SolverCG<DistributedVector> cg(control);
      try {
        cg.solve(*matrix_, x, b, amg_);
      } catch (const SolverControl::NoConvergence& failure) {
        std::ostringstream message;
        message << "fem solver: CG with AMG did not converge: relative residual "
                << failure.last_residual / b_norm << " after " << failure.last_step
                << " iterations; 'max iterations' = " << parameters_.max_iterations
                << ", 'relative tolerance' = " << parameters_.relative_tolerance
                << "; raise them, or check that the fixed boundaries prevent rigid-body motion";
        throw SolverError(message.str());
      }
      report.iterations = control.last_step();
      report.residual = control.last_value();
    }
  }
  report.solve_seconds = timer.wall_time();
}

// ---------------------------------------------------------------------------------------------
// ElasticBody::Impl

ElasticBody::Impl::Impl(const unsigned int degree_, MPI_Comm communicator_)
    : communicator(communicator_),
      degree(degree_),
      triangulation(communicator_),
      fe(FE_Q<dim>(degree_ == 0 ? 1 : degree_), dim),
      mapping(1),
      dof_handler(triangulation) {
  if (degree_ != 1 && degree_ != 2)
    throw InputError("fem: element degree = " + std::to_string(degree_) +
                     " is not supported; valid: 1 (FE_Q1) or 2 (FE_Q2)");
}

const Material& ElasticBody::Impl::material(const CellIterator& cell) const {
  return materials.at(cell->material_id());
}

// Every material id of the mesh must have a material, and every boundary condition must name a
// boundary id the mesh has. The coarse mesh is known to every process, so these checks need no
// communication and every process throws the same error.
void ElasticBody::Impl::check_input() const {
  if (triangulation.n_levels() == 0)
    throw InputError(
        "fem: no mesh; build one with make_box, make_track_section, make_sleeper or "
        "read_gmsh before setup");
  std::set<unsigned int> material_ids, defined;
  for (const auto& cell : triangulation.cell_iterators_on_level(0))
    material_ids.insert(cell->material_id());
  for (const auto& entry : materials) defined.insert(entry.first);
  for (const unsigned int id : material_ids)
    if (materials.count(id) == 0)
      throw InputError("fem: " + mesh_description + " has cells with material id " +
                       std::to_string(id) +
                       " but no material is defined for it; defined ids: " + list_ids(defined));
  const auto ids = triangulation.get_boundary_ids();
  const std::set<unsigned int> boundary_ids(ids.begin(), ids.end());
  auto check = [&](const unsigned int id, const std::string& what) {
    if (boundary_ids.count(id) == 0)
      throw InputError("fem: " + what + " is applied on boundary id " + std::to_string(id) +
                       " which " + mesh_description +
                       " does not have; boundary ids: " + list_ids(boundary_ids));
  };
  for (const auto& condition : dirichlet) check(condition.boundary_id, "a fixed displacement");
  for (const auto& entry : tractions) check(entry.first, "a traction");
  for (const auto& entry : boundary_forces) check(entry.first, "a boundary force");
  for (const unsigned int id : absorbing) check(id, "an absorbing boundary");
}

void ElasticBody::Impl::setup_dofs() {
  dof_handler.distribute_dofs(fe);
  owned_dofs = dof_handler.locally_owned_dofs();
  DoFTools::extract_locally_relevant_dofs(dof_handler, relevant_dofs);

  constraints.clear();
  constraints.reinit(relevant_dofs);
  DoFTools::make_hanging_node_constraints(dof_handler, constraints);
  inhomogeneous_constraints = false;
  for (const auto& condition : dirichlet) {
    const ComponentMask mask(
        std::vector<bool>(condition.components.begin(), condition.components.end()));
    if (condition.value) {
      VectorTools::interpolate_boundary_values(mapping, dof_handler, condition.boundary_id,
                                               FieldFunction(condition.value), constraints, mask);
      inhomogeneous_constraints = true;
    } else {
      VectorTools::interpolate_boundary_values(mapping, dof_handler, condition.boundary_id,
                                               Functions::ZeroFunction<dim>(dim), constraints,
                                               mask);
    }
  }
  constraints.close();

  TrilinosWrappers::SparsityPattern sparsity(owned_dofs, owned_dofs, relevant_dofs, communicator);
  DoFTools::make_sparsity_pattern(dof_handler, sparsity, constraints, false,
                                  Utilities::MPI::this_mpi_process(communicator));
  sparsity.compress();
  stiffness.reinit(sparsity);
  mass.reinit(sparsity);
  boundary_damping.reinit(sparsity);
  effective_matrix.reinit(sparsity);

  for (DistributedVector* v : {&solution, &velocity, &acceleration, &interface_load})
    v->reinit(owned_dofs, communicator);
  ghosted_solution.reinit(owned_dofs, relevant_dofs, communicator);
  ghosted_velocity.reinit(owned_dofs, relevant_dofs, communicator);

  // Position and component of every locally owned dof: the rigid-body modes and load moments.
  owned_support_points.assign(owned_dofs.n_elements(), Point<dim>());
  owned_components.assign(owned_dofs.n_elements(), 0);
  FEValues<dim> fe_values(mapping, fe, Quadrature<dim>(fe.get_unit_support_points()),
                          update_quadrature_points);
  std::vector<types::global_dof_index> dof_indices(fe.n_dofs_per_cell());
  for (const auto& cell : dof_handler.active_cell_iterators()) {
    if (!cell->is_locally_owned()) continue;
    fe_values.reinit(cell);
    cell->get_dof_indices(dof_indices);
    for (unsigned int i = 0; i < fe.n_dofs_per_cell(); ++i)
      if (owned_dofs.is_element(dof_indices[i])) {
        const auto local = owned_dofs.index_within_set(dof_indices[i]);
        owned_support_points[local] = fe_values.quadrature_point(i);
        owned_components[local] = fe.system_to_component_index(i).first;
      }
  }
}

// K_ij = int lambda (div phi_i)(div phi_j) + 2 mu eps(phi_i) : eps(phi_j) dx, per cell with the
// cell's material, condensed with the constraints (hanging nodes and Dirichlet rows).
void ElasticBody::Impl::assemble_stiffness() {
  const QGauss<dim> quadrature(degree + 1);
  FEValues<dim> fe_values(mapping, fe, quadrature, update_gradients | update_JxW_values);
  const FEValuesExtractors::Vector displacement(0);
  const unsigned int n = fe.n_dofs_per_cell();
  FullMatrix<double> cell_matrix(n, n);
  std::vector<types::global_dof_index> dof_indices(n);
  std::vector<SymmetricTensor<2, dim>> eps(n);
  std::vector<double> div(n);
  for (const auto& cell : dof_handler.active_cell_iterators()) {
    if (!cell->is_locally_owned()) continue;
    fe_values.reinit(cell);
    const double lambda = material(cell).lame_lambda();
    const double mu = material(cell).shear_modulus();
    cell_matrix = 0.0;
    for (unsigned int q = 0; q < quadrature.size(); ++q) {
      for (unsigned int i = 0; i < n; ++i) {
        eps[i] = fe_values[displacement].symmetric_gradient(i, q);
        div[i] = trace(eps[i]);
      }
      const double dx = fe_values.JxW(q);
      for (unsigned int i = 0; i < n; ++i)
        for (unsigned int j = 0; j <= i; ++j)
          cell_matrix(i, j) += (lambda * div[i] * div[j] + 2.0 * mu * (eps[i] * eps[j])) * dx;
    }
    for (unsigned int i = 0; i < n; ++i)
      for (unsigned int j = i + 1; j < n; ++j) cell_matrix(i, j) = cell_matrix(j, i);
    cell->get_dof_indices(dof_indices);
    constraints.distribute_local_to_global(cell_matrix, dof_indices, stiffness);
  }
  stiffness.compress(VectorOperation::add);
}

double ElasticBody::Impl::boundary_area(const unsigned int boundary_id) const {
  const QGauss<dim - 1> face_quadrature(degree + 1);
  FEFaceValues<dim> fe_face_values(mapping, fe, face_quadrature, update_JxW_values);
  double area = 0.0;
  for (const auto& cell : dof_handler.active_cell_iterators())
    if (cell->is_locally_owned())
      for (const auto& face : cell->face_iterators())
        if (face->at_boundary() && face->boundary_id() == boundary_id) {
          fe_face_values.reinit(cell, face);
          for (unsigned int q = 0; q < face_quadrature.size(); ++q) area += fe_face_values.JxW(q);
        }
  return Utilities::MPI::sum(area, communicator);
}

// f_i = int (rho g + f) . phi_i dx + int_Gamma_N t . phi_i ds, plus the interface point loads.
// With prescribed non-zero displacements the cell matrix is needed too: condensing it moves
// -K_ij g_j to the right-hand side.
void ElasticBody::Impl::assemble_load(DistributedVector& load) const {
  load = 0.0;
  const QGauss<dim> quadrature(degree + 1);
  const QGauss<dim - 1> face_quadrature(degree + 1);
  FEValues<dim> fe_values(
      mapping, fe, quadrature,
      update_values | update_gradients | update_quadrature_points | update_JxW_values);
  FEFaceValues<dim> fe_face_values(mapping, fe, face_quadrature, update_values | update_JxW_values);
  const FEValuesExtractors::Vector displacement(0);
  const unsigned int n = fe.n_dofs_per_cell();
  Vector<double> cell_load(n);
  FullMatrix<double> cell_matrix(n, n);
  std::vector<types::global_dof_index> dof_indices(n);
  for (const auto& cell : dof_handler.active_cell_iterators()) {
    if (!cell->is_locally_owned()) continue;
    fe_values.reinit(cell);
    const Material& m = material(cell);
    cell_load = 0.0;
    for (unsigned int q = 0; q < quadrature.size(); ++q) {
      Tensor<1, dim> f;
      for (unsigned int d = 0; d < dim; ++d) f[d] = m.density * gravity[d];
      if (body_force) {
        const Vector3 extra = body_force(to_array(fe_values.quadrature_point(q)));
        for (unsigned int d = 0; d < dim; ++d) f[d] += extra[d];
      }
      for (unsigned int i = 0; i < n; ++i) {
        const unsigned int c = fe.system_to_component_index(i).first;
        cell_load(i) += f[c] * fe_values.shape_value(i, q) * fe_values.JxW(q);
      }
    }
    for (const auto& face : cell->face_iterators()) {
      if (!face->at_boundary()) continue;
      const auto traction = resolved_tractions.find(face->boundary_id());
      if (traction == resolved_tractions.end()) continue;
      fe_face_values.reinit(cell, face);
      for (unsigned int q = 0; q < face_quadrature.size(); ++q)
        for (unsigned int i = 0; i < n; ++i) {
          const unsigned int c = fe.system_to_component_index(i).first;
          cell_load(i) +=
              traction->second[c] * fe_face_values.shape_value(i, q) * fe_face_values.JxW(q);
        }
    }
    cell->get_dof_indices(dof_indices);
    if (inhomogeneous_constraints) {
      cell_matrix = 0.0;
      const double lambda = m.lame_lambda(), mu = m.shear_modulus();
      for (unsigned int q = 0; q < quadrature.size(); ++q)
        for (unsigned int i = 0; i < n; ++i) {
          const auto eps_i = fe_values[displacement].symmetric_gradient(i, q);
          for (unsigned int j = 0; j < n; ++j) {
            const auto eps_j = fe_values[displacement].symmetric_gradient(j, q);
            cell_matrix(i, j) +=
                (lambda * trace(eps_i) * trace(eps_j) + 2.0 * mu * (eps_i * eps_j)) *
                fe_values.JxW(q);
          }
        }
      constraints.distribute_local_to_global(cell_load, dof_indices, load, cell_matrix);
    } else {
      constraints.distribute_local_to_global(cell_load, dof_indices, load);
    }
  }
  load.compress(VectorOperation::add);
  // The interface load is already consistent; only the constrained rows must be dropped.
  DistributedVector interface_part(interface_load);
  constraints.set_zero(interface_part);
  load += interface_part;
}

// The traction of each Neumann boundary: the given traction plus a boundary force spread
// uniformly over the boundary's area.
void ElasticBody::Impl::resolve_tractions() {
  check_input();
  resolved_tractions = tractions;
  for (const auto& [id, force] : boundary_forces) {
    const double area = boundary_area(id);
    Vector3& t = resolved_tractions[id];
    for (unsigned int c = 0; c < dim; ++c) t[c] += force[c] / area;
  }
}

void ElasticBody::Impl::update_ghosts() {
  ghosted_solution = solution;
  ghosted_velocity = velocity;
}

// ---------------------------------------------------------------------------------------------
// ElasticBody

ElasticBody::ElasticBody(const unsigned int degree, MPI_Comm communicator)
    : impl_(std::make_unique<Impl>(degree, communicator)) {}

ElasticBody::~ElasticBody() = default;

void ElasticBody::set_material(const unsigned int material_id, const Material& material) {
  material.validate("material id " + std::to_string(material_id));
  impl_->materials[material_id] = material;
  impl_->is_set_up = false;
}

void ElasticBody::set_gravity(const Vector3& acceleration) {
  impl_->gravity = acceleration;
}

void ElasticBody::set_body_force(const VectorField& force_density) {
  impl_->body_force = force_density;
}

void ElasticBody::fix(const unsigned int boundary_id, const std::array<bool, 3> components,
                      const VectorField& value) {
  impl_->dirichlet.push_back({boundary_id, components, value});
  impl_->is_set_up = false;
}

// Loads may change between solves without a new setup: only the load vector depends on them.
void ElasticBody::set_traction(const unsigned int boundary_id, const Vector3& traction) {
  impl_->tractions[boundary_id] = traction;
  if (impl_->is_set_up) impl_->resolve_tractions();
}

void ElasticBody::set_boundary_force(const unsigned int boundary_id, const Vector3& force) {
  impl_->boundary_forces[boundary_id] = force;
  if (impl_->is_set_up) impl_->resolve_tractions();
}

// Absorbing boundaries enter only the damping matrix, assembled by start_dynamics.
void ElasticBody::set_absorbing(const unsigned int boundary_id) {
  impl_->absorbing.insert(boundary_id);
}

void ElasticBody::set_solver(const SolverParameters& parameters) {
  if (!(parameters.relative_tolerance > 0.0 && parameters.relative_tolerance < 1.0))
    throw InputError(
        "fem solver: 'relative tolerance' = " + std::to_string(parameters.relative_tolerance) +
        " is invalid; valid: 0 < tolerance < 1");
  if (parameters.max_iterations == 0)
    throw InputError("fem solver: 'max iterations' = 0 is invalid; valid: >= 1");
  impl_->solver_parameters = parameters;
  impl_->is_set_up = false;
}

SolveReport ElasticBody::setup() {
  Impl& d = *impl_;
  d.check_input();
  SolveReport report;
  Timer timer;
  d.setup_dofs();
  d.resolve_tractions();
  d.assemble_stiffness();
  report.assembly_seconds = timer.wall_time();
  d.static_solver_ready = false;
  d.is_set_up = true;
  d.is_dynamic = false;
  d.time = 0.0;
  d.update_ghosts();
  return report;
}

SolveReport ElasticBody::solve_static() {
  Impl& d = *impl_;
  if (!d.is_set_up) setup();
  SolveReport report;
  Timer timer;
  // The preconditioner is built on the first solve after setup and reused until the next setup.
  if (!d.static_solver_ready) {
    d.static_solver.initialize(d.stiffness, d.solver_parameters, d.degree > 1,
                               d.owned_support_points, d.owned_components);
    d.static_solver_ready = true;
    report.preconditioner_seconds = timer.wall_time();
    timer.restart();
  }
  DistributedVector load(d.owned_dofs, d.communicator);
  d.assemble_load(load);
  report.assembly_seconds = timer.wall_time();
  d.static_solver.solve(d.solution, load, report);
  d.constraints.distribute(d.solution);
  d.velocity = 0.0;
  d.update_ghosts();
  return report;
}

std::vector<double> ElasticBody::displacement_dofs() const {
  const Impl& d = *impl_;
  // Each dof has one owner and zeros elsewhere, so the sum over processes is exact.
  std::vector<double> values(d.dof_handler.n_dofs(), 0.0), all(values.size());
  for (const auto i : d.owned_dofs) values[i] = d.solution[i];
  MPI_Allreduce(values.data(), all.data(), static_cast<int>(values.size()), MPI_DOUBLE, MPI_SUM,
                d.communicator);
  return all;
}

void ElasticBody::set_displacement_dofs(const std::vector<double>& values) {
  Impl& d = *impl_;
  if (!d.is_set_up) setup();
  if (values.size() != d.dof_handler.n_dofs())
    throw InputError(d.mesh_description + ": " + std::to_string(values.size()) +
                     " displacement values for " + std::to_string(d.dof_handler.n_dofs()) +
                     " degrees of freedom; valid: the state of the same mesh and degree");
  for (const auto i : d.owned_dofs) d.solution[i] = values[i];
  d.solution.compress(VectorOperation::insert);
  d.velocity = 0.0;
  d.update_ghosts();
}

double ElasticBody::time() const {
  return impl_->time;
}

std::uint64_t ElasticBody::n_dofs() const {
  return impl_->dof_handler.n_dofs();
}

std::uint64_t ElasticBody::n_cells() const {
  return impl_->triangulation.n_global_active_cells();
}

}  // namespace trackbed::fem
