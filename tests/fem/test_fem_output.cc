// Output files: the PVTU record and its pieces, and the HDF5 file, whose node coordinates and
// displacements must reproduce the exact solution of a uniaxial column.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <unistd.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "fem/elastic_body.h"

namespace trackbed::fem {
namespace {

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

std::vector<double> read_dataset(hid_t file, const char* name, hsize_t& rows, hsize_t& columns) {
  const hid_t dataset = H5Dopen2(file, name, H5P_DEFAULT);
  EXPECT_GE(dataset, 0) << "no dataset " << name;
  const hid_t space = H5Dget_space(dataset);
  hsize_t dims[2] = {0, 1};
  const int rank = H5Sget_simple_extent_dims(space, dims, nullptr);
  rows = dims[0];
  columns = rank > 1 ? dims[1] : 1;
  std::vector<double> data(rows * columns);
  H5Dread(dataset, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data());
  H5Sclose(space);
  H5Dclose(dataset);
  return data;
}

// Free column under a top pressure p (see test_fem_static): u = (nu p x, nu p y, -p z) / E.
class FemOutput : public ::testing::Test {
 protected:
  void SetUp() override {
    body_.make_box({{{0, 0, 0}}, {{1, 1, 2}}, {{2, 2, 4}}, {}});
    body_.set_material(0, material_);
    body_.set_gravity({{0, 0, 0}});
    body_.fix(body_.boundary_id("xmin"), {{true, false, false}});
    body_.fix(body_.boundary_id("ymin"), {{false, true, false}});
    body_.fix(body_.boundary_id("zmin"), {{false, false, true}});
    body_.set_traction(body_.boundary_id("zmax"), {{0, 0, -p_}});
    SolverParameters solver;
    solver.relative_tolerance = 1e-12;
    body_.set_solver(solver);
    body_.setup();
    body_.solve_static();
  }
  Vector3 exact(double x, double y, double z) const {
    const double e = material_.youngs_modulus, nu = material_.poisson_ratio;
    return {{nu * p_ * x / e, nu * p_ * y / e, -p_ * z / e}};
  }
  const Material material_{"soil", 80e6, 0.3, 1900};
  const double p_ = 1e5;
  ElasticBody body_{2, MPI_COMM_WORLD};
  const std::string directory_ = ::testing::TempDir();
  const std::string base_ = "column_" + std::to_string(getpid());
};

TEST_F(FemOutput, PvtuRecordNamesItsPiecesAndFields) {
  const std::string record = body_.write_vtu(directory_, base_, 3);
  EXPECT_EQ(record, directory_ + "/" + base_ + "_00003.pvtu");
  const std::string text = read_text(record);
  for (const char* field : {"displacement", "velocity", "stress_zz", "von_mises", "material_id",
                            "mpi_rank", base_.c_str()})
    EXPECT_NE(text.find(field), std::string::npos) << field;
  const std::string piece = directory_ + "/" + base_ + "_00003.0000.vtu";
  EXPECT_NE(read_text(piece).find("<UnstructuredGrid>"), std::string::npos);
  EXPECT_FALSE(std::ifstream(piece + ".tmp").good());
  std::remove(record.c_str());
  std::remove(piece.c_str());
}

// Every node of the HDF5 file carries the exact displacement (linear field, exact for Q2).
// deal.II's DataOut stores single precision, so the tolerance is 1e-6 relative (float epsilon
// 6e-8, on both coordinates and values).
TEST_F(FemOutput, Hdf5HoldsNodesAndDisplacements) {
  const std::string file = directory_ + "/" + base_ + ".h5";
  body_.write_hdf5(file, 0.5);
  const hid_t h5 = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(h5, 0);
  hsize_t n_nodes = 0, dim = 0, n_values = 0, components = 0;
  const auto nodes = read_dataset(h5, "nodes", n_nodes, dim);
  const auto u = read_dataset(h5, "displacement", n_values, components);
  H5Fclose(h5);
  ASSERT_EQ(dim, 3u);
  ASSERT_EQ(components, 3u);
  ASSERT_EQ(n_values, n_nodes);
  EXPECT_EQ(n_nodes, 5u * 5u * 9u);  // the Q2 support points of 2 x 2 x 4 cells, each once
  const double scale = p_ * 2.0 / material_.youngs_modulus;
  for (hsize_t i = 0; i < n_nodes; ++i) {
    const Vector3 e = exact(nodes[3 * i], nodes[3 * i + 1], nodes[3 * i + 2]);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(u[3 * i + c], e[c], 1e-6 * scale);
  }
  const std::string xdmf = directory_ + "/" + base_ + ".xdmf";
  EXPECT_NE(read_text(xdmf).find(base_ + ".h5"), std::string::npos);
  std::remove(file.c_str());
  std::remove(xdmf.c_str());
}

}  // namespace
}  // namespace trackbed::fem
