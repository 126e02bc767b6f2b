// Triangle-mesh walls: STL input, topology, mass properties, closest points, sphere-mesh contacts
// and the candidate grid (dem/engine/triangle_mesh.h).
#include "dem/engine/mesh_contact.h"
#include "dem/engine/triangle_grid.h"
#include "dem/engine/triangle_mesh.h"
#include "dem/io/stl_file.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>
#include "flat_grid.h"
#include "input_error_message.h"

namespace trackbed::dem {
namespace {

using testing::flat_grid;
namespace fs = std::filesystem;

// ---- helpers ----------------------------------------------------------------------------------

// A directory of its own per test, removed afterwards.
class TempDir {
 public:
  TempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = fs::temp_directory_path() / ("trackbed_mesh_" + std::to_string(::getpid()) + "_" +
                                         info->test_suite_name() + "_" + info->name());
    fs::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  std::string file(const std::string& name) const { return (path_ / name).string(); }

 private:
  fs::path path_;
};

void write_file(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out << bytes;
}

std::string facet_text(const Vec3& a, const Vec3& b, const Vec3& c) {
  std::ostringstream s;
  s.precision(17);
  s << "  facet normal 0 0 0\n    outer loop\n";
  for (const Vec3* v : {&a, &b, &c}) {
    s << "      vertex " << v->x() << " " << v->y() << " " << v->z() << "\n";
  }
  s << "    endloop\n  endfacet\n";
  return s.str();
}

// One ASCII solid per part of the mesh, each triangle written with its own three vertices (as
// STL does, so the reader has to merge them).
std::string ascii_stl_by_part(const TriangleMesh& mesh) {
  std::string text;
  for (std::size_t p = 0; p < mesh.part_names.size(); ++p) {
    text += "solid " + mesh.part_names[p] + "\n";
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
      if (mesh.triangle_part[t] != static_cast<int>(p)) continue;
      const auto& tri = mesh.triangles[t];
      text += facet_text(mesh.vertices[tri[0]], mesh.vertices[tri[1]], mesh.vertices[tri[2]]);
    }
    text += "endsolid " + mesh.part_names[p] + "\n";
  }
  return text;
}

void append_le32(std::string& s, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) s.push_back(static_cast<char>((v >> (8 * i)) & 0xff));
}

void append_float(std::string& s, float f) {
  std::uint32_t bits;
  std::memcpy(&bits, &f, 4);
  append_le32(s, bits);
}

std::string binary_stl(const TriangleMesh& mesh, const std::string& header_text) {
  std::string s = header_text;
  s.resize(80, ' ');
  append_le32(s, static_cast<std::uint32_t>(mesh.triangles.size()));
  for (const auto& tri : mesh.triangles) {
    for (int i = 0; i < 3; ++i) append_float(s, 0.0f);  // normal, ignored by the reader
    for (int v : tri) {
      for (int i = 0; i < 3; ++i) append_float(s, static_cast<float>(mesh.vertices[v][i]));
    }
    s.append(2, '\0');  // attribute byte count
  }
  return s;
}

using testing::contains;
using testing::input_error_message;

std::vector<int> all_triangles(const TriangleMesh& mesh) {
  std::vector<int> ids(mesh.triangles.size());
  for (std::size_t i = 0; i < ids.size(); ++i) ids[i] = static_cast<int>(i);
  return ids;
}

std::vector<MeshContactPoint> contacts(const TriangleMesh& mesh, const Vec3& centre,
                                       double radius) {
  const std::vector<int> ids = all_triangles(mesh);
  std::vector<MeshContactPoint> out;
  sphere_mesh_contacts(mesh, centre, radius, ids.data(), static_cast<int>(ids.size()), out);
  return out;
}

double segment_distance(const Vec3& p, const Vec3& a, const Vec3& b, Vec3* closest) {
  const double t = std::clamp((p - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
  *closest = a + t * (b - a);
  return (p - *closest).norm();
}

// ---- STL --------------------------------------------------------------------------------------

TEST(TriangleMeshStl, AsciiSingleSolidMergesRepeatedVertices) {
  TempDir dir;
  const TriangleMesh box = make_box_mesh(Vec3(0, 0, 0), Vec3(2.6, 0.3, 0.2), false);
  TriangleMesh renamed = box;
  renamed.part_names = {"cube"};
  const std::string path = dir.file("cube.stl");
  write_file(path, ascii_stl_by_part(renamed));

  const TriangleMesh mesh = read_stl(path);
  EXPECT_EQ(mesh.vertices.size(), 8u);  // 36 written
  EXPECT_EQ(mesh.triangles.size(), 12u);
  ASSERT_EQ(mesh.part_names, std::vector<std::string>{"cube"});
  EXPECT_TRUE(mesh.is_closed());
  EXPECT_NEAR(closed_mesh_mass_properties(mesh).volume, 2.6 * 0.3 * 0.2, 1e-15);
}

TEST(TriangleMeshStl, AsciiKeywordsAnyCaseAndCrLf) {
  TempDir dir;
  const std::string path = dir.file("tri.stl");
  write_file(path,
             "SOLID Plate\r\n FACET NORMAL 0 0 1\r\n  OUTER LOOP\r\n   VERTEX 0 0 0\r\n"
             "   VERTEX 1 0 0\r\n   VERTEX 0 1 0\r\n  ENDLOOP\r\n ENDFACET\r\nENDSOLID Plate\r\n");
  const TriangleMesh mesh = read_stl(path);
  ASSERT_EQ(mesh.triangles.size(), 1u);
  EXPECT_EQ(mesh.part_names, std::vector<std::string>{"Plate"});
  EXPECT_TRUE(mesh.triangle_normal(0).isApprox(Vec3(0, 0, 1), 1e-15));
}

TEST(TriangleMeshStl, MultipleSolidsBecomeParts) {
  TempDir dir;
  const TriangleMesh sleeper = make_box_mesh(Vec3(-1.3, -0.15, 0), Vec3(1.3, 0.15, 0.2), true);
  std::string text = ascii_stl_by_part(sleeper);
  // A nameless solid is named after the file; a repeated name joins the earlier part.
  text += "solid\n" + facet_text(Vec3(0, 0, 1), Vec3(1, 0, 1), Vec3(0, 1, 1)) + "endsolid\n";
  text +=
      "solid base\n" + facet_text(Vec3(0, 0, 2), Vec3(1, 0, 2), Vec3(0, 1, 2)) + "endsolid base\n";
  const std::string path = dir.file("sleeper.stl");
  write_file(path, text);

  const TriangleMesh mesh = read_stl(path);
  ASSERT_EQ(mesh.part_names, (std::vector<std::string>{"base", "top", "sides", "ends", "sleeper"}));
  std::vector<int> count(mesh.part_names.size(), 0);
  for (int p : mesh.triangle_part) ++count[p];
  EXPECT_EQ(count, (std::vector<int>{3, 2, 4, 4, 1}));
  // The base triangles are the two at z = 0 and the extra one at z = 2.
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    if (mesh.triangle_part[t] != 0) continue;
    const double z = mesh.vertices[mesh.triangles[t][0]].z();
    EXPECT_TRUE(z == 0.0 || z == 2.0);
  }
}

TEST(TriangleMeshStl, BinaryWithSolidHeaderIsDetectedBySize) {
  TempDir dir;
  const TriangleMesh box = make_box_mesh(Vec3(0, 0, 0), Vec3(0.5, 0.25, 0.125), true);
  const std::string path = dir.file("sleeper_base.stl");
  write_file(path, binary_stl(box, "solid this header only pretends to be ASCII"));

  const TriangleMesh mesh = read_stl(path);
  EXPECT_EQ(mesh.vertices.size(), 8u);
  EXPECT_EQ(mesh.triangles.size(), 12u);
  EXPECT_EQ(mesh.part_names, std::vector<std::string>{"sleeper_base"});
  EXPECT_TRUE(mesh.is_closed());
  // Coordinates exactly representable in float survive unchanged.
  EXPECT_DOUBLE_EQ(closed_mesh_mass_properties(mesh).volume, 0.5 * 0.25 * 0.125);
}

TEST(TriangleMeshStl, ErrorsNameFileLineAndWhatIsValid) {
  TempDir dir;
  const auto check = [&](const std::string& name, const std::string& bytes,
                         const std::string& expected_prefix, const std::string& expected_text) {
    const std::string path = dir.file(name);
    write_file(path, bytes);
    const std::string message = input_error_message([&] { read_stl(path); });
    EXPECT_EQ(message.rfind(path + expected_prefix, 0), 0u) << message;
    EXPECT_TRUE(contains(message, expected_text)) << message;
    EXPECT_FALSE(contains(message, "\n")) << message;
  };
  const std::string good_facet = facet_text(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0));

  // Malformed keyword on line 5 (facet on 2, outer loop on 3, first vertex on 4).
  check("typo.stl",
        "solid a\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertx 1 0 0\nvertex 0 1 0\n"
        "endloop\nendfacet\nendsolid a\n",
        ":5: ", "expected 'vertex'");
  check("number.stl", "solid a\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1.0abc 0 0\n",
        ":5: ", "a number");
  check("nan.stl",
        "solid a\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 nan 0\n"
        "endloop\nendfacet\nendsolid a\n",
        ":6: ", "not finite");
  check("unclosed.stl", "solid a\n" + good_facet, ":8: ", "endsolid");  // facet on lines 2-8
  check("trailing.stl", "solid a\n" + good_facet + "endsolid a\nhello\n",
        ":10: ", "expected 'solid NAME'");
  check("stray.stl", "solid a\n" + good_facet + "vertex 1 2 3\nendsolid a\n",
        ":9: ", "expected 'facet' or 'endsolid'");
  // Degenerate: the facet opening on line 9 has collinear vertices.
  check("degenerate.stl",
        "solid a\n" + good_facet + facet_text(Vec3(0, 0, 0), Vec3(1, 1, 1), Vec3(2, 2, 2)) +
            "endsolid a\n",
        ":9: ", "degenerate");
  check("empty_solid.stl", "solid a\nendsolid a\n", ": ", "no triangles");

  const TriangleMesh box = make_box_mesh(Vec3(0, 0, 0), Vec3(1, 1, 1), false);
  const std::string binary = binary_stl(box, "binary");
  check("truncated.stl", binary.substr(0, binary.size() - 10), ": ", "truncated");
  check("short.stl", std::string(40, '\x01'), ": ", "too short");
  check("zero.stl", binary.substr(0, 80) + std::string(4, '\0'), ": ", "no triangles");
  std::string nan_binary = binary;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::memcpy(&nan_binary[84 + 50 * 3 + 12 + 4], &nan, 4);  // facet 3, first vertex, y
  check("nan_binary.stl", nan_binary, ": binary facet 3", "non-finite");

  const std::string missing = dir.file("missing.stl");
  const std::string message = input_error_message([&] { read_stl(missing); });
  EXPECT_EQ(message.rfind(missing + ": ", 0), 0u) << message;
  EXPECT_TRUE(contains(message, "no such STL file")) << message;
}

// ---- topology ---------------------------------------------------------------------------------

TEST(TriangleMeshTopology, MergesVerticesWithinToleranceOnly) {
  // Two triangles sharing an edge; the second repeats the shared vertices, perturbed by delta on a
  // mesh of size about 1.4 (merging tolerance 1.4e-6).
  const auto two_triangles = [](double delta) {
    TriangleMesh mesh;
    mesh.vertices = {Vec3(0, 0, 0),         Vec3(1, 0, 0), Vec3(0, 1, 0),
                     Vec3(1 + delta, 0, 0), Vec3(1, 1, 0), Vec3(0, 1 - delta, delta)};
    mesh.triangles = {{0, 1, 2}, {3, 4, 5}};
    mesh.finalize();
    return mesh;
  };
  const TriangleMesh merged = two_triangles(1e-9);
  EXPECT_EQ(merged.vertices.size(), 4u);
  EXPECT_EQ(merged.num_edges, 5);
  EXPECT_EQ(merged.triangles[1], (std::array<int, 3>{1, 3, 2}));  // first occurrence kept
  EXPECT_EQ(merged.vertices[1], Vec3(1, 0, 0));

  const TriangleMesh apart = two_triangles(1e-4);
  EXPECT_EQ(apart.vertices.size(), 6u);
  EXPECT_EQ(apart.num_edges, 6);
}

TEST(TriangleMeshTopology, BoxEdgesAndAdjacency) {
  const TriangleMesh box = make_box_mesh(Vec3(0, 0, 0), Vec3(1, 2, 3), true);
  EXPECT_EQ(box.num_edges, 18);  // 12 box edges and 6 face diagonals
  for (int e = 0; e < box.num_edges; ++e) {
    EXPECT_EQ(box.edge_triangle_offsets[e + 1] - box.edge_triangle_offsets[e], 2);
    EXPECT_LT(box.edge_vertices[e][0], box.edge_vertices[e][1]);
  }
  EXPECT_EQ(box.vertex_edges.size(), 36u);
  for (std::size_t t = 0; t < box.triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const auto& ev = box.edge_vertices[box.triangle_edges[t][k]];
      const int a = box.triangles[t][k], b = box.triangles[t][(k + 1) % 3];
      EXPECT_EQ(ev[0], std::min(a, b));
      EXPECT_EQ(ev[1], std::max(a, b));
    }
  }
  // Outward normals: part "base" faces -z, "ends" face +-x.
  for (std::size_t t = 0; t < box.triangles.size(); ++t) {
    const Vec3 n = box.triangle_normal(static_cast<int>(t));
    const std::string& part = box.part_names[box.triangle_part[t]];
    if (part == "base") EXPECT_TRUE(n.isApprox(Vec3(0, 0, -1)));
    if (part == "top") EXPECT_TRUE(n.isApprox(Vec3(0, 0, 1)));
    if (part == "sides") EXPECT_NEAR(std::abs(n.y()), 1.0, 1e-15);
    if (part == "ends") EXPECT_NEAR(std::abs(n.x()), 1.0, 1e-15);
  }
}

TEST(TriangleMeshTopology, IsClosed) {
  const TriangleMesh box = make_box_mesh(Vec3(0, 0, 0), Vec3(1, 1, 1), false);
  EXPECT_TRUE(box.is_closed());

  TriangleMesh open = box;
  open.triangles.pop_back();
  open.triangle_part.pop_back();
  open.finalize();
  EXPECT_FALSE(open.is_closed());

  TriangleMesh flipped = box;
  std::swap(flipped.triangles[5][1], flipped.triangles[5][2]);
  flipped.finalize();
  EXPECT_FALSE(flipped.is_closed());

  TriangleMesh fin = box;  // a third triangle on a box edge: not a 2-manifold
  fin.vertices.emplace_back(0.5, -1.0, -1.0);
  fin.triangles.push_back({0, 1, 8});
  fin.triangle_part.push_back(0);
  fin.finalize();
  EXPECT_FALSE(fin.is_closed());

  EXPECT_FALSE(flat_grid(2, false).is_closed());
}

TEST(TriangleMeshTopology, RefusesDegenerateTriangle) {
  TriangleMesh mesh;
  mesh.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(2, 0, 0)};
  mesh.triangles = {{0, 1, 2}, {0, 1, 3}};
  try {
    mesh.finalize();
    FAIL() << "degenerate triangle accepted";
  } catch (const DegenerateTriangleError& e) {
    EXPECT_EQ(e.triangle(), 1);
    EXPECT_TRUE(contains(e.what(), "triangle 1 (part 'mesh') is degenerate")) << e.what();
  }
}

TEST(TriangleMeshTopology, TransformsKeepTopology) {
  TriangleMesh box = make_box_mesh(Vec3(0, 0, 0), Vec3(1, 2, 3), true);
  const auto edges = box.triangle_edges;
  const Mat3 r = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  box.translate(Vec3(5, -1, 2));
  box.rotate(r, Vec3(1, 1, 1));
  box.scale(2.0, Vec3(0, 0, 0));
  EXPECT_EQ(box.triangle_edges, edges);
  EXPECT_TRUE(box.is_closed());
  const MeshMassProperties mp = closed_mesh_mass_properties(box);
  EXPECT_NEAR(mp.volume, 6.0 * 8.0, 1e-12);
  const Vec3 centroid = 2.0 * (Vec3(1, 1, 1) + r * (Vec3(5.5, 0, 3.5) - Vec3(1, 1, 1)));
  EXPECT_LT((mp.centroid - centroid).norm(), 1e-12);
}

// ---- mass properties --------------------------------------------------------------------------

TEST(TriangleMeshMass, BoxMatchesAnalytic) {
  const Vec3 lower(1, -1, 0.2), upper(3, 0.5, 0.7);
  const Vec3 size = upper - lower;
  const MeshMassProperties mp = closed_mesh_mass_properties(make_box_mesh(lower, upper, true));
  const double v = size.prod();
  EXPECT_NEAR(mp.volume, v, 1e-14);
  EXPECT_LT((mp.centroid - 0.5 * (lower + upper)).norm(), 1e-14);
  const Vec3 sq = size.cwiseProduct(size);
  Mat3 expected = Mat3::Zero();
  expected.diagonal() = v / 12.0 * Vec3(sq.y() + sq.z(), sq.x() + sq.z(), sq.x() + sq.y());
  EXPECT_LT((mp.inertia - expected).norm(), 1e-14);
}

TEST(TriangleMeshMass, RotatedBoxFarFromOriginMatchesAnalytic) {
  TriangleMesh box = make_box_mesh(Vec3(0, 0, 0), Vec3(2.6, 0.3, 0.2), false);
  const Mat3 r = Eigen::AngleAxisd(0.4, Vec3(0.2, -1, 0.5).normalized()).toRotationMatrix();
  box.rotate(r, Vec3(0, 0, 0));
  box.translate(Vec3(1000, -2000, 300));
  const MeshMassProperties mp = closed_mesh_mass_properties(box);
  const double v = 2.6 * 0.3 * 0.2;
  Mat3 local = Mat3::Zero();
  local.diagonal() = v / 12.0 * Vec3(0.09 + 0.04, 6.76 + 0.04, 6.76 + 0.09);
  const Mat3 expected = r * local * r.transpose();
  // Integration about the bounding-box centre keeps the error at rounding of the box size.
  EXPECT_NEAR(mp.volume, v, 1e-13);
  EXPECT_LT((mp.centroid - (r * Vec3(1.3, 0.15, 0.1) + Vec3(1000, -2000, 300))).norm(), 1e-11);
  EXPECT_LT((mp.inertia - expected).norm(), 1e-13);
}

TEST(TriangleMeshMass, RefusesOpenOrInvertedMesh) {
  TriangleMesh open = make_box_mesh(Vec3(0, 0, 0), Vec3(1, 1, 1), false);
  open.triangles.pop_back();
  open.triangle_part.pop_back();
  open.finalize();
  EXPECT_TRUE(
      contains(input_error_message([&] { closed_mesh_mass_properties(open); }), "closed mesh"));

  TriangleMesh inverted = make_box_mesh(Vec3(0, 0, 0), Vec3(1, 1, 1), false);
  for (auto& tri : inverted.triangles) std::swap(tri[1], tri[2]);
  inverted.finalize();
  EXPECT_TRUE(contains(input_error_message([&] { closed_mesh_mass_properties(inverted); }),
                       "outward normals"));
}

// ---- closest point ----------------------------------------------------------------------------

TEST(TriangleMeshClosestPoint, MatchesExactReferenceAndDenseSampling) {
  // An obtuse triangle, so that all seven Voronoi regions have room.
  const Vec3 a(0.1, -0.2, 0.3), b(1.3, 0.1, 0.0), c(-0.4, 0.6, 0.5);
  const Vec3 n = (b - a).cross(c - a).normalized();
  const std::array<const Vec3*, 3> vtx = {&a, &b, &c};

  // Dense sampling of the triangle: a closest point is within spacing * longest edge of a sample.
  const int m = 300;
  std::vector<Vec3> samples;
  for (int i = 0; i <= m; ++i) {
    for (int j = 0; i + j <= m; ++j) samples.push_back(a + (b - a) * i / m + (c - a) * j / m);
  }
  const double spacing = std::max({(b - a).norm(), (c - a).norm()}) / m;

  int counts[3] = {0, 0, 0};
  const int g = 9;
  for (int i = 0; i < g; ++i) {
    for (int j = 0; j < g; ++j) {
      for (int k = 0; k < 5; ++k) {
        const Vec3 p =
            Vec3(-1.0 + 3.0 * i / (g - 1), -1.0 + 2.2 * j / (g - 1), 0.0) + (k - 2) * 0.35 * n;
        const TriangleClosestPoint cp = closest_point_on_triangle(p, a, b, c);
        ++counts[static_cast<int>(cp.feature)];

        // Exact reference: the projection if inside, else the best of the three edges.
        const Vec3 q = p - (p - a).dot(n) * n;
        const bool inside = (b - a).cross(q - a).dot(n) >= 0 && (c - b).cross(q - b).dot(n) >= 0 &&
                            (a - c).cross(q - c).dot(n) >= 0;
        Vec3 reference = q;
        if (!inside) {
          double best = std::numeric_limits<double>::infinity();
          for (int e = 0; e < 3; ++e) {
            Vec3 x;
            const double d = segment_distance(p, *vtx[e], *vtx[(e + 1) % 3], &x);
            if (d < best) best = d, reference = x;
          }
        }
        EXPECT_LT((cp.point - reference).norm(), 1e-12) << p.transpose();
        const Vec3 from_weights =
            cp.barycentric.x() * a + cp.barycentric.y() * b + cp.barycentric.z() * c;
        EXPECT_LT((from_weights - cp.point).norm(), 1e-12);

        double sampled = std::numeric_limits<double>::infinity();
        for (const Vec3& s : samples) sampled = std::min(sampled, (p - s).norm());
        const double distance = (p - cp.point).norm();
        EXPECT_LE(distance, sampled + 1e-12);
        EXPECT_LE(sampled, distance + spacing);

        // The feature holds the point: a vertex is the point, an edge's segment contains it and
        // the opposite weight is zero, a face has all weights positive.
        const Vec3& w = cp.barycentric;
        switch (cp.feature) {
          case MeshFeature::Vertex:
            EXPECT_EQ(cp.point, *vtx[cp.local_id]);
            break;
          case MeshFeature::Edge:
            EXPECT_EQ(w[(cp.local_id + 2) % 3], 0.0);
            EXPECT_GT(w[cp.local_id], 0.0);
            EXPECT_GT(w[(cp.local_id + 1) % 3], 0.0);
            break;
          case MeshFeature::Face:
            EXPECT_GT(w.minCoeff(), 0.0);
            EXPECT_TRUE(inside);
            break;
        }
      }
    }
  }
  for (int f = 0; f < 3; ++f) EXPECT_GT(counts[f], 0) << "feature " << f << " never tested";
}

// ---- sphere-mesh contacts ---------------------------------------------------------------------

// On a flat mesh, wherever the sphere is (over a face, exactly over an edge or a vertex, either
// side), there is exactly one contact and it is the plane contact.
void check_flat_mesh(const TriangleMesh& grid, const Mat3& rotation, const Vec3& shift) {
  TriangleMesh mesh = grid;
  mesh.rotate(rotation, Vec3::Zero());
  mesh.translate(shift);
  const Vec3 normal = rotation * Vec3::UnitZ();
  const double radius = 0.7;  // larger than half a cell, so the sphere spans many triangles

  std::vector<Vec3> in_plane;  // (u, v) in the grid's own coordinates, within [0, 4]^2
  for (const Vec3& v : grid.vertices) in_plane.push_back(v);
  for (const auto& ev : grid.edge_vertices) {
    const Vec3& a = grid.vertices[ev[0]];
    const Vec3& b = grid.vertices[ev[1]];
    for (double t : {0.5, 0.1, 0.37, 1e-13, 1.0 - 1e-9}) in_plane.push_back(a + t * (b - a));
  }
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int i = 0; i < 200; ++i) in_plane.emplace_back(4.0 * unit(rng), 4.0 * unit(rng), 0.0);
  for (const Vec3& v : grid.vertices) {  // a hair away from vertices, in every direction
    for (int i = 0; i < 8; ++i) {
      const double angle = 0.25 * M_PI * i + 0.1;
      const Vec3 p = v + 1e-10 * Vec3(std::cos(angle), std::sin(angle), 0.0);
      if (p.x() >= 0 && p.x() <= 4 && p.y() >= 0 && p.y() <= 4) in_plane.push_back(p);
    }
  }

  TriangleGrid triangle_grid;
  triangle_grid.build(mesh, 0.5);
  std::vector<int> candidates;
  std::vector<MeshContactPoint> out;
  for (const Vec3& uv : in_plane) {
    for (double h : {0.3, -0.45, 0.05 + 0.6 * unit(rng)}) {
      const Vec3 foot = shift + rotation * uv;
      const Vec3 centre = foot + h * normal;
      triangle_grid.query(centre, radius, candidates);
      sphere_mesh_contacts(mesh, centre, radius, candidates.data(),
                           static_cast<int>(candidates.size()), out);
      ASSERT_EQ(out.size(), 1u) << "at (" << uv.transpose() << "), height " << h;
      EXPECT_NEAR(out[0].overlap, radius - std::abs(h), 1e-12);
      EXPECT_LT((out[0].normal - (h > 0 ? normal : Vec3(-normal))).norm(), 1e-12);
      EXPECT_LT((out[0].point - foot).norm(), 1e-12);
    }
  }
}

TEST(TriangleMeshContacts, FlatMeshIsOnePlaneContact) {
  const Mat3 tilt = Eigen::AngleAxisd(0.3, Vec3(1, -2, 0.5).normalized()).toRotationMatrix();
  for (bool alternating : {false, true}) {  // vertices of 6 triangles; of 4 and 8
    const TriangleMesh grid = flat_grid(4, alternating);
    ASSERT_EQ(grid.triangles.size(), 32u);
    check_flat_mesh(grid, Mat3::Identity(), Vec3::Zero());
    check_flat_mesh(grid, tilt, Vec3(0.3, -0.2, 0.1));
  }
}

// A roof: two planes meeting at a convex ridge along y (x = 0, z = 0), sloping down by 0.5 per
// unit.
TriangleMesh roof() {
  TriangleMesh mesh;
  mesh.vertices = {Vec3(0, -1, 0),    Vec3(0, 1, 0),     Vec3(-1, -1, -0.5),
                   Vec3(-1, 1, -0.5), Vec3(1, -1, -0.5), Vec3(1, 1, -0.5)};
  mesh.triangles = {{0, 1, 3}, {0, 3, 2}, {0, 4, 5}, {0, 5, 1}};
  mesh.finalize();
  return mesh;
}

TEST(TriangleMeshContacts, ConvexEdgeGivesOneContact) {
  const TriangleMesh mesh = roof();
  const double radius = 0.5;
  // Over the ridge, outside both faces' prisms: one edge contact straight down to the ridge.
  const auto at_ridge = contacts(mesh, Vec3(0.0, 0.2, 0.3), radius);
  ASSERT_EQ(at_ridge.size(), 1u);
  EXPECT_EQ(at_ridge[0].feature, MeshFeature::Edge);
  EXPECT_LT((at_ridge[0].point - Vec3(0, 0.2, 0)).norm(), 1e-15);
  EXPECT_LT((at_ridge[0].normal - Vec3(0, 0, 1)).norm(), 1e-15);
  EXPECT_NEAR(at_ridge[0].overlap, 0.2, 1e-15);

  // Sweep across the ridge, through the region boundaries, even exactly on them: always one.
  const Vec3 n_left = Vec3(-0.5, 0, 1).normalized();
  for (int i = -40; i <= 40; ++i) {
    const Vec3 centre(0.02 * i, 0.3, 0.3 - 0.01 * std::abs(i));
    EXPECT_EQ(contacts(mesh, centre, radius).size(), 1u) << centre.transpose();
  }
  for (double d : {0.1, 0.3, 0.45}) {  // exactly on the boundary of the left face's region
    const auto out = contacts(mesh, Vec3(0, -0.1, 0) + d * n_left, radius);
    ASSERT_EQ(out.size(), 1u);
    EXPECT_NEAR(out[0].overlap, radius - d, 1e-15);
    EXPECT_LT((out[0].normal - n_left).norm(), 1e-15);
  }
  // Over the left face: one face contact with its normal.
  const auto on_face = contacts(mesh, Vec3(-0.4, 0.0, -0.2) + 0.3 * n_left, radius);
  ASSERT_EQ(on_face.size(), 1u);
  EXPECT_EQ(on_face[0].feature, MeshFeature::Face);
  EXPECT_LT((on_face[0].normal - n_left).norm(), 1e-15);
}

TEST(TriangleMeshContacts, BoxEdgesAndCornersGiveOneContact) {
  const TriangleMesh box = make_box_mesh(Vec3(0, 0, 0), Vec3(1, 1, 1), true);
  const auto corner = contacts(box, Vec3(1.2, 1.2, 1.2), 0.5);
  ASSERT_EQ(corner.size(), 1u);
  EXPECT_EQ(corner[0].feature, MeshFeature::Vertex);
  EXPECT_LT((corner[0].normal - Vec3(1, 1, 1).normalized()).norm(), 1e-15);
  EXPECT_NEAR(corner[0].overlap, 0.5 - std::sqrt(3 * 0.04), 1e-15);

  const auto edge = contacts(box, Vec3(0.3, -0.2, 1.2), 0.5);
  ASSERT_EQ(edge.size(), 1u);
  EXPECT_EQ(edge[0].feature, MeshFeature::Edge);
  EXPECT_LT((edge[0].point - Vec3(0.3, 0, 1)).norm(), 1e-15);

  // Exactly over the box's face diagonals and their ends (the corners): still one contact each.
  for (const Vec3& centre : {Vec3(0.5, 0.5, 1.3), Vec3(0.25, 0.25, 1.3), Vec3(1, 1, 1.3),
                             Vec3(0, 0, 1.3), Vec3(0.5, 1.0, 1.3), Vec3(1.0, 0.5, 1.3)}) {
    const auto out = contacts(box, centre, 0.5);
    ASSERT_EQ(out.size(), 1u) << centre.transpose();
    EXPECT_LT((out[0].normal - Vec3(0, 0, 1)).norm(), 1e-15);
    EXPECT_NEAR(out[0].overlap, 0.2, 1e-15);
  }
}

TEST(TriangleMeshContacts, ConcaveCornerGivesOneContactPerFace) {
  // A floor (z = 0, x in [0, 2]) and a wall (x = 0, z in [0, 2]) meeting at a concave edge.
  TriangleMesh corner;
  corner.vertices = {Vec3(0, -1, 0), Vec3(0, 1, 0),  Vec3(2, -1, 0),
                     Vec3(2, 1, 0),  Vec3(0, -1, 2), Vec3(0, 1, 2)};
  corner.triangles = {{0, 2, 3}, {0, 3, 1}, {0, 1, 5}, {0, 5, 4}};
  corner.finalize();
  const auto two = contacts(corner, Vec3(0.3, 0.0, 0.4), 0.5);
  ASSERT_EQ(two.size(), 2u);
  for (const MeshContactPoint& c : two) {
    EXPECT_EQ(c.feature, MeshFeature::Face);
    if (c.normal.z() > 0.5) {
      EXPECT_LT((c.normal - Vec3(0, 0, 1)).norm(), 1e-15);
      EXPECT_NEAR(c.overlap, 0.1, 1e-15);
    } else {
      EXPECT_LT((c.normal - Vec3(1, 0, 0)).norm(), 1e-15);
      EXPECT_NEAR(c.overlap, 0.2, 1e-15);
    }
  }
  // Touching the floor only, even over the floor's diagonal: one.
  EXPECT_EQ(contacts(corner, Vec3(1.0, 0.0, 0.4), 0.5).size(), 1u);
  EXPECT_EQ(contacts(corner, Vec3(1.0, 0.0, 0.4), 0.5)[0].feature, MeshFeature::Face);

  // Inside a closed box near a corner, two-sided contacts: one per face, normals pointing inward.
  const TriangleMesh box = make_box_mesh(Vec3(0, 0, 0), Vec3(2, 2, 2), false);
  const auto three = contacts(box, Vec3(0.3, 0.35, 0.4), 0.5);
  ASSERT_EQ(three.size(), 3u);
  Vec3 sum = Vec3::Zero();
  double overlap = 0;
  for (const MeshContactPoint& c : three) {
    EXPECT_EQ(c.feature, MeshFeature::Face);
    sum += c.normal;
    overlap += c.overlap;
  }
  EXPECT_LT((sum - Vec3(1, 1, 1)).norm(), 1e-15);
  EXPECT_NEAR(overlap, 0.2 + 0.15 + 0.1, 1e-15);
}

TEST(TriangleMeshContacts, NoContactOutsideRadiusAndNoGrowthOnReuse) {
  const TriangleMesh box = make_box_mesh(Vec3(0, 0, 0), Vec3(1, 1, 1), false);
  EXPECT_TRUE(contacts(box, Vec3(0.5, 0.5, 1.5), 0.5).empty());  // touching, zero overlap
  const std::vector<int> ids = all_triangles(box);
  std::vector<MeshContactPoint> out;
  // Inside, near three faces; the y = 0 face's diagonal passes under the centre, so its two
  // triangles and the diagonal all report the same point before merging.
  const Vec3 centre(0.8, 0.25, 0.2);
  sphere_mesh_contacts(box, centre, 0.3, ids.data(), 12, out);
  ASSERT_EQ(out.size(), 3u);
  const MeshContactPoint* data = out.data();
  for (int repeat = 0; repeat < 3; ++repeat) {
    sphere_mesh_contacts(box, centre, 0.3, ids.data(), 12, out);
    EXPECT_EQ(out.size(), 3u);
    EXPECT_EQ(out.data(), data);  // out's storage reused
  }
}

// ---- candidate grid ---------------------------------------------------------------------------

TEST(TriangleMeshGrid, QueryEqualsBruteForce) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  TriangleMesh mesh = flat_grid(10, true);  // 200 triangles in z = 0, x and y in [0, 10]
  for (int i = 0; i < 300; ++i) {           // and 300 small random ones above it
    const Vec3 base(10 * unit(rng), 10 * unit(rng), 5 * unit(rng));
    const int v = static_cast<int>(mesh.vertices.size());
    mesh.vertices.push_back(base);
    mesh.vertices.push_back(base + Vec3(unit(rng), unit(rng), unit(rng)) * 0.8);
    mesh.vertices.push_back(base + Vec3(-unit(rng), unit(rng), -unit(rng)) * 0.8);
    mesh.triangles.push_back({v, v + 1, v + 2});
  }
  mesh.triangle_part.clear();
  mesh.finalize();

  TriangleGrid grid;
  grid.build(mesh, 0.37);
  std::vector<int> found;
  std::vector<MeshContactPoint> from_grid, from_all;
  const std::vector<int> ids = all_triangles(mesh);
  for (int q = 0; q < 500; ++q) {
    const Vec3 centre(-1 + 12 * unit(rng), -1 + 12 * unit(rng), -1 + 7 * unit(rng));
    const double radius = 0.01 + 1.5 * unit(rng);
    grid.query(centre, radius, found);

    std::vector<int> expected;
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
      const auto& tri = mesh.triangles[t];
      const Vec3 lo =
          mesh.vertices[tri[0]].cwiseMin(mesh.vertices[tri[1]]).cwiseMin(mesh.vertices[tri[2]]);
      const Vec3 hi =
          mesh.vertices[tri[0]].cwiseMax(mesh.vertices[tri[1]]).cwiseMax(mesh.vertices[tri[2]]);
      if ((lo - centre).cwiseMax(centre - hi).cwiseMax(0.0).squaredNorm() <= radius * radius) {
        expected.push_back(static_cast<int>(t));
      }
      // Every triangle closer than the radius is a candidate.
      const TriangleClosestPoint cp = closest_point_on_triangle(
          centre, mesh.vertices[tri[0]], mesh.vertices[tri[1]], mesh.vertices[tri[2]]);
      if ((cp.point - centre).norm() < radius) {
        EXPECT_TRUE(std::binary_search(found.begin(), found.end(), static_cast<int>(t)));
      }
    }
    ASSERT_EQ(found, expected) << "query " << q;

    sphere_mesh_contacts(mesh, centre, radius, found.data(), static_cast<int>(found.size()),
                         from_grid);
    sphere_mesh_contacts(mesh, centre, radius, ids.data(), static_cast<int>(ids.size()), from_all);
    ASSERT_EQ(from_grid.size(), from_all.size());
    for (std::size_t i = 0; i < from_grid.size(); ++i) {
      EXPECT_EQ(from_grid[i].feature, from_all[i].feature);
      EXPECT_EQ(from_grid[i].feature_id, from_all[i].feature_id);
    }
  }
  grid.query(Vec3(50, 50, 50), 1.0, found);
  EXPECT_TRUE(found.empty());
}

}  // namespace
}  // namespace trackbed::dem
