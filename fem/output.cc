// Results of ElasticBody: point values, error norms, energies, VTU/PVTU and HDF5 files.
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/numerics/data_out.h>
#include <deal.II/numerics/data_postprocessor.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "common/durable_rename.h"
#include "fem/elastic_body_impl.h"
#include "fem/errors.h"

namespace trackbed::fem {

using namespace dealii;

namespace {

// sigma = lambda tr(eps) I + 2 mu eps.
SymmetricTensor<2, dim> stress(const Material& m, const Tensor<2, dim>& displacement_gradient) {
  const SymmetricTensor<2, dim> eps = symmetrize(displacement_gradient);
  return m.lame_lambda() * trace(eps) * unit_symmetric_tensor<dim>() +
         2.0 * m.shear_modulus() * eps;
}

// von Mises equivalent stress sqrt(3/2 s:s), s the deviator of sigma.
double von_mises(const SymmetricTensor<2, dim>& sigma) {
  const SymmetricTensor<2, dim> s = deviator(sigma);
  return std::sqrt(1.5 * (s * s));
}

// Six stress components and the von Mises stress at every output point, from the displacement
// gradient and the material of the cell.
class StressPostprocessor : public DataPostprocessor<dim> {
 public:
  explicit StressPostprocessor(const std::map<unsigned int, Material>& materials)
      : materials_(materials) {}

  void evaluate_vector_field(const DataPostprocessorInputs::Vector<dim>& inputs,
                             std::vector<Vector<double>>& computed) const override {
    const auto cell = inputs.template get_cell<dim>();
    const Material& m = materials_.at(cell->material_id());
    for (unsigned int q = 0; q < inputs.solution_gradients.size(); ++q) {
      Tensor<2, dim> grad;
      for (unsigned int c = 0; c < dim; ++c) grad[c] = inputs.solution_gradients[q][c];
      const SymmetricTensor<2, dim> sigma = stress(m, grad);
      const unsigned int index[6][2] = {{0, 0}, {1, 1}, {2, 2}, {0, 1}, {1, 2}, {0, 2}};
      for (unsigned int k = 0; k < 6; ++k) computed[q](k) = sigma[index[k][0]][index[k][1]];
      computed[q](6) = von_mises(sigma);
    }
  }
  std::vector<std::string> get_names() const override {
    return {"stress_xx", "stress_yy", "stress_zz", "stress_xy",
            "stress_yz", "stress_xz", "von_mises"};
  }
  std::vector<DataComponentInterpretation::DataComponentInterpretation>
  get_data_component_interpretation() const override {
    return std::vector<DataComponentInterpretation::DataComponentInterpretation>(
        7, DataComponentInterpretation::component_is_scalar);
  }
  UpdateFlags get_needed_update_flags() const override { return update_gradients; }

 private:
  const std::map<unsigned int, Material>& materials_;
};

// Files are written under a temporary name and renamed durably, so an interrupted write (or a
// power cut) never leaves a truncated file under the final name.
void commit(const std::string& temporary, const std::string& final_name) {
  if (!durable_rename(temporary, final_name))
    throw InputError(final_name +
                     ": cannot write the output file; check that its directory "
                     "exists and is writable");
}

}  // namespace

// Each process looks for a locally owned cell around each point; the lowest rank that owns one
// evaluates there, and a sum over processes gives every process every value.
std::vector<PointValues> ElasticBody::probe(const std::vector<Vector3>& points) const {
  const Impl& d = *impl_;
  const unsigned int rank = Utilities::MPI::this_mpi_process(d.communicator);
  const unsigned int nobody = Utilities::MPI::n_mpi_processes(d.communicator);
  std::vector<unsigned int> owner(points.size(), nobody);
  std::vector<std::pair<CellIterator, Point<dim>>> found(points.size());
  for (std::size_t k = 0; k < points.size(); ++k) {
    try {
      for (const auto& [cell, unit] : GridTools::find_all_active_cells_around_point(
               d.mapping, d.dof_handler, to_point(points[k]), 1e-10))
        if (cell->is_locally_owned()) {
          owner[k] = rank;
          found[k] = {cell, GeometryInfo<dim>::project_to_unit_cell(unit)};
          break;
        }
    } catch (const std::exception&) {
      // Not in this process's part of the mesh.
    }
  }
  MPI_Allreduce(MPI_IN_PLACE, owner.data(), owner.size(), MPI_UNSIGNED, MPI_MIN, d.communicator);
  std::vector<double> values(points.size() * 15, 0.0);
  const FEValuesExtractors::Vector displacement(0);
  for (std::size_t k = 0; k < points.size(); ++k) {
    if (owner[k] == nobody) {
      std::ostringstream message;
      message << "fem probe: point (" << points[k][0] << ", " << points[k][1] << ", "
              << points[k][2] << ") lies outside " << d.mesh_description
              << "; valid: points inside the body";
      throw InputError(message.str());
    }
    if (owner[k] != rank) continue;
    const auto& [cell, unit] = found[k];
    FEValues<dim> fe_values(d.mapping, d.fe, Quadrature<dim>(unit),
                            update_values | update_gradients);
    fe_values.reinit(cell);
    std::vector<Tensor<1, dim>> u(1), v(1);
    std::vector<Tensor<2, dim>> grad(1);
    fe_values[displacement].get_function_values(d.ghosted_solution, u);
    fe_values[displacement].get_function_values(d.ghosted_velocity, v);
    fe_values[displacement].get_function_gradients(d.ghosted_solution, grad);
    const SymmetricTensor<2, dim> sigma = stress(d.material(cell), grad[0]);
    double* out = &values[15 * k];
    for (unsigned int i = 0; i < dim; ++i) {
      out[i] = u[0][i];
      out[3 + i] = v[0][i];
      for (unsigned int j = 0; j < dim; ++j) out[6 + 3 * i + j] = sigma[i][j];
    }
  }
  MPI_Allreduce(MPI_IN_PLACE, values.data(), values.size(), MPI_DOUBLE, MPI_SUM, d.communicator);
  std::vector<PointValues> result(points.size());
  for (std::size_t k = 0; k < points.size(); ++k)
    for (unsigned int i = 0; i < dim; ++i) {
      result[k].displacement[i] = values[15 * k + i];
      result[k].velocity[i] = values[15 * k + 3 + i];
      for (unsigned int j = 0; j < dim; ++j)
        result[k].stress[i][j] = values[15 * k + 6 + 3 * i + j];
    }
  return result;
}

// ||u_h - u||^2 = int |u_h - u|^2 dx and |u_h - u|_1^2 = int |grad u_h - grad u|^2 dx with a
// Gauss rule of p + 3 points per direction, exact enough not to pollute the rates.
ErrorNorms ElasticBody::error_norms(const VectorField& exact,
                                    const TensorField& exact_gradient) const {
  const Impl& d = *impl_;
  const QGauss<dim> quadrature(d.degree + 3);
  FEValues<dim> fe_values(
      d.mapping, d.fe, quadrature,
      update_values | update_gradients | update_quadrature_points | update_JxW_values);
  const FEValuesExtractors::Vector displacement(0);
  std::vector<Tensor<1, dim>> u(quadrature.size());
  std::vector<Tensor<2, dim>> grad(quadrature.size());
  double l2 = 0.0, h1 = 0.0;
  for (const auto& cell : d.dof_handler.active_cell_iterators()) {
    if (!cell->is_locally_owned()) continue;
    fe_values.reinit(cell);
    fe_values[displacement].get_function_values(d.ghosted_solution, u);
    fe_values[displacement].get_function_gradients(d.ghosted_solution, grad);
    for (unsigned int q = 0; q < quadrature.size(); ++q) {
      const Vector3 x = to_array(fe_values.quadrature_point(q));
      const Vector3 ue = exact(x);
      const Tensor3 ge = exact_gradient(x);
      for (unsigned int i = 0; i < dim; ++i) {
        l2 += std::pow(u[q][i] - ue[i], 2) * fe_values.JxW(q);
        for (unsigned int j = 0; j < dim; ++j)
          h1 += std::pow(grad[q][i][j] - ge[i][j], 2) * fe_values.JxW(q);
      }
    }
  }
  return {std::sqrt(Utilities::MPI::sum(l2, d.communicator)),
          std::sqrt(Utilities::MPI::sum(h1, d.communicator))};
}

Energies ElasticBody::energies() const {
  const Impl& d = *impl_;
  DistributedVector product(d.owned_dofs, d.communicator);
  Energies e;
  d.stiffness.vmult(product, d.solution);
  e.strain = 0.5 * (d.solution * product);
  if (d.is_dynamic) {
    d.mass.vmult(product, d.velocity);
    e.kinetic = 0.5 * (d.velocity * product);
  }
  return e;
}

namespace {

// Displacement, velocity, stress, von Mises, material id and MPI rank on patches of the
// element degree.
void fill(DataOut<dim>& data_out, const ElasticBody::Impl& d,
          const StressPostprocessor& postprocessor, Vector<float>& material_ids,
          Vector<float>& ranks) {
  const std::vector<DataComponentInterpretation::DataComponentInterpretation> vector(
      dim, DataComponentInterpretation::component_is_part_of_vector);
  data_out.attach_dof_handler(d.dof_handler);
  data_out.add_data_vector(d.ghosted_solution, std::vector<std::string>(dim, "displacement"),
                           DataOut<dim>::type_dof_data, vector);
  data_out.add_data_vector(d.ghosted_velocity, std::vector<std::string>(dim, "velocity"),
                           DataOut<dim>::type_dof_data, vector);
  data_out.add_data_vector(d.ghosted_solution, postprocessor);
  material_ids.reinit(d.triangulation.n_active_cells());
  ranks.reinit(d.triangulation.n_active_cells());
  for (const auto& cell : d.triangulation.active_cell_iterators())
    if (cell->is_locally_owned()) {
      material_ids(cell->active_cell_index()) = cell->material_id();
      ranks(cell->active_cell_index()) = cell->subdomain_id();
    }
  data_out.add_data_vector(material_ids, "material_id");
  data_out.add_data_vector(ranks, "mpi_rank");
  data_out.build_patches(d.mapping, d.degree);
}

}  // namespace

std::string ElasticBody::write_vtu(const std::string& directory, const std::string& base,
                                   const unsigned int step) const {
  const Impl& d = *impl_;
  const unsigned int rank = Utilities::MPI::this_mpi_process(d.communicator);
  const unsigned int n_ranks = Utilities::MPI::n_mpi_processes(d.communicator);
  StressPostprocessor postprocessor(d.materials);
  DataOut<dim> data_out;
  Vector<float> material_ids, ranks;
  fill(data_out, d, postprocessor, material_ids, ranks);

  auto piece = [&](unsigned int r) {
    return base + "_" + Utilities::int_to_string(step, 5) + "." + Utilities::int_to_string(r, 4) +
           ".vtu";
  };
  const std::string piece_path = directory + "/" + piece(rank);
  {
    std::ofstream out(piece_path + ".tmp");
    if (!out)
      throw InputError(piece_path + ": cannot write the output file; check that the directory '" +
                       directory + "' exists and is writable");
    data_out.write_vtu(out);
  }
  commit(piece_path + ".tmp", piece_path);
  const std::string record =
      directory + "/" + base + "_" + Utilities::int_to_string(step, 5) + ".pvtu";
  MPI_Barrier(d.communicator);
  if (rank == 0) {
    std::vector<std::string> pieces;
    for (unsigned int r = 0; r < n_ranks; ++r) pieces.push_back(piece(r));
    {
      std::ofstream out(record + ".tmp");
      data_out.write_pvtu_record(out, pieces);
    }
    commit(record + ".tmp", record);
  }
  MPI_Barrier(d.communicator);
  return record;
}

void ElasticBody::write_hdf5(const std::string& file_name, const double time) const {
  const Impl& d = *impl_;
  const unsigned int rank = Utilities::MPI::this_mpi_process(d.communicator);
  StressPostprocessor postprocessor(d.materials);
  DataOut<dim> data_out;
  Vector<float> material_ids, ranks;
  fill(data_out, d, postprocessor, material_ids, ranks);
  // Shared vertices are merged, so "nodes" lists each mesh node once.
  DataOutBase::DataOutFilter filter(DataOutBase::DataOutFilterFlags(true, true));
  data_out.write_filtered_data(filter);
  const std::string temporary = file_name + ".tmp";
  try {
    data_out.write_hdf5_parallel(filter, temporary, d.communicator);
  } catch (const std::exception&) {
    throw InputError(file_name +
                     ": cannot write the HDF5 file; check that its directory exists "
                     "and is writable");
  }
  const std::string h5_name = file_name.substr(file_name.find_last_of('/') + 1);
  const std::string xdmf = file_name.substr(0, file_name.rfind(".h5")) + ".xdmf";
  const std::vector<XDMFEntry> entries{
      data_out.create_xdmf_entry(filter, h5_name, time, d.communicator)};
  data_out.write_xdmf_file(entries, xdmf + ".tmp", d.communicator);
  MPI_Barrier(d.communicator);
  if (rank == 0) {
    commit(temporary, file_name);
    commit(xdmf + ".tmp", xdmf);
  }
  MPI_Barrier(d.communicator);
}

}  // namespace trackbed::fem
