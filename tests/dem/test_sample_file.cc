// A sample file (sample.h5) gives back exactly what was written: bodies, shapes, sizes, walls,
// meshes, contact springs and info; foreign or damaged files are refused with one line.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "common/input_error.h"
#include "dem/io/sample.h"
#include "dem/io/snapshot.h"
#include "sim_builder.h"

namespace trackbed::dem {
namespace {

namespace fs = std::filesystem;

Sample small_sample() {
  Sample s;
  const ClumpTemplate t = make_clump_template(
      "stone",
      {{Vec3(-0.01, 0, 0), 0.012}, {Vec3(0.01, 0.002, 0), 0.01}, {Vec3(0, 0.01, 0), 0.008}});
  s.particles.add_ball(Vec3(0.1, 0.2, 0.3), 0.02, 0, 2800, 7);
  s.particles.add_clump(t, Vec3(-0.1, 0, 0.05), Quat(Eigen::AngleAxisd(0.4, Vec3::UnitY())), 1,
                        2500, 3);
  s.particles.v[1] = Vec3(0.1, -0.2, 0.3);
  s.particles.w[0] = Vec3(1, 2, 3);
  s.materials = {"ballast", "other"};
  s.shape = {-1, 0};
  s.sieve_size = {0.04, 0.051};
  s.shapes = {"stone"};
  PlaneWall w;
  w.name = "base";
  w.normal = Vec3::UnitZ();
  w.material = 1;
  s.planes.push_back(w);
  MeshBody m = MeshBody::from_world_mesh(
      "sleeper", make_box_mesh(Vec3(-0.5, -0.1, 0.3), Vec3(0.5, 0.1, 0.4), true), 1, 2500,
      Vec3::Zero());
  m.q = Quat(Eigen::AngleAxisd(0.01, Vec3::UnitZ()));
  m.update_world_mesh();
  s.meshes.push_back(m);
  s.contacts.pairs.push_back({{7, 0}, {3, 2}, Vec3(1, 2, 3), Vec3(4, 5, 6)});
  s.contacts.walls.push_back({1, 2, {3, 1}, Vec3(-1, 0, 0), Vec3(0, -2, 0), Vec3(0, 0, 1)});
  s.info = {{"section/length", "0.6"}, {"zone", "box(0, 0, 0, 1, 1, 1) | all"}};
  return s;
}

TEST(SampleFile, RoundTripIsExact) {
  const fs::path path = fs::temp_directory_path() / "trackbed_test_sample.h5";
  const Sample a = small_sample();
  write_sample(path.string(), a);
  EXPECT_FALSE(fs::exists(path.string() + ".part"));
  const Sample b = read_sample(path.string());
  const Particles &p = a.particles, &q = b.particles;
  ASSERT_EQ(q.num_bodies(), 2);
  ASSERT_EQ(q.num_elements(), 4);
  for (int i = 0; i < 2; ++i) {
    EXPECT_EQ(q.x[i], p.x[i]);
    EXPECT_EQ(q.v[i], p.v[i]);
    EXPECT_EQ(q.w[i], p.w[i]);
    EXPECT_EQ(q.q[i].coeffs(), p.q[i].coeffs());
    EXPECT_EQ(q.mass[i], p.mass[i]);
    EXPECT_EQ(q.inertia[i], p.inertia[i]);
    EXPECT_EQ(q.id[i], p.id[i]);
    EXPECT_EQ(q.is_clump[i], p.is_clump[i]);
    EXPECT_EQ(q.body_material[i], p.body_material[i]);
  }
  for (int e = 0; e < 4; ++e) {
    EXPECT_EQ(q.offset[e], p.offset[e]);
    EXPECT_EQ(q.radius[e], p.radius[e]);
    EXPECT_EQ(q.pos[e], p.pos[e]);  // recomputed from the body state, bit for bit
    EXPECT_EQ(q.material[e], p.material[e]);
  }
  EXPECT_EQ(b.materials, a.materials);
  EXPECT_EQ(b.shape, a.shape);
  EXPECT_EQ(b.sieve_size, a.sieve_size);
  EXPECT_EQ(b.shapes, a.shapes);
  ASSERT_EQ(b.planes.size(), 1u);
  EXPECT_EQ(b.planes[0].name, "base");
  EXPECT_EQ(b.planes[0].material, 1);
  ASSERT_EQ(b.meshes.size(), 1u);
  const MeshBody &m = a.meshes[0], &n = b.meshes[0];
  EXPECT_EQ(n.name, "sleeper");
  EXPECT_EQ(n.x, m.x);
  EXPECT_EQ(n.q.coeffs(), m.q.coeffs());
  EXPECT_EQ(n.mass, m.mass);
  EXPECT_EQ(n.inertia, m.inertia);
  EXPECT_EQ(n.local.part_names, m.local.part_names);
  EXPECT_EQ(n.local.triangle_part, m.local.triangle_part);
  for (std::size_t v = 0; v < m.world.vertices.size(); ++v)
    EXPECT_LT((n.world.vertices[v] - m.world.vertices[v]).norm(), 1e-15);
  ASSERT_EQ(b.contacts.pairs.size(), 1u);
  EXPECT_EQ(b.contacts.pairs[0].j.body_id, 3);
  EXPECT_EQ(b.contacts.pairs[0].j.rank, 2);
  EXPECT_EQ(b.contacts.pairs[0].roll, Vec3(4, 5, 6));
  ASSERT_EQ(b.contacts.walls.size(), 1u);
  EXPECT_EQ(b.contacts.walls[0].slot, 2);
  EXPECT_EQ(b.contacts.walls[0].normal, Vec3(0, 0, 1));
  EXPECT_EQ(b.info, a.info);
  EXPECT_EQ(b.info_value("zone"), "box(0, 0, 0, 1, 1, 1) | all");
  fs::remove(path);
}

TEST(SampleFile, ForeignAndMissingFilesAreRefused) {
  const fs::path dir = fs::temp_directory_path();
  auto message = [](const std::string& path) {
    try {
      read_sample(path);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message((dir / "no_such_sample.h5").string()).find("no such file"), std::string::npos);
  const fs::path text = dir / "trackbed_test_not_hdf5.h5";
  std::ofstream(text) << "not a sample\n";
  EXPECT_NE(message(text.string()).find("cannot open as HDF5"), std::string::npos);
  // A snapshot is HDF5 but not a sample.
  Particles p;
  p.add_ball(Vec3(0, 0, 0.1), 0.01, 0, 2800, 0);
  Simulation sim(testing::table_with_pair(testing::test_material(), 1e6), p, SimulationSettings());
  sim.setup();
  const fs::path snap = dir / "trackbed_test_snapshot_not_sample.h5";
  write_snapshot(snap.string(), sim);
  EXPECT_NE(message(snap.string()).find("not a trackbed sample"), std::string::npos);
  fs::remove(text);
  fs::remove(snap);
}

}  // namespace
}  // namespace trackbed::dem
