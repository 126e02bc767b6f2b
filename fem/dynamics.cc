// Dynamic response: Newmark time stepping with Rayleigh damping and Lysmer absorbing boundaries.
//
//   M a + C v + K u = f(t),   C = alpha M + beta K + C_abs,
// Newmark (Hughes, "The Finite Element Method", 2000, sec. 9.1), average acceleration
// (beta_N = 1/4, gamma_N = 1/2): unconditionally stable and second-order accurate, with no
// numerical damping. With c0 = 1/(beta_N dt^2), c1 = gamma_N/(beta_N dt), c2 = 1/(beta_N dt),
// c3 = 1/(2 beta_N) - 1, c4 = gamma_N/beta_N - 1, c5 = dt (gamma_N/(2 beta_N) - 1):
//   (K + c1 C + c0 M) u_{n+1} = f_{n+1} + M (c0 u_n + c2 v_n + c3 a_n)
//                                       + C (c1 u_n + c4 v_n + c5 a_n),
//   a_{n+1} = c0 (u_{n+1} - u_n) - c2 v_n - c3 a_n,
//   v_{n+1} = v_n + dt ((1 - gamma_N) a_n + gamma_N a_{n+1}).
// The absorbing boundary (Lysmer & Kuhlemeyer, J. Eng. Mech. Div. ASCE 95, 1969) applies the
// traction t = -rho c_p (v.n) n - rho c_s (v - (v.n) n), which absorbs plane P and S waves at
// normal incidence exactly; its matrix is
//   C_abs,ij = int_Gamma rho c_p (phi_i.n)(phi_j.n) + rho c_s (phi_i.phi_j - (phi_i.n)(phi_j.n))
//   ds.
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/base/timer.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/lac/solver_cg.h>
#include <deal.II/lac/solver_control.h>

#include "fem/elastic_body_impl.h"
#include "fem/errors.h"

namespace trackbed::fem {

using namespace dealii;

namespace {
constexpr double newmark_beta = 0.25, newmark_gamma = 0.5;
}

// M_ij = int rho phi_i . phi_j dx; shape functions are primitive, so only equal components pair.
void ElasticBody::Impl::assemble_mass_and_boundary_damping() {
  mass = 0.0;
  boundary_damping = 0.0;
  const QGauss<dim> quadrature(degree + 1);
  const QGauss<dim - 1> face_quadrature(degree + 1);
  FEValues<dim> fe_values(mapping, fe, quadrature, update_values | update_JxW_values);
  FEFaceValues<dim> fe_face_values(mapping, fe, face_quadrature,
                                   update_values | update_normal_vectors | update_JxW_values);
  const unsigned int n = fe.n_dofs_per_cell();
  FullMatrix<double> cell_mass(n, n), cell_damping(n, n);
  std::vector<types::global_dof_index> dof_indices(n);
  for (const auto& cell : dof_handler.active_cell_iterators()) {
    if (!cell->is_locally_owned()) continue;
    const Material& m = material(cell);
    fe_values.reinit(cell);
    cell_mass = 0.0;
    for (unsigned int q = 0; q < quadrature.size(); ++q)
      for (unsigned int i = 0; i < n; ++i)
        for (unsigned int j = 0; j < n; ++j)
          if (fe.system_to_component_index(i).first == fe.system_to_component_index(j).first)
            cell_mass(i, j) += m.density * fe_values.shape_value(i, q) *
                               fe_values.shape_value(j, q) * fe_values.JxW(q);
    cell->get_dof_indices(dof_indices);
    constraints.distribute_local_to_global(cell_mass, dof_indices, mass);

    bool has_absorbing_face = false;
    cell_damping = 0.0;
    for (const auto& face : cell->face_iterators()) {
      if (!face->at_boundary() || absorbing.count(face->boundary_id()) == 0) continue;
      has_absorbing_face = true;
      fe_face_values.reinit(cell, face);
      const double rho_cp = m.density * m.p_wave_speed(), rho_cs = m.density * m.s_wave_speed();
      for (unsigned int q = 0; q < face_quadrature.size(); ++q) {
        const Tensor<1, dim>& normal = fe_face_values.normal_vector(q);
        for (unsigned int i = 0; i < n; ++i) {
          const unsigned int ci = fe.system_to_component_index(i).first;
          for (unsigned int j = 0; j < n; ++j) {
            const unsigned int cj = fe.system_to_component_index(j).first;
            // phi_i = phi_i e_ci: (phi_i.n)(phi_j.n) = phi_i phi_j n_ci n_cj.
            const double nn = normal[ci] * normal[cj];
            const double identity = (ci == cj) ? 1.0 : 0.0;
            cell_damping(i, j) += (rho_cp * nn + rho_cs * (identity - nn)) *
                                  fe_face_values.shape_value(i, q) *
                                  fe_face_values.shape_value(j, q) * fe_face_values.JxW(q);
          }
        }
      }
    }
    if (has_absorbing_face)
      constraints.distribute_local_to_global(cell_damping, dof_indices, boundary_damping);
  }
  mass.compress(VectorOperation::add);
  boundary_damping.compress(VectorOperation::add);
}

void ElasticBody::Impl::apply_damping(const DistributedVector& x, DistributedVector& result) const {
  DistributedVector tmp(x);
  boundary_damping.vmult(result, x);
  mass.vmult(tmp, x);
  result.add(newmark.rayleigh_mass, tmp);
  stiffness.vmult(tmp, x);
  result.add(newmark.rayleigh_stiffness, tmp);
}

SolveReport ElasticBody::start_dynamics(const NewmarkParameters& parameters) {
  Impl& d = *impl_;
  if (!(parameters.time_step > 0.0))
    throw InputError("fem dynamics: 'time step' = " + std::to_string(parameters.time_step) +
                     " s is invalid; valid: > 0");
  if (parameters.rayleigh_mass < 0.0 || parameters.rayleigh_stiffness < 0.0)
    throw InputError(
        "fem dynamics: Rayleigh coefficients alpha = " + std::to_string(parameters.rayleigh_mass) +
        " 1/s, beta = " + std::to_string(parameters.rayleigh_stiffness) +
        " s are invalid; valid: both >= 0");
  for (const auto& condition : d.dirichlet)
    if (condition.value)
      throw InputError("fem dynamics: boundary id " + std::to_string(condition.boundary_id) +
                       " has a non-zero prescribed displacement; dynamic mode supports fixed "
                       "(zero) displacements only");
  if (!d.is_set_up) setup();
  d.check_input();
  d.newmark = parameters;
  SolveReport report;
  Timer timer;
  d.assemble_mass_and_boundary_damping();

  const double dt = parameters.time_step;
  const double c0 = 1.0 / (newmark_beta * dt * dt), c1 = newmark_gamma / (newmark_beta * dt);
  // K_eff = (1 + c1 beta) K + (c0 + c1 alpha) M + c1 C_abs.
  d.effective_matrix.copy_from(d.stiffness);
  d.effective_matrix *= 1.0 + c1 * parameters.rayleigh_stiffness;
  d.effective_matrix.add(c0 + c1 * parameters.rayleigh_mass, d.mass);
  d.effective_matrix.add(c1, d.boundary_damping);
  report.assembly_seconds = timer.wall_time();
  timer.restart();
  d.dynamic_solver.initialize(d.effective_matrix, d.solver_parameters, d.degree > 1,
                              d.owned_support_points, d.owned_components);
  report.preconditioner_seconds = timer.wall_time();

  // Start at rest: v_0 = 0, and M a_0 = f_0 - K u_0 (zero when u_0 is the static equilibrium).
  d.velocity = 0.0;
  DistributedVector residual(d.owned_dofs, d.communicator), ku(residual);
  d.assemble_load(residual);
  d.stiffness.vmult(ku, d.solution);
  residual -= ku;
  d.constraints.set_zero(residual);
  d.acceleration = 0.0;
  if (residual.l2_norm() > 0.0) {
    SolverControl control(d.solver_parameters.max_iterations,
                          d.solver_parameters.relative_tolerance * residual.l2_norm(), false,
                          false);
    SolverCG<DistributedVector> cg(control);
    TrilinosWrappers::PreconditionJacobi jacobi;
    jacobi.initialize(d.mass);
    cg.solve(d.mass, d.acceleration, residual, jacobi);
    d.constraints.set_zero(d.acceleration);
  }
  d.is_dynamic = true;
  d.update_ghosts();
  return report;
}

SolveReport ElasticBody::advance() {
  Impl& d = *impl_;
  if (!d.is_dynamic) throw InputError("fem dynamics: advance() called before start_dynamics()");
  const double dt = d.newmark.time_step;
  const double c0 = 1.0 / (newmark_beta * dt * dt), c1 = newmark_gamma / (newmark_beta * dt),
               c2 = 1.0 / (newmark_beta * dt), c3 = 1.0 / (2.0 * newmark_beta) - 1.0,
               c4 = newmark_gamma / newmark_beta - 1.0,
               c5 = dt * (newmark_gamma / (2.0 * newmark_beta) - 1.0);
  d.time += dt;
  SolveReport report;
  Timer timer;
  DistributedVector rhs(d.owned_dofs, d.communicator), combination(rhs), product(rhs);
  d.assemble_load(rhs);
  // + M (c0 u + c2 v + c3 a)
  combination.equ(c0, d.solution);
  combination.add(c2, d.velocity, c3, d.acceleration);
  d.mass.vmult(product, combination);
  rhs += product;
  // + C (c1 u + c4 v + c5 a)
  combination.equ(c1, d.solution);
  combination.add(c4, d.velocity, c5, d.acceleration);
  d.apply_damping(combination, product);
  rhs += product;
  d.constraints.set_zero(rhs);
  report.assembly_seconds = timer.wall_time();

  DistributedVector new_solution(d.solution);
  d.dynamic_solver.solve(new_solution, rhs, report);
  d.constraints.distribute(new_solution);

  // a_{n+1} = c0 (u_{n+1} - u_n) - c2 v_n - c3 a_n
  DistributedVector new_acceleration(new_solution);
  new_acceleration -= d.solution;
  new_acceleration *= c0;
  new_acceleration.add(-c2, d.velocity, -c3, d.acceleration);
  // v_{n+1} = v_n + dt ((1 - gamma) a_n + gamma a_{n+1})
  d.velocity.add(dt * (1.0 - newmark_gamma), d.acceleration, dt * newmark_gamma, new_acceleration);
  d.acceleration = new_acceleration;
  d.solution = new_solution;
  d.update_ghosts();
  return report;
}

}  // namespace trackbed::fem
