// Gmsh input and bad input: every error is one line naming the file or parameter and what is
// valid.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <fstream>
#include <functional>

#include "fem/elastic_body.h"
#include "fem/errors.h"

namespace trackbed::fem {
namespace {

std::string temporary_file(const std::string& name, const std::string& content) {
  const std::string path = ::testing::TempDir() + "/" + std::to_string(getpid()) + "_" + name;
  std::ofstream(path) << content;
  return path;
}

// A 1 m x 1 m x 2 m column of two hexahedra in Gmsh 2.2 format: subgrade (volume group 2) below
// sub-ballast (volume group 1), surface groups "bottom" (10) and "top" (11); the sides have no
// group, so deal.II gives them boundary id 0.
std::string column_msh() {
  std::string nodes;
  for (int iz = 0; iz < 3; ++iz)
    for (int iy = 0; iy < 2; ++iy)
      for (int ix = 0; ix < 2; ++ix)
        nodes += std::to_string(1 + ix + 2 * iy + 4 * iz) + " " + std::to_string(ix) + " " +
                 std::to_string(iy) + " " + std::to_string(iz) + "\n";
  return "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n"
         "$PhysicalNames\n4\n2 10 \"bottom\"\n2 11 \"top\"\n3 1 \"sub_ballast\"\n"
         "3 2 \"subgrade\"\n$EndPhysicalNames\n"
         "$Nodes\n12\n" +
         nodes +
         "$EndNodes\n"
         "$Elements\n4\n"
         "1 3 2 10 1 1 3 4 2\n"
         "2 3 2 11 2 9 10 12 11\n"
         "3 5 2 2 3 1 2 4 3 5 6 8 7\n"
         "4 5 2 1 4 5 6 8 7 9 10 12 11\n"
         "$EndElements\n";
}

// The same column in Gmsh 4.1 format: entities carry the physical tags (surface 1 = bottom,
// surface 2 = top, volume 1 = subgrade, volume 2 = sub-ballast).
std::string column_msh41() {
  std::string coordinates;
  for (int iz = 0; iz < 3; ++iz)
    for (int iy = 0; iy < 2; ++iy)
      for (int ix = 0; ix < 2; ++ix)
        coordinates +=
            std::to_string(ix) + " " + std::to_string(iy) + " " + std::to_string(iz) + "\n";
  std::string tags;
  for (int i = 1; i <= 12; ++i) tags += std::to_string(i) + "\n";
  return "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n"
         "$PhysicalNames\n4\n2 10 \"bottom\"\n2 11 \"top\"\n3 1 \"sub_ballast\"\n"
         "3 2 \"subgrade\"\n$EndPhysicalNames\n"
         "$Entities\n0 0 2 2\n"
         "1 0 0 0 1 1 0 1 10 0\n"
         "2 0 0 2 1 1 2 1 11 0\n"
         "1 0 0 0 1 1 1 1 2 0\n"
         "2 0 0 1 1 1 2 1 1 0\n"
         "$EndEntities\n"
         "$Nodes\n1 12 1 12\n3 1 0 12\n" +
         tags + coordinates +
         "$EndNodes\n"
         "$Elements\n4 4 1 4\n"
         "2 1 3 1\n1 1 3 4 2\n"
         "2 2 3 1\n2 9 10 12 11\n"
         "3 1 5 1\n3 1 2 4 3 5 6 8 7\n"
         "3 2 5 1\n4 5 6 8 7 9 10 12 11\n"
         "$EndElements\n";
}

// Runs `action`, expects an error of type E whose one-line message contains every fragment.
template <typename E>
void expect_error(const std::function<void()>& action, const std::vector<std::string>& fragments) {
  try {
    action();
    ADD_FAILURE() << "no error thrown";
  } catch (const E& error) {
    const std::string message = error.what();
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    for (const std::string& fragment : fragments)
      EXPECT_NE(message.find(fragment), std::string::npos) << message << " lacks " << fragment;
  }
}

// The column read from Gmsh (format 2.2 and 4.1), laterally confined (both horizontal components
// fixed on the unnamed sides, id 0), fixed at the bottom and pressed by q at the top: the 1-D
// solution u_z(top) = -q (1 / M_subgrade + 1 / M_sub-ballast) x 1 m, linear per layer, which Q1
// gets exactly (solver tolerance 1e-12; test tolerance 1e-9 relative).
class FemGmsh : public ::testing::TestWithParam<int> {};

TEST_P(FemGmsh, ColumnWithPhysicalGroups) {
  const std::string file = GetParam() == 2 ? temporary_file("column.msh", column_msh())
                                           : temporary_file("column41.msh", column_msh41());
  ElasticBody body(1, MPI_COMM_WORLD);
  body.read_gmsh(file);
  body.refine_globally(1);
  body.set_material(1, sub_ballast());
  body.set_material(2, subgrade_fill());
  body.set_gravity({{0, 0, 0}});
  body.fix(body.boundary_id("bottom"));
  body.fix(0, {{true, true, false}});
  const double q = 5e4;
  body.set_traction(body.boundary_id("top"), {{0, 0, -q}});
  SolverParameters solver;
  solver.relative_tolerance = 1e-12;
  body.set_solver(solver);
  body.setup();
  body.solve_static();
  const double exact = -q * (1.0 / subgrade_fill().constrained_modulus() +
                             1.0 / sub_ballast().constrained_modulus());
  const auto top = body.probe({{{0.5, 0.5, 2.0}}, {{0.2, 0.7, 1.5}}});
  EXPECT_NEAR(top[0].displacement[2], exact, 1e-9 * std::abs(exact));
  EXPECT_NEAR(top[1].stress[2][2], -q, 1e-9 * q);
  std::remove(file.c_str());
}

INSTANTIATE_TEST_SUITE_P(Formats, FemGmsh, ::testing::Values(2, 4));

TEST(FemInput, MissingMeshFile) {
  ElasticBody body(1, MPI_COMM_WORLD);
  expect_error<InputError>([&] { body.read_gmsh("/nonexistent/bed.msh"); },
                           {"/nonexistent/bed.msh", "cannot open", "Gmsh"});
}

TEST(FemInput, MalformedMeshFile) {
  const std::string file = temporary_file("bad.msh",
                                          "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n"
                                          "$Nodes\n3\n1 0 0\n$EndNodes\n");
  ElasticBody body(1, MPI_COMM_WORLD);
  expect_error<InputError>([&] { body.read_gmsh(file); }, {file, "malformed", "hexahedra"});
  std::remove(file.c_str());
}

TEST(FemInput, TetrahedralMeshIsRejected) {
  const std::string file = temporary_file(
      "tet.msh",
      "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n"
      "$EndNodes\n$Elements\n1\n1 4 2 1 1 1 2 3 4\n$EndElements\n");
  ElasticBody body(1, MPI_COMM_WORLD);
  expect_error<InputError>([&] { body.read_gmsh(file); }, {file, "hexahedra"});
  std::remove(file.c_str());
}

TEST(FemInput, UnknownMaterialId) {
  const std::string file = temporary_file("column2.msh", column_msh());
  ElasticBody body(1, MPI_COMM_WORLD);
  body.read_gmsh(file);
  body.set_material(1, sub_ballast());
  body.fix(body.boundary_id("bottom"));
  expect_error<InputError>([&] { body.setup(); }, {file, "material id 2", "defined ids: 1"});
  std::remove(file.c_str());
}

TEST(FemInput, UnknownBoundaryNameAndId) {
  ElasticBody body(1, MPI_COMM_WORLD);
  body.make_box({});
  body.set_material(0, sub_ballast());
  expect_error<InputError>([&] { body.boundary_id("ballast"); }, {"'ballast'", "'zmin'"});
  body.fix(42);
  expect_error<InputError>([&] { body.setup(); }, {"boundary id 42", "0, 1, 2, 3, 4, 5"});
}

TEST(FemInput, NonPhysicalMaterials) {
  ElasticBody body(1, MPI_COMM_WORLD);
  expect_error<InputError>(
      [&] {
        body.set_material(3, {"clay", 50e6, 0.5, 1800});
      },
      {"material id 3", "'clay'", "Poisson ratio", "nu < 0.5"});
  expect_error<InputError>(
      [&] {
        body.set_material(3, {"clay", 0.0, 0.3, 1800});
      },
      {"material id 3", "Young's modulus", "> 0"});
  expect_error<InputError>(
      [&] {
        body.set_material(3, {"clay", 50e6, 0.3, -1.0});
      },
      {"material id 3", "density", "> 0"});
}

TEST(FemInput, BadElementDegreeAndGeometry) {
  expect_error<InputError>([] { ElasticBody body(3, MPI_COMM_WORLD); }, {"degree = 3", "1", "2"});
  ElasticBody body(1, MPI_COMM_WORLD);
  TrackSection section;
  section.ground_half_width = 3.0;
  expect_error<InputError>([&] { body.make_track_section(section, 0.25); },
                           {"'ground half width' = 3", "embankment base"});
  expect_error<InputError>([&] { body.setup(); }, {"no mesh"});
}

// One AMG-preconditioned CG iteration cannot reach a relative residual of 1e-12 on a mesh big
// enough for a multilevel hierarchy (on tiny meshes ML's coarse solve is exact).
TEST(FemInput, SolverNonConvergence) {
  ElasticBody body(1, MPI_COMM_WORLD);
  body.make_box({{{0, 0, 0}}, {{1, 1, 1}}, {{10, 10, 10}}, {}});
  body.set_material(0, subgrade_fill());
  body.fix(body.boundary_id("zmin"));
  SolverParameters solver;
  solver.relative_tolerance = 1e-12;
  solver.max_iterations = 1;
  body.set_solver(solver);
  body.setup();
  expect_error<SolverError>([&] { body.solve_static(); },
                            {"did not converge", "'max iterations' = 1"});
  solver.max_iterations = 0;
  expect_error<InputError>([&] { body.set_solver(solver); }, {"'max iterations' = 0"});
}

}  // namespace
}  // namespace trackbed::fem
