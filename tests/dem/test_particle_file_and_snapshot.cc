// The particle file places balls and clumps as documented (docs/formats.md), and an HDF5
// snapshot restores the state it saved.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "dem/engine/clump_template.h"
#include "dem/io/clump_template_file.h"
#include "dem/io/particle_file.h"
#include "dem/io/snapshot.h"
#include "sim_builder.h"

namespace trackbed::dem {
namespace {

namespace fs = std::filesystem;

fs::path temp_file(const std::string& name, const std::string& text) {
  const fs::path p = fs::temp_directory_path() / ("trackbed_test_pf_" + name);
  std::ofstream(p) << text;
  return p;
}

TEST(ParticleFile, ClumpRowsPlaceTheTemplateFrame) {
  // Template spheres given off-centre in their own frame; the row puts the frame's origin at X,
  // rotates it by q and scales it by s: every sphere must land at X + s R c_input.
  const std::vector<SphereShape> input = {{Vec3(0.10, 0.02, 0.00), 0.012},
                                          {Vec3(0.115, 0.02, 0.004), 0.01},
                                          {Vec3(0.10, 0.035, -0.003), 0.009}};
  std::string tcsv = "x,y,z,radius\n";
  for (const auto& s : input)
    tcsv += std::to_string(s.centre.x()) + "," + std::to_string(s.centre.y()) + "," +
            std::to_string(s.centre.z()) + "," + std::to_string(s.radius) + "\n";
  const ClumpTemplate t = read_clump_template_csv(temp_file("t.csv", tcsv).string(), "stone");
  const Quat q = Quat(Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()));
  const Vec3 X(1.0, -2.0, 0.5);
  const double scale = 1.3;
  const fs::path pcsv =
      temp_file("p.csv", "x,y,z,radius,template,scale,qw,qx,qy,qz,vx\n" + std::to_string(X.x()) +
                             "," + std::to_string(X.y()) + "," + std::to_string(X.z()) +
                             ",,stone," + std::to_string(scale) + "," + std::to_string(q.w()) +
                             "," + std::to_string(q.x()) + "," + std::to_string(q.y()) + "," +
                             std::to_string(q.z()) + ",0.5\n0,0,0,0.02,,,,,,,\n");
  MaterialTable m;
  m.add(testing::test_material());
  Particles p;
  read_particle_file(pcsv.string(), m, {{"stone", t}}, p);
  ASSERT_EQ(p.num_bodies(), 2);
  ASSERT_EQ(p.num_elements(), 4);
  EXPECT_TRUE(p.is_clump[0]);
  EXPECT_DOUBLE_EQ(p.v[0].x(), 0.5);
  // The CSV text carries 6 digits: compare with the rotation the file holds.
  const Quat q_file(std::stod(std::to_string(q.w())), std::stod(std::to_string(q.x())),
                    std::stod(std::to_string(q.y())), std::stod(std::to_string(q.z())));
  for (int e = 0; e < 3; ++e) {
    const Vec3 expected = X + scale * (q_file.normalized() * input[e].centre);
    // Element order within a clump follows the template file.
    EXPECT_LT((p.pos[e] - expected).norm(), 1e-6) << e;  // 6-digit text in the files
    EXPECT_NEAR(p.radius[e], scale * input[e].radius, 1e-9);
  }
  // The body sits at the (scaled, moved) centroid with the scaled volume's mass.
  EXPECT_NEAR(p.mass[0], 2800 * t.volume * scale * scale * scale, 1e-9);
  EXPECT_EQ(p.radius[3], 0.02);
}

TEST(Snapshot, RestoresTheSavedState) {
  Material mat = testing::test_material();
  auto build = [&] {
    MaterialTable t;
    t.add(mat);
    Particles p;
    p.add_ball(Vec3(0, 0, 0.05), 0.02, 0, mat.density, 0);
    p.add_clump(make_clump_template("c", {{Vec3(0, 0, 0), 0.02}, {Vec3(0.02, 0, 0), 0.015}}),
                Vec3(0.1, 0, 0.05), Quat::Identity(), 0, mat.density, 1);
    SimulationSettings s;
    s.time_step = 1e-5;
    auto sim = std::make_unique<Simulation>(std::move(t), std::move(p), s);
    sim->add_plane(testing::floor_at(0));
    return sim;
  };
  auto a = build();
  a->particles().w[1] = Vec3(1, 2, 3);
  testing::run_for(*a, 0.05);
  const fs::path file = fs::temp_directory_path() / "trackbed_test_snapshot.h5";
  write_snapshot(file.string(), *a);
  EXPECT_FALSE(fs::exists(file.string() + ".part"));
  auto b = build();
  b->setup();
  read_snapshot(file.string(), *b);
  EXPECT_EQ(b->time(), a->time());
  EXPECT_EQ(b->step_count(), a->step_count());
  for (int i = 0; i < 2; ++i) {
    EXPECT_EQ(b->particles().x[i], a->particles().x[i]);
    EXPECT_EQ(b->particles().v[i], a->particles().v[i]);
    EXPECT_EQ(b->particles().w[i], a->particles().w[i]);
    EXPECT_EQ(b->particles().q[i].coeffs(), a->particles().q[i].coeffs());
  }
  for (int e = 0; e < 3; ++e) EXPECT_EQ(b->particles().pos[e], a->particles().pos[e]);
  // A file of another model is refused with a clear line.
  MaterialTable t;
  t.add(mat);
  Particles one;
  one.add_ball(Vec3(0, 0, 0.05), 0.02, 0, mat.density, 0);
  Simulation c(std::move(t), std::move(one), SimulationSettings());
  try {
    read_snapshot(file.string(), c);
    ADD_FAILURE() << "no error for a snapshot of another model";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("the model needs"), std::string::npos) << e.what();
  }
  fs::remove(file);
}

}  // namespace
}  // namespace trackbed::dem
