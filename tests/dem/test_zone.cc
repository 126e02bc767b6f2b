// Zones classify points as docs/zones.md says: every shape closed, the operators' precedence and
// associativity, parse errors with their position, a canonical text that reads back, and the
// pilot zone built from real snapshot files.
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <random>

#include "common/input_error.h"
#include "dem/engine/triangle_mesh.h"
#include "dem/io/snapshot.h"
#include "dem/samples/pilot_zone.h"
#include "dem/samples/zone.h"
#include "sim_builder.h"

namespace trackbed::dem {
namespace {

namespace fs = std::filesystem;

ZonePtr parse(const std::string& text) {
  return parse_zone(text, "test", "");
}

std::string parse_error(const std::string& text, const std::string& base = "") {
  try {
    parse_zone(text, "case.prm: sample/clump zone", base);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

bool in(const std::string& text, const Vec3& x) {
  return parse(text)->contains(x);
}

// A step well above the rounding of the coordinates used (~1e-16) and far below any feature.
constexpr double kNear = 1e-9;

TEST(Zone, BoxIsClosed) {
  const std::string box = "box(0, 0, 0, 1, 2, 3)";
  EXPECT_TRUE(in(box, Vec3(0.5, 1, 1.5)));
  EXPECT_TRUE(in(box, Vec3(1, 2, 3)));  // a corner
  EXPECT_TRUE(in(box, Vec3(1 - kNear, 1, 1)));
  EXPECT_FALSE(in(box, Vec3(1 + kNear, 1, 1)));
  EXPECT_FALSE(in(box, Vec3(0.5, -kNear, 1)));
  EXPECT_FALSE(in(box, Vec3(0.5, 1, 3 + kNear)));
}

TEST(Zone, HalfspaceIsTheSideOppositeTheNormal) {
  // Clumps above 265 mm: the outward normal points down.
  const std::string above = "halfspace(0, 0, 0.265, 0, 0, -1)";
  EXPECT_TRUE(in(above, Vec3(7, -3, 0.265)));
  EXPECT_TRUE(in(above, Vec3(0, 0, 0.265 + kNear)));
  EXPECT_FALSE(in(above, Vec3(0, 0, 0.265 - kNear)));
  // A slanted normal, not unit length: x + y <= 1.
  EXPECT_TRUE(in("halfspace(1, 0, 0, 2, 2, 0)", Vec3(0.5, 0.5 - kNear, 9)));
  EXPECT_FALSE(in("halfspace(1, 0, 0, 2, 2, 0)", Vec3(0.5, 0.5 + kNear, 9)));
}

TEST(Zone, SphereAllAndNone) {
  EXPECT_TRUE(in("sphere(1, 1, 1, 0.5)", Vec3(1.5, 1, 1)));
  EXPECT_TRUE(in("sphere(1, 1, 1, 0.5)", Vec3(1, 1.5 - kNear, 1)));
  EXPECT_FALSE(in("sphere(1, 1, 1, 0.5)", Vec3(1, 1, 0.5 - kNear)));
  EXPECT_TRUE(in("all", Vec3(1e9, -1e9, 0)));
  EXPECT_FALSE(in("none", Vec3(0, 0, 0)));
}

TEST(Zone, NonConvexPrismAnLShape) {
  // An L in the (x, y) plane: the unit square [1, 2] x [1, 2] is cut out of [0, 2]^2.
  const std::string l = "prism(z, 0, 1, 0,0, 2,0, 2,1, 1,1, 1,2, 0,2)";
  EXPECT_TRUE(in(l, Vec3(0.5, 0.5, 0.5)));
  EXPECT_TRUE(in(l, Vec3(1.5, 0.5, 0.5)));
  EXPECT_TRUE(in(l, Vec3(0.5, 1.5, 0.5)));
  EXPECT_FALSE(in(l, Vec3(1.5, 1.5, 0.5)));  // the notch
  EXPECT_TRUE(in(l, Vec3(1.5, 1 - kNear, 0.5)));
  EXPECT_FALSE(in(l, Vec3(1.5, 1 + kNear, 0.5)));
  EXPECT_TRUE(in(l, Vec3(1.5, 1, 0.5)));  // on an edge: closed
  EXPECT_TRUE(in(l, Vec3(2, 0, 0)));      // a vertex
  // The horizontal through p passes through vertex (1, 1) and along edge (2,1)-(1,1): the
  // crossing count must still be right on either side.
  EXPECT_TRUE(in(l, Vec3(0.5, 1, 0.5)));
  EXPECT_FALSE(in(l, Vec3(-0.5, 1, 0.5)));
  EXPECT_FALSE(in(l, Vec3(2.5, 1, 0.5)));
  EXPECT_FALSE(in(l, Vec3(0.5, 0.5, 1 + kNear)));  // beyond hi
  EXPECT_FALSE(in(l, Vec3(0.5, 0.5, -kNear)));     // below lo
}

TEST(Zone, PrismCoordinatesFollowTheAxis) {
  // The triangle (0,0), (1,0), (0,2) in each axis' plane: inside when u + v/2 <= 1.
  EXPECT_TRUE(in("prism(y, 0, 1, 0,0, 1,0, 0,2)", Vec3(0.2, 0.5, 1.5)));  // (u, v) = (x, z)
  EXPECT_FALSE(in("prism(y, 0, 1, 0,0, 1,0, 0,2)", Vec3(0.2, 0.5, 1.7)));
  EXPECT_FALSE(in("prism(y, 0, 1, 0,0, 1,0, 0,2)", Vec3(0.2, 1.5, 1.0)));  // beyond hi in y
  EXPECT_TRUE(in("prism(x, 0, 1, 0,0, 1,0, 0,2)", Vec3(0.5, 0.2, 1.5)));   // (u, v) = (y, z)
  EXPECT_FALSE(in("prism(x, 0, 1, 0,0, 1,0, 0,2)", Vec3(0.5, 0.2, 1.7)));
  EXPECT_TRUE(in("prism(z, 0, 1, 0,0, 1,0, 0,2)", Vec3(0.2, 1.5, 0.5)));  // (u, v) = (x, y)
  EXPECT_FALSE(in("prism(z, 0, 1, 0,0, 1,0, 0,2)", Vec3(0.2, 1.7, 0.5)));
  // The unit cube as a prism and as a box: the same closed set.
  const ZonePtr prism = parse("prism(x, 0, 1, 0,0, 1,0, 1,1, 0,1)");
  const ZonePtr box = parse("box(0, 0, 0, 1, 1, 1)");
  std::mt19937_64 rng(2);
  std::uniform_real_distribution<double> u(-0.5, 1.5);
  for (int i = 0; i < 2000; ++i) {
    const Vec3 x(u(rng), u(rng), u(rng));
    ASSERT_EQ(prism->contains(x), box->contains(x)) << x.transpose();
  }
  for (const Vec3& corner : {Vec3(1, 1, 1), Vec3(0, 1, 0), Vec3(0.5, 0, 1)})
    EXPECT_TRUE(prism->contains(corner) && box->contains(corner)) << corner.transpose();
}

TEST(Zone, PrecedenceAndAssociativity) {
  // Slabs along x: a = [0, 3], b = [1, 3], c = [2, 3].
  const std::string a = "box(0,0,0, 3,1,1)", b = "box(1,0,0, 3,1,1)", c = "box(2,0,0, 3,1,1)";
  const Vec3 at_2_5(2.5, 0.5, 0.5), at_0_5(0.5, 0.5, 0.5);
  // a - b - c is (a - b) - c = [0, 1); a - (b - c) also holds [2, 3].
  EXPECT_FALSE(in(a + " - " + b + " - " + c, at_2_5));
  EXPECT_TRUE(in(a + " - (" + b + " - " + c + ")", at_2_5));
  EXPECT_TRUE(in(a + " - " + b + " - " + c, at_0_5));
  // '&' binds tighter: a | b & c is a | (b & c). With d = [4, 5]: d | b & c holds [2, 3], while
  // (d | b) & c would too; d | a & c = d | [2, 3] does not hold 0.5, (d | a) & c neither, but
  // a | d & c = a holds 0.5 where (a | d) & c does not.
  const std::string d = "box(4,0,0, 5,1,1)";
  EXPECT_TRUE(in(a + " | " + d + " & " + c, at_0_5));
  EXPECT_FALSE(in("(" + a + " | " + d + ") & " + c, at_0_5));
  EXPECT_TRUE(in(d + " & " + c + " | " + a, at_0_5));  // (d & c) | a
  // '+' is '|', and '|', '+', '-' are one left-associative level: a - b + c = (a - b) + c.
  EXPECT_TRUE(in(a + " - " + b + " + " + c, at_2_5));
  EXPECT_FALSE(in(a + " - (" + b + " + " + c + ")", at_2_5));
  EXPECT_FALSE(in(a + " | " + b + " - " + c, at_2_5));  // (a | b) - c
  // & before -: b & c - a... = (b & c) - a is empty here.
  EXPECT_FALSE(in(b + " & " + c + " - " + a, at_2_5));
  // Free whitespace, scientific notation, signs.
  EXPECT_TRUE(in(" ( box( -1e0,-.5 ,-5E-1,+1,0.5e+0,5e-1 ))&all ", Vec3(0.9, 0.4, -0.4)));
}

struct ErrorCase {
  std::string text;
  std::string expected;  // a piece of the message
};

TEST(Zone, ParseErrorsNameThePositionAndWhatIsValid) {
  const std::vector<ErrorCase> cases = {
      {"boxx(0,0,0,1,1,1)",
       "case.prm: sample/clump zone: character 1 of \"boxx(0,0,0,1,1,1)\": unknown shape 'boxx'; "
       "valid: all, none, box, halfspace, sphere, prism, pilot"},
      {"box(0,0,0 1,1,1)",
       "character 11 of \"box(0,0,0 1,1,1)\": expected ',' or ')' after argument 3 of box(x0, y0, "
       "z0, x1, y1, z1), found '1'"},
      {"box(0,0,0,1,1)",
       "character 1 of \"box(0,0,0,1,1)\": box(x0, y0, z0, x1, y1, z1) takes 6 "
       "arguments, got 5"},
      {"sphere(0,0,0,1,2)", "sphere(cx, cy, cz, r) takes 4 arguments, got 5"},
      {"(box(0,0,0,1,1,1) | all",
       "character 24 of \"(box(0,0,0,1,1,1) | all\": expected ')' to "
       "close the '(' at character 1, found the end of the text"},
      {"all )",
       "character 5 of \"all )\": unexpected ')' after a complete zone; valid: an "
       "operator |, +, -, & or the end of the text"},
      {"sphere(0,0,0,1.2.3)",
       "character 14 of \"sphere(0,0,0,1.2.3)\": '1.2.3' is not a number (argument 4 of "
       "sphere(cx, cy, cz, r)); valid: a decimal number"},
      {"sphere(0,0,0,inf)", "'inf' is not a number"},
      {"sphere(+-1,0,0,1)", "'+-1' is not a number"},
      {"sphere(0,0,0,2e)", "'2e' is not a number"},
      {"box(0,0,0,1,1,-1)",
       "character 1 of \"box(0,0,0,1,1,-1)\": box: upper z -1 is not above lower z 0; valid: "
       "box(x0, y0, z0, x1, y1, z1) with x1 > x0"},
      {"box(0,0,0,1,0,1)", "box: upper y 0 is not above lower y 0"},
      {"all | halfspace(0,0,0, 0,0,0)",
       "character 7 of \"all | halfspace(0,0,0, 0,0,0)\": halfspace: the normal (0, 0, 0) has no "
       "direction"},
      {"prism(z,0,1, 0,0, 1,1, 1,0, 0,1)",
       "prism: edge 1 (vertices 1-2) and edge 3 (vertices 3-4) cross or touch; valid: a simple "
       "polygon"},
      {"prism(z,0,1, 0,0, 2,0, 1,0)",
       "prism: edge 1 (vertices 1-2) and edge 2 (vertices 2-3) fold back onto each other"},
      {"prism(z,0,1, 0,0, 1,0, 1,0, 0,1)", "prism: vertices 2 and 3 coincide"},
      {"prism(z,0,1, 0,0, 1,0)", "takes an axis, lo, hi and at least 3 vertices (u, v); got 7"},
      {"prism(z,0,1, 0,0, 1,0, 1,1, 0)", "vertex coordinates come in (u, v) pairs; got 7"},
      {"prism(w,0,1, 0,0, 1,0, 0,1)", "character 7 of \"prism(w,0,1, 0,0, 1,0, 0,1)\": axis 'w'"},
      {"prism(z,1,1, 0,0, 1,0, 0,1)", "prism: hi 1 is not above lo 1"},
      {"sphere(0,0,0,0)", "sphere: radius 0 is not valid; valid: a radius > 0"},
      {"box(0,0,0,1,1,1) &",
       "character 19 of \"box(0,0,0,1,1,1) &\": expected a shape (all, "
       "none, box, halfspace, sphere, prism, pilot) or '(', found the end"},
      {"box(0,0,0,1,1,1,)",
       "character 17 of \"box(0,0,0,1,1,1,)\": expected a number as "
       "argument 7 of box(x0, y0, z0, x1, y1, z1), found ')'"},
      {"box 1", "character 5 of \"box 1\": expected '(' after box"},
      {"   ", "character 4 of \"   \": empty zone expression"},
      {"pilot(\"run, 1, 1, 1)", "the path opened with '\"' at character 7 has no closing '\"'"},
  };
  for (const auto& c : cases) {
    const std::string message = parse_error(c.text);
    EXPECT_NE(message.find(c.expected), std::string::npos) << c.text << "\n  got: " << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    // Named once: a shape's own check is not wrapped twice.
    EXPECT_EQ(message.find("case.prm", 1), std::string::npos) << message;
  }
}

TEST(Zone, CanonicalText) {
  EXPECT_EQ(parse("box(0,0,0,1,1,1)+sphere(0,0,0,1)&all")->to_string(),
            "box(0, 0, 0, 1, 1, 1) | sphere(0, 0, 0, 1) & all");
  EXPECT_EQ(parse("((all - none) - all)")->to_string(), "all - none - all");
  EXPECT_EQ(parse("all - (none - all)")->to_string(), "all - (none - all)");
  EXPECT_EQ(parse("(all | none) & all")->to_string(), "(all | none) & all");
  EXPECT_EQ(parse("all & (none & all)")->to_string(), "all & (none & all)");
  EXPECT_EQ(parse("sphere(0.1, 2.5e-3, 1e-7, 3)")->to_string(), "sphere(0.1, 0.0025, 1e-07, 3)");
  EXPECT_EQ(parse("prism( y ,0,0.28, -1.3,0.35, 1.3,0.35, 0,0.5)")->to_string(),
            "prism(y, 0, 0.28, -1.3, 0.35, 1.3, 0.35, 0, 0.5)");
}

TEST(Zone, CanonicalTextReadsBackAsTheSameZone) {
  const std::string text =
      "box(-1.6, -0.3, 0.2, 1.6, 0.3, 0.6) | halfspace(0, 0, 0.265, 0.1, 0.2, -1) & "
      "sphere(0.3, 0, 0.4, 0.35) - prism(y, -0.2, 0.2, 1.3,0.35, 1.8,0.35, 2.2,0.1, 1.7,0.2, "
      "1.3,0) - (all - box(-2, -1, -1, 2, 1, 0.45)) + none";
  const ZonePtr z = parse(text);
  const ZonePtr back = parse(z->to_string());
  EXPECT_EQ(back->to_string(), z->to_string());
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> ux(-2.5, 2.5), uy(-0.5, 0.5), uz(-0.2, 0.8);
  int inside = 0;
  for (int i = 0; i < 20000; ++i) {
    const Vec3 x(ux(rng), uy(rng), uz(rng));
    ASSERT_EQ(z->contains(x), back->contains(x)) << x.transpose();
    inside += z->contains(x);
  }
  // Both sides of the boundaries are sampled, so the comparison means something.
  EXPECT_GT(inside, 1000);
  EXPECT_LT(inside, 19000);
}

TEST(Zone, Bounds) {
  const auto box = parse("box(0,0,0,1,2,3)")->bounds();
  ASSERT_TRUE(box);
  EXPECT_EQ(box->min(), Vec3(0, 0, 0));
  EXPECT_EQ(box->max(), Vec3(1, 2, 3));
  EXPECT_FALSE(parse("halfspace(0,0,0,0,0,1)")->bounds());
  EXPECT_FALSE(parse("box(0,0,0,1,1,1) | all")->bounds());
  const auto cut = parse("halfspace(0,0,0.5,0,0,1) & box(0,0,0,1,1,1)")->bounds();
  ASSERT_TRUE(cut);
  EXPECT_EQ(cut->max(), Vec3(1, 1, 1));
  const auto both = parse("sphere(5,0,0,1) | prism(z, -1, 1, 0,0, 1,0, 0,2)")->bounds();
  ASSERT_TRUE(both);
  EXPECT_EQ(both->min(), Vec3(0, -1, -1));
  EXPECT_EQ(both->max(), Vec3(6, 2, 1));
  EXPECT_TRUE(parse("none")->bounds()->isEmpty());
  EXPECT_TRUE(parse("box(0,0,0,1,1,1) & box(2,2,2,3,3,3)")->bounds()->isEmpty());
}

TEST(SphereUnion, GridAgreesWithBruteForceAndIsFast) {
  // 20,000 bounding spheres of a section's stones (radii 20-50 mm, the dilated bounding spheres
  // of 22.4-63 mm stones) in a 2.6 x 0.6 x 0.5 m bed.
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> ux(-1.3, 1.3), uy(-0.3, 0.3), uz(0, 0.5), ur(0.02, 0.05);
  std::vector<SphereUnion::Sphere> spheres;
  for (int i = 0; i < 20000; ++i) spheres.push_back({Vec3(ux(rng), uy(rng), uz(rng)), ur(rng)});
  const SphereUnion zone(spheres);
  std::uniform_real_distribution<double> qx(-1.5, 1.5), qy(-0.5, 0.5), qz(-0.2, 0.7);
  int inside = 0;
  for (int i = 0; i < 3000; ++i) {
    const Vec3 x(qx(rng), qy(rng), qz(rng));
    bool brute = false;
    for (const auto& s : spheres) brute = brute || (x - s.centre).norm() <= s.radius;
    ASSERT_EQ(zone.contains(x), brute) << x.transpose();
    inside += brute;
  }
  EXPECT_GT(inside, 300);
  EXPECT_LT(inside, 2700);
  // Points on the spheres' surfaces, just inside and just outside.
  for (int i = 0; i < 200; ++i) {
    const auto& s = spheres[i];
    EXPECT_TRUE(zone.contains(s.centre + Vec3(0, 0, s.radius * (1 - 1e-9))));
  }
  // 650,000 queries (a sample of 650k candidate positions): the requirement is "well under a
  // second"; the grid takes ~0.05 s in Release on one core, so 1 s leaves room for a loaded
  // machine.
  std::vector<Vec3> queries;
  for (int i = 0; i < 650000; ++i) queries.emplace_back(qx(rng), qy(rng), qz(rng));
  const auto start = std::chrono::steady_clock::now();
  long hits = 0;
  for (const auto& q : queries) hits += zone.contains(q);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_GT(hits, 0);
  EXPECT_LT(seconds, 1.0);
  RecordProperty("query_seconds", std::to_string(seconds));
  EXPECT_FALSE(SphereUnion({}).contains(Vec3::Zero()));
}

// ---- the pilot zone, from snapshots written by a small model ----

// Four bodies: three balls and a clump, with ids 10-13, and a sleeper box.
struct PilotBody {
  std::int64_t id;
  Vec3 x;
  double radius;  // 0: the clump
};
const std::vector<PilotBody> kBodies = {{10, Vec3(0.0, 0, 0.02), 0.02},
                                        {11, Vec3(0.1, 0, 0.02), 0.015},
                                        {12, Vec3(0.2, 0, 0.02), 0.02},
                                        {13, Vec3(0.35, 0, 0.02), 0}};
const Vec3 kSleeperStart(0, 0, 0.3);

// Writes a snapshot of the bodies moved by `moved` (per body, in kBodies order), added to the
// model in `order`, with the sleeper moved by `sleeper` along x, at `step`.
void write_pilot_snapshot(const fs::path& file, const std::vector<int>& order,
                          const std::vector<Vec3>& moved, double sleeper, long step) {
  const Material mat = testing::test_material();
  MaterialTable table;
  table.add(mat);
  Particles p;
  const ClumpTemplate clump =
      make_clump_template("c", {{Vec3(0, 0, 0), 0.02}, {Vec3(0.03, 0, 0), 0.015}});
  for (int b : order) {
    const PilotBody& body = kBodies[b];
    if (body.radius > 0)
      p.add_ball(body.x + moved[b], body.radius, 0, mat.density, body.id);
    else
      p.add_clump(clump, body.x + moved[b], Quat::Identity(), 0, mat.density, body.id);
  }
  Simulation sim(std::move(table), std::move(p), SimulationSettings());
  const TriangleMesh box = make_box_mesh(Vec3(-0.2, -0.1, 0.25), Vec3(0.5, 0.1, 0.35), true);
  sim.add_mesh_body(MeshBody::from_world_mesh("sleeper", box, 0, 0, kSleeperStart));
  sim.meshes()[0].x = kSleeperStart + Vec3(sleeper, 0, 0);
  sim.set_time(1e-3 * step, step);
  write_snapshot(file.string(), sim);
}

// A pilot run: the reference, the sleeper 2.5 mm on (clump moved 4 mm, ball 10 1 mm), and 5 mm on
// (ball 10 moved 4 mm, ball 11 1 mm, ball 12 2.9 mm, the clump 10 mm), each with the bodies in
// another order.
fs::path write_pilot_run(const std::string& name) {
  // The process id keeps two builds' test runs on one machine apart.
  const fs::path run =
      fs::temp_directory_path() / ("trackbed_test_zone_" + std::to_string(::getpid()) + "_" + name);
  fs::remove_all(run);
  fs::create_directories(run / "snapshots");
  const Vec3 zero = Vec3::Zero(), x = Vec3::UnitX();
  write_pilot_snapshot(run / "snapshots" / "state-000000000.h5", {0, 1, 2, 3},
                       {zero, zero, zero, zero}, 0, 0);
  write_pilot_snapshot(run / "snapshots" / "state-000000100.h5", {3, 2, 1, 0},
                       {0.001 * x, zero, zero, 0.004 * x}, 0.0025, 100);
  write_pilot_snapshot(run / "snapshots" / "state-000000200.h5", {1, 3, 0, 2},
                       {0.004 * x, 0.001 * x, 0.0029 * x, 0.01 * x}, 0.005, 200);
  return run;
}

TEST(SnapshotBodies, ReadsBodiesBoundingRadiiAndMeshes) {
  const fs::path run = write_pilot_run("reader");
  const SnapshotBodies s = read_snapshot_bodies((run / "snapshots/state-000000200.h5").string());
  EXPECT_EQ(s.step, 200);
  EXPECT_DOUBLE_EQ(s.time, 0.2);
  EXPECT_EQ(s.id, (std::vector<std::int64_t>{11, 13, 10, 12}));
  EXPECT_EQ(s.position[2], kBodies[0].x + Vec3(0.004, 0, 0));
  EXPECT_EQ(s.bounding_radius[0], 0.015);  // a ball: its radius
  // The clump: the far pebble's distance from the centre of mass plus its radius, as the model
  // that wrote the file has it.
  Particles clump;
  clump.add_clump(make_clump_template("c", {{Vec3(0, 0, 0), 0.02}, {Vec3(0.03, 0, 0), 0.015}}),
                  kBodies[3].x, Quat::Identity(), 0, 2800, 13);
  double bound = 0;
  for (int e = 0; e < clump.num_elements(); ++e)
    bound = std::max(bound, (clump.pos[e] - clump.x[0]).norm() + clump.radius[e]);
  EXPECT_NEAR(s.bounding_radius[1], bound, 1e-15);  // the same doubles, summed in one order
  EXPECT_GT(bound, 0.03);                           // more than either pebble alone
  ASSERT_EQ(s.mesh_position.size(), 1u);
  EXPECT_EQ(s.mesh_position[0], kSleeperStart + Vec3(0.005, 0, 0));
  EXPECT_EQ(read_snapshot_clock((run / "snapshots/state-000000100.h5").string()).step, 100);

  const fs::path foreign = run / "foreign.h5";
  std::ofstream(foreign) << "not HDF5\n";
  for (const fs::path& bad : {foreign, run / "missing.h5"}) {
    try {
      read_snapshot_bodies(bad.string());
      ADD_FAILURE() << "no error for " << bad;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(bad.string() + ": "), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("valid: "), std::string::npos) << e.what();
    }
  }
  fs::remove_all(run);
}

TEST(PilotZone, SelectsTheBodiesThatMovedWhenTheSleeperHadMoved) {
  const fs::path run = write_pilot_run("select");
  // Relative to the case folder; the run folder holds snapshots/.
  const ZonePtr zone = parse_zone("pilot(" + run.filename().string() + ", 0.004, 0.003, 0.01)",
                                  "case.prm: sample/clump zone", run.parent_path().string());
  const auto summaries = zone->pilot_summaries();
  ASSERT_EQ(summaries.size(), 1u);
  const PilotSummary& s = summaries[0];
  EXPECT_EQ(s.step, 200);  // 2.5 mm at step 100 is short of 4 mm
  EXPECT_EQ(s.sleeper_displacement, 0.005);
  EXPECT_EQ(s.selected_bodies, 2);  // ball 10 (4 mm) and the clump (10 mm); 2.9 mm is not > 3
  EXPECT_EQ(s.total_bodies, 4);
  EXPECT_EQ(fs::path(s.snapshot).filename(), "state-000000200.h5");

  const SnapshotBodies ref = read_snapshot_bodies((run / "snapshots/state-000000000.h5").string());
  const double dilation = 0.01;
  for (std::size_t b = 0; b < ref.id.size(); ++b) {
    const bool selected = ref.id[b] == 10 || ref.id[b] == 13;
    const double r = ref.bounding_radius[b] + dilation;
    // Spheres at the reference position, bounding radius + dilation, in every direction.
    for (const Vec3& dir : {Vec3(1, 0, 0), Vec3(0, -1, 0), Vec3(0, 0.6, 0.8)}) {
      EXPECT_EQ(zone->contains(ref.position[b] + (r - 1e-6) * dir), selected) << ref.id[b];
      EXPECT_FALSE(zone->contains(ref.position[b] + (r + 1e-6) * dir)) << ref.id[b];
    }
  }
  // Without dilation the zone shrinks to the bounding spheres.
  const ZonePtr tight =
      parse_zone("pilot(\"" + run.string() + "/snapshots\", 0.004, 0.003, 0)", "test", "");
  const Vec3 ball10 = kBodies[0].x;
  EXPECT_TRUE(tight->contains(ball10 + Vec3(0.02 - 1e-6, 0, 0)));
  EXPECT_FALSE(tight->contains(ball10 + Vec3(0.02 + 1e-6, 0, 0)));
  EXPECT_TRUE(zone->contains(ball10 + Vec3(0.02 + 1e-6, 0, 0)));

  // A smaller sleeper displacement picks the first snapshot that reaches it, with its movers.
  const auto early =
      parse_zone("pilot(" + run.string() + ", 0.002, 0.0005, 0)", "test", "")->pilot_summaries()[0];
  EXPECT_EQ(early.step, 100);
  EXPECT_EQ(early.sleeper_displacement, 0.0025);
  EXPECT_EQ(early.selected_bodies, 2);  // ball 10 (1 mm) and the clump (4 mm)

  // The canonical text names the resolved folder and reads back as the same zone.
  const ZonePtr back = parse(zone->to_string());
  EXPECT_EQ(back->to_string(), zone->to_string());
  EXPECT_EQ(back->pilot_summaries()[0].selected_bodies, 2);
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> ux(-0.05, 0.45), uyz(-0.05, 0.07);
  for (int i = 0; i < 2000; ++i) {
    const Vec3 x(ux(rng), uyz(rng), uyz(rng));
    ASSERT_EQ(zone->contains(x), back->contains(x)) << x.transpose();
  }
  // In an expression, the summaries come in text order.
  EXPECT_EQ(
      parse("all & " + zone->to_string() + " | " + tight->to_string())->pilot_summaries().size(),
      2u);
  fs::remove_all(run);
}

TEST(PilotZone, SnapshotsAreTakenInStepOrderNotNameOrder) {
  const fs::path run = write_pilot_run("order");
  // Renamed so that name order is not step order: the reference must be the step-0 file.
  fs::rename(run / "snapshots/state-000000000.h5", run / "snapshots/b.h5");
  fs::rename(run / "snapshots/state-000000200.h5", run / "snapshots/a.h5");
  fs::rename(run / "snapshots/state-000000100.h5", run / "snapshots/c.h5");
  const auto s =
      parse("pilot(" + run.string() + "/snapshots/*.h5, 0.004, 0.003, 0)")->pilot_summaries()[0];
  EXPECT_EQ(fs::path(s.snapshot).filename(), "a.h5");
  EXPECT_EQ(s.step, 200);
  EXPECT_EQ(s.selected_bodies, 2);
  // A pattern that matches one file leaves no displacement to measure.
  const std::string one = parse_error("pilot(" + run.string() + "/snapshots/b*, 0.004, 0, 0)");
  EXPECT_NE(one.find("pilot: 1 snapshot(s) found; valid: at least two"), std::string::npos) << one;
  EXPECT_NE(one.find("output/snapshot interval"), std::string::npos) << one;
  fs::remove_all(run);
}

TEST(PilotZone, ErrorsSayWhatWasFoundAndWhatIsValid) {
  const fs::path run = write_pilot_run("errors");
  const std::string base = run.parent_path().string(), name = run.filename().string();
  const std::string far = parse_error("all - pilot(" + name + ", 0.01, 0.003, 0)", base);
  EXPECT_NE(far.find("case.prm: sample/clump zone: character 7 of"), std::string::npos) << far;
  EXPECT_NE(far.find("pilot: the sleeper (first mesh body) moved at most 0.005 m (in " +
                     (run / "snapshots" / "state-000000200.h5").string() +
                     ") over the 3 snapshots; valid: a sleeper displacement up to 0.005 m"),
            std::string::npos)
      << far;
  EXPECT_NE(parse_error("pilot(no-such-run, 0.004, 0.003, 0)", base)
                .find("pilot: " + (run.parent_path() / "no-such-run").string() +
                      ": no such folder or file"),
            std::string::npos);
  EXPECT_NE(parse_error("pilot(" + name + ", 0, 0.003, 0)", base)
                .find("pilot: sleeper displacement 0 m; valid: a finite distance > 0"),
            std::string::npos);
  EXPECT_NE(parse_error("pilot(" + name + ", 0.004, -1, 0)", base).find("threshold -1 m"),
            std::string::npos);
  EXPECT_NE(parse_error("pilot(" + name + ", 0.004, 0.003, -0.01)", base).find("dilation -0.01"),
            std::string::npos);
  EXPECT_NE(parse_error("pilot(" + name + ", 0.004, 0.003)", base).find("takes 4 arguments, got 3"),
            std::string::npos);
  // A foreign file among the snapshots.
  std::ofstream(run / "snapshots" / "state-000000300.h5") << "not HDF5\n";
  EXPECT_NE(parse_error("pilot(" + name + ", 0.004, 0.003, 0)", base)
                .find("state-000000300.h5: cannot open as HDF5"),
            std::string::npos);
  fs::remove_all(run);
}

}  // namespace
}  // namespace trackbed::dem
