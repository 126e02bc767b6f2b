// An elastic continuum body: the subgrade layers under the ballast, or the elastic sleeper.
//
// 3-D small-strain linear elasticity, div sigma + rho g + f = rho u'' (u'' = 0 in quasi-static
// mode), sigma = lambda tr(eps) I + 2 mu eps, eps = (grad u + grad u^T) / 2, on a
// parallel::distributed::Triangulation with FE_Q elements of degree 1 or 2. The deal.II objects
// live behind a pointer so that this header, which the coupling includes, needs only the standard
// library and MPI. See docs/fem.md for the equations and their sources.
//
// Use:
//   ElasticBody body(2, MPI_COMM_WORLD);
//   body.make_track_section(section, h);      // or make_box, make_sleeper, read_gmsh
//   body.set_material(track_section::subgrade_id, subgrade_fill());   // every id in the mesh
//   body.fix(body.boundary_id("bottom"));
//   body.setup();                            // dofs, stiffness matrix, AMG: once per mesh
//   body.solve_static();                     // once per load change
#pragma once

#include <mpi.h>

#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "fem/geometry.h"
#include "fem/material.h"

namespace trackbed::fem {

using Tensor3 = std::array<std::array<double, 3>, 3>;
using VectorField = std::function<Vector3(const Vector3&)>;
using TensorField = std::function<Tensor3(const Vector3&)>;  // [i][j] = d u_i / d x_j

struct SolverParameters {
  enum class Method { cg_amg, direct };
  // cg_amg: conjugate gradients preconditioned by Trilinos ML smoothed-aggregation AMG with the six
  // rigid-body modes as near-null space. direct: Amesos KLU, for small problems.
  Method method = Method::cg_amg;
  double relative_tolerance = 1e-8;  // ||r|| <= tol ||b||
  unsigned int max_iterations = 1000;
};

// Newmark's average-acceleration method (beta = 1/4, gamma = 1/2: unconditionally stable, no
// numerical damping) with Rayleigh damping C = alpha M + beta K.
struct NewmarkParameters {
  double time_step = 1e-4;          // s
  double rayleigh_mass = 0.0;       // alpha, 1/s
  double rayleigh_stiffness = 0.0;  // beta, s
};

struct SolveReport {
  unsigned int iterations = 0;          // CG iterations (0 for the direct solver)
  double residual = 0.0;                // final residual norm (0 for the direct solver)
  double assembly_seconds = 0.0;        // matrices (setup) or load vector (solve)
  double preconditioner_seconds = 0.0;  // AMG setup or direct factorisation
  double solve_seconds = 0.0;
};

struct PointValues {
  Vector3 displacement{};  // m
  Vector3 velocity{};      // m/s (zero in quasi-static mode)
  Tensor3 stress{};        // Pa, tension positive
};

struct ErrorNorms {
  double l2 = 0.0;  // ||u_h - u||_L2, m * m^(3/2)
  double h1 = 0.0;  // |u_h - u|_H1 (semi-norm)
};

// Sum of a load vector: force and moment about a reference point.
struct LoadResultant {
  Vector3 force{};   // N
  Vector3 moment{};  // N m
};

struct Energies {
  double kinetic = 0.0;  // v^T M v / 2, J
  double strain = 0.0;   // u^T K u / 2, J
};

class ElasticBody {
 public:
  // degree: 1 or 2. Every process of `communicator` takes part in every call below.
  ElasticBody(unsigned int degree, MPI_Comm communicator);
  ~ElasticBody();
  ElasticBody(const ElasticBody&) = delete;
  ElasticBody& operator=(const ElasticBody&) = delete;

  // --- Geometry (one of these, then optionally refine_globally and mark_boundary) ---
  void make_box(const BoxGeometry& box);
  // The continuum tier of `section` (its layers below the formation z = 0), coarse cells of about
  // element_size m (twice that outside the embankment).
  void make_track_section(const TrackSection& section, double element_size);
  void make_sleeper(const SleeperGeometry& sleeper);
  // An ASCII Gmsh mesh (format 2.2 or 4.1) of hexahedra: volume physical groups become material
  // ids, surface physical groups boundary ids, and their names boundary names.
  void read_gmsh(const std::string& file_name);
  void refine_globally(unsigned int times);
  // Gives the boundary faces whose centre satisfies `selects` the id `boundary_id`, named `name`.
  void mark_boundary(const std::string& name, unsigned int boundary_id,
                     const std::function<bool(const Vector3& face_centre)>& selects);
  // The id of a named boundary; throws InputError listing the names that exist.
  unsigned int boundary_id(const std::string& name) const;

  // --- Materials, boundary conditions and loads ---
  void set_material(unsigned int material_id, const Material& material);
  void set_gravity(const Vector3& acceleration);          // m/s^2, default (0, 0, -9.81)
  void set_body_force(const VectorField& force_density);  // N/m^3, in addition to gravity
  // Prescribes the selected displacement components on a boundary: zero, or `value(x)`.
  void fix(unsigned int boundary_id, std::array<bool, 3> components = {{true, true, true}},
           const VectorField& value = {});
  void set_traction(unsigned int boundary_id, const Vector3& traction);  // Pa
  // A uniform traction whose resultant over the boundary is `force` (N).
  void set_boundary_force(unsigned int boundary_id, const Vector3& force);
  // Lysmer-Kuhlemeyer viscous boundary: traction -rho c_p (v.n) n - rho c_s (v - (v.n) n).
  void set_absorbing(unsigned int boundary_id);
  void set_solver(const SolverParameters& parameters);

  // --- Algorithm ---
  // Checks the input, distributes dofs and assembles the stiffness matrix (the displacement is
  // zero after it). Call again after changing mesh, materials or fixed boundaries.
  SolveReport setup();
  // Quasi-static: solves K u = f for the current loads. The first solve after setup builds the
  // AMG preconditioner (or the direct factorisation); later solves reuse matrix and
  // preconditioner and start from the previous displacement.
  SolveReport solve_static();
  // Dynamic: starts Newmark time stepping from the current displacement at rest; assembles the
  // mass, damping and effective matrices and the preconditioner of the effective matrix.
  SolveReport start_dynamics(const NewmarkParameters& parameters);
  // One Newmark step with the current loads (read at the new time).
  SolveReport advance();
  double time() const;

  // --- Results (collective) ---
  // Values at points inside the body; throws InputError for a point outside.
  std::vector<PointValues> probe(const std::vector<Vector3>& points) const;
  ErrorNorms error_norms(const VectorField& exact, const TensorField& exact_gradient) const;
  Energies energies() const;
  // Force and moment about `reference` of the loads added by BoundaryInterface::add_forces.
  LoadResultant interface_load_resultant(const Vector3& reference) const;
  std::uint64_t n_dofs() const;
  // The displacement in global dof order, the same on every process: the state a checkpoint keeps
  // (a later solve starts from it). Collective.
  std::vector<double> displacement_dofs() const;
  // Restores displacement_dofs() of a body built and set up alike (velocity zero). Collective.
  // Throws InputError for a count that is not n_dofs().
  void set_displacement_dofs(const std::vector<double>& values);
  std::uint64_t n_cells() const;
  // VTU pieces and a PVTU record "<directory>/<base>_<step>.pvtu" with displacement, velocity,
  // stress components, von Mises stress, material id and MPI rank; returns the record's path.
  std::string write_vtu(const std::string& directory, const std::string& base,
                        unsigned int step) const;
  // The same fields in one HDF5 file (datasets "nodes", "cells", one per field) plus an XDMF
  // description "<file without .h5>.xdmf" for ParaView.
  void write_hdf5(const std::string& file_name, double time) const;

  // The deal.II objects (fem/elastic_body_impl.h), for the library's own translation units.
  struct Impl;
  Impl& impl() { return *impl_; }
  const Impl& impl() const { return *impl_; }

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace trackbed::fem
