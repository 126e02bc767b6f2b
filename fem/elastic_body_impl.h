// The deal.II side of ElasticBody, shared by the fem/*.cc files only (never installed or included
// by users of the library).
#pragma once

#include <deal.II/base/index_set.h>
#include <deal.II/base/point.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/mapping_q.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/trilinos_precondition.h>
#include <deal.II/lac/trilinos_solver.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/trilinos_vector.h>

#include <Epetra_MultiVector.h>

#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "fem/elastic_body.h"

namespace trackbed::fem {

constexpr int dim = 3;
using CellIterator = dealii::DoFHandler<dim>::active_cell_iterator;
using Matrix = dealii::TrilinosWrappers::SparseMatrix;
using DistributedVector = dealii::TrilinosWrappers::MPI::Vector;

inline dealii::Point<dim> to_point(const Vector3& v) {
  return {v[0], v[1], v[2]};
}
inline Vector3 to_array(const dealii::Point<dim>& p) {
  return {{p[0], p[1], p[2]}};
}
inline Vector3 to_array(const dealii::Tensor<1, dim>& t) {
  return {{t[0], t[1], t[2]}};
}

// Solves systems with one matrix many times: CG preconditioned by ML AMG whose near-null space
// is the six rigid-body modes, or a direct factorisation.
class LinearSolver {
 public:
  // Builds the preconditioner (or factorisation) of `matrix`. `support_points` and `components`
  // describe the locally owned dofs in the order of the matrix rows.
  void initialize(const Matrix& matrix, const SolverParameters& parameters, bool higher_order,
                  const std::vector<dealii::Point<dim>>& support_points,
                  const std::vector<unsigned int>& components);
  // Solves matrix x = b starting from x; throws SolverError if CG does not converge.
  void solve(DistributedVector& x, const DistributedVector& b, SolveReport& report) const;

 private:
  const Matrix* matrix_ = nullptr;
  SolverParameters parameters_;
  std::unique_ptr<Epetra_MultiVector> rigid_body_modes_;
  dealii::TrilinosWrappers::PreconditionAMG amg_;
  std::unique_ptr<dealii::SolverControl> direct_control_;
  std::unique_ptr<dealii::TrilinosWrappers::SolverDirect> direct_;
};

struct DirichletCondition {
  unsigned int boundary_id;
  std::array<bool, 3> components;
  VectorField value;  // empty: zero
};

struct ElasticBody::Impl {
  Impl(unsigned int degree, MPI_Comm communicator);

  // Input checks and setup (elastic_body.cc).
  void check_input() const;
  void setup_dofs();
  void assemble_stiffness();
  // f = int (rho g + f) . phi + int_Gamma_N t . phi + interface load; constrained.
  void assemble_load(DistributedVector& load) const;
  void resolve_tractions();
  void update_ghosts();
  const Material& material(const CellIterator& cell) const;
  // Total area of the boundary faces with an id (collective).
  double boundary_area(unsigned int boundary_id) const;
  // Dynamics (dynamics.cc).
  void assemble_mass_and_boundary_damping();
  // C x = alpha M x + beta K x + C_abs x.
  void apply_damping(const DistributedVector& x, DistributedVector& result) const;

  MPI_Comm communicator;
  unsigned int degree;
  dealii::parallel::distributed::Triangulation<dim> triangulation;
  dealii::FESystem<dim> fe;
  dealii::MappingQ<dim> mapping;
  dealii::DoFHandler<dim> dof_handler;
  std::string mesh_description = "the mesh";  // named in messages, e.g. "mesh 'bed.msh'"

  std::map<unsigned int, Material> materials;
  std::map<std::string, unsigned int> boundary_names;
  Vector3 gravity{{0.0, 0.0, -9.81}};
  VectorField body_force;
  std::vector<DirichletCondition> dirichlet;
  std::map<unsigned int, Vector3> tractions;        // Pa
  std::map<unsigned int, Vector3> boundary_forces;  // N
  std::set<unsigned int> absorbing;
  SolverParameters solver_parameters;

  dealii::IndexSet owned_dofs, relevant_dofs;
  dealii::AffineConstraints<double> constraints;
  bool inhomogeneous_constraints = false;
  std::map<unsigned int, Vector3> resolved_tractions;  // tractions plus forces / area
  std::vector<dealii::Point<dim>> owned_support_points;
  std::vector<unsigned int> owned_components;

  Matrix stiffness, mass, boundary_damping, effective_matrix;
  LinearSolver static_solver, dynamic_solver;
  DistributedVector solution, velocity, acceleration, interface_load;
  DistributedVector ghosted_solution, ghosted_velocity;
  bool is_set_up = false;
  bool static_solver_ready = false;
  bool is_dynamic = false;
  NewmarkParameters newmark;
  double time = 0.0;
};

}  // namespace trackbed::fem
