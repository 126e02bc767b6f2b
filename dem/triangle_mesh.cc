#include "dem/triangle_mesh.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string_view>
#include <tuple>
#include <unordered_map>

namespace trackbed::dem {

namespace {

std::string format_double(double value) {
  std::ostringstream s;
  s.precision(6);
  s << value;
  return s.str();
}

// ---- vertex merging -------------------------------------------------------------------------

struct CellKey {
  std::int64_t x, y, z;
  bool operator==(const CellKey& o) const { return x == o.x && y == o.y && z == o.z; }
};

struct CellKeyHash {
  std::size_t operator()(const CellKey& k) const {
    std::uint64_t h = static_cast<std::uint64_t>(k.x) * 0x9E3779B97F4A7C15ull;
    h ^= static_cast<std::uint64_t>(k.y) * 0xC2B2AE3D27D4EB4Full + (h << 6) + (h >> 2);
    h ^= static_cast<std::uint64_t>(k.z) * 0x165667B19E3779F9ull + (h << 6) + (h >> 2);
    return static_cast<std::size_t>(h);
  }
};

// Maps every vertex to the first earlier vertex within tol (a hash grid of cell tol, so only the
// 27 neighbouring cells are searched) and writes the distinct vertices to merged. A vertex is
// compared with representatives only, so the result does not depend on chains of near points.
void merge_close_vertices(const std::vector<Vec3>& vertices, double tol, std::vector<int>& new_id,
                          std::vector<Vec3>& merged) {
  const int n = static_cast<int>(vertices.size());
  new_id.assign(n, -1);
  merged.clear();
  if (!(tol > 0.0)) {  // a zero-size mesh: all its vertices are one point
    if (n > 0) merged.push_back(vertices[0]);
    new_id.assign(n, 0);
    return;
  }
  std::unordered_map<CellKey, std::vector<int>, CellKeyHash> cells;
  cells.reserve(vertices.size());
  const double tol2 = tol * tol;
  for (int i = 0; i < n; ++i) {
    const Vec3& v = vertices[i];
    const CellKey key{static_cast<std::int64_t>(std::floor(v.x() / tol)),
                      static_cast<std::int64_t>(std::floor(v.y() / tol)),
                      static_cast<std::int64_t>(std::floor(v.z() / tol))};
    int found = -1;
    for (int dx = -1; dx <= 1 && found < 0; ++dx) {
      for (int dy = -1; dy <= 1 && found < 0; ++dy) {
        for (int dz = -1; dz <= 1 && found < 0; ++dz) {
          const auto it = cells.find(CellKey{key.x + dx, key.y + dy, key.z + dz});
          if (it == cells.end()) continue;
          for (int rep : it->second) {
            if ((merged[rep] - v).squaredNorm() <= tol2) {
              found = rep;
              break;
            }
          }
        }
      }
    }
    if (found < 0) {
      found = static_cast<int>(merged.size());
      merged.push_back(v);
      cells[key].push_back(found);
    }
    new_id[i] = found;
  }
}

// ---- contact predicates ---------------------------------------------------------------------

// Regions are closed and widened by this much (a barycentric weight, or an edge parameter) so
// that rounding, about 1e-16 times (radius + edge) / height, never opens a gap between the
// region of a face and that of its edge or vertex: a point on a shared boundary then belongs to
// both features, and the duplicate is merged by position (kMergeRadius, kMergeEdge).
constexpr double kRegionSlack = 1e-12;
// Two contacts closer than kMergeRadius * radius + kMergeEdge * (longest edges of their
// triangles) are the same contact. This is 100 times the widening above and 1e7 times the
// rounding of closest points at coordinates of 100 radii, yet two genuine contacts are only this
// close when the centre lies within 1e-9 radii of a concave crease.
constexpr double kMergeRadius = 1e-9;
constexpr double kMergeEdge = 1e-10;

// Barycentric weight of the vertex opposite local edge k of triangle t at the projection of p
// onto the triangle's plane: positive on the triangle's side of the edge's line.
double opposite_weight(const TriangleMesh& mesh, int t, int k, const Vec3& p) {
  const auto& tri = mesh.triangles[t];
  const Vec3& v0 = mesh.vertices[tri[0]];
  const Vec3 n = (mesh.vertices[tri[1]] - v0).cross(mesh.vertices[tri[2]] - v0);
  const Vec3& a = mesh.vertices[tri[k]];
  const Vec3& b = mesh.vertices[tri[(k + 1) % 3]];
  return (p - a).dot(n.cross(b - a)) / n.squaredNorm();
}

// Parameter of the projection of p onto the line of edge e, 0 at its lower-id vertex, 1 at the
// other. Always computed from the edge alone, so every triangle and vertex sees the same value.
double edge_parameter(const TriangleMesh& mesh, int e, const Vec3& p) {
  const Vec3& lo = mesh.vertices[mesh.edge_vertices[e][0]];
  const Vec3 d = mesh.vertices[mesh.edge_vertices[e][1]] - lo;
  return (p - lo).dot(d) / d.squaredNorm();
}

int local_edge_index(const TriangleMesh& mesh, int t, int e) {
  const auto& te = mesh.triangle_edges[t];
  return te[0] == e ? 0 : (te[1] == e ? 1 : 2);
}

bool edge_region_contains(const TriangleMesh& mesh, int e, double t, const Vec3& p) {
  if (t < -kRegionSlack || t > 1.0 + kRegionSlack) return false;
  for (int i = mesh.edge_triangle_offsets[e]; i < mesh.edge_triangle_offsets[e + 1]; ++i) {
    const int tri = mesh.edge_triangles[i];
    if (opposite_weight(mesh, tri, local_edge_index(mesh, tri, e), p) > kRegionSlack) {
      return false;
    }
  }
  return true;
}

bool vertex_region_contains(const TriangleMesh& mesh, int v, const Vec3& p) {
  for (int i = mesh.vertex_edge_offsets[v]; i < mesh.vertex_edge_offsets[v + 1]; ++i) {
    const int e = mesh.vertex_edges[i];
    const double t = edge_parameter(mesh, e, p);
    const bool behind = mesh.edge_vertices[e][0] == v ? t <= kRegionSlack : t >= 1.0 - kRegionSlack;
    if (!behind) return false;
  }
  return true;
}

bool has_feature(const std::vector<MeshContactPoint>& out, MeshFeature feature, int id) {
  for (const MeshContactPoint& c : out) {
    if (c.feature == feature && c.feature_id == id) return true;
  }
  return false;
}

double longest_edge(const TriangleMesh& mesh, int t) {
  const auto& tri = mesh.triangles[t];
  const Vec3& a = mesh.vertices[tri[0]];
  const Vec3& b = mesh.vertices[tri[1]];
  const Vec3& c = mesh.vertices[tri[2]];
  return std::sqrt(std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()}));
}

// Direction from point to centre; at zero distance (centre on the mesh) the outward normal of the
// triangle, the only direction left that is defined.
Vec3 contact_direction(const TriangleMesh& mesh, int t, const Vec3& from_point, double distance) {
  if (distance > 0.0) return from_point / distance;
  return mesh.triangle_normal(t);
}

// ---- STL ------------------------------------------------------------------------------------

std::uint32_t read_le32(const char* bytes) {
  const auto* u = reinterpret_cast<const unsigned char*>(bytes);
  return static_cast<std::uint32_t>(u[0]) | (static_cast<std::uint32_t>(u[1]) << 8) |
         (static_cast<std::uint32_t>(u[2]) << 16) | (static_cast<std::uint32_t>(u[3]) << 24);
}

float read_le_float(const char* bytes) {
  static_assert(std::numeric_limits<float>::is_iec559, "binary STL stores IEEE 754 floats");
  const std::uint32_t bits = read_le32(bytes);
  float value;
  std::memcpy(&value, &bits, sizeof value);
  return value;
}

bool iequals(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (std::tolower(static_cast<unsigned char>(a[i])) !=
        std::tolower(static_cast<unsigned char>(b[i]))) {
      return false;
    }
  }
  return true;
}

bool is_space(char c) {
  return std::isspace(static_cast<unsigned char>(c)) != 0;
}

// Whitespace-separated tokens of an ASCII STL text with their line numbers.
class StlLexer {
 public:
  explicit StlLexer(const std::string& text) : text_(text) {}

  bool next(std::string_view& token) {
    while (pos_ < text_.size() && is_space(text_[pos_])) {
      if (text_[pos_] == '\n') ++line_;
      ++pos_;
    }
    // At the end the line stays that of the last token: the place to add what is missing.
    if (pos_ == text_.size()) return false;
    token_line_ = line_;
    const std::size_t start = pos_;
    while (pos_ < text_.size() && !is_space(text_[pos_])) ++pos_;
    token = std::string_view(text_).substr(start, pos_ - start);
    return true;
  }

  // The rest of the current line, trimmed: the name after "solid" may contain spaces.
  std::string rest_of_line() {
    const std::size_t end = std::min(text_.find('\n', pos_), text_.size());
    std::size_t b = pos_, e = end;
    while (b < e && is_space(text_[b])) ++b;
    while (e > b && is_space(text_[e - 1])) --e;
    pos_ = end;
    return text_.substr(b, e - b);
  }

  int line() const { return token_line_; }

 private:
  const std::string& text_;
  std::size_t pos_ = 0;
  int line_ = 1;
  int token_line_ = 1;
};

constexpr const char* kFacetGrammar =
    "an ASCII STL facet is 'facet normal NX NY NZ', 'outer loop', three 'vertex X Y Z', "
    "'endloop', 'endfacet'";

std::string quoted(std::string_view s) {
  constexpr std::size_t kShown = 40;  // binary garbage read as text must not flood the message
  std::string shown(s.substr(0, kShown));
  for (char& c : shown) {
    if (!std::isprint(static_cast<unsigned char>(c))) c = '?';
  }
  return "'" + shown + (s.size() > kShown ? "...'" : "'");
}

class AsciiStlParser {
 public:
  AsciiStlParser(const std::string& text, const std::string& path, const std::string& stem)
      : lex_(text), path_(path), stem_(stem) {}

  // Parses the whole text into mesh (not finalized); facet_lines gets each triangle's line.
  void parse(TriangleMesh& mesh, std::vector<int>& facet_lines) {
    std::string_view tok;
    while (lex_.next(tok)) {
      if (!iequals(tok, "solid")) {
        throw error("expected 'solid NAME' to open an ASCII STL solid, got " + quoted(tok));
      }
      const int solid_line = lex_.line();
      std::string name = lex_.rest_of_line();
      if (name.empty()) name = stem_;
      int part = -1;
      while (true) {
        if (!lex_.next(tok)) {
          throw error("end of file inside solid '" + name + "' opened on line " +
                      std::to_string(solid_line) + "; close it with 'endsolid'");
        }
        if (iequals(tok, "endsolid")) {
          lex_.rest_of_line();
          break;
        }
        if (!iequals(tok, "facet")) {
          throw error("expected 'facet' or 'endsolid', got " + quoted(tok) + "; " + kFacetGrammar);
        }
        facet_lines.push_back(lex_.line());
        if (part < 0) part = part_index(mesh, name);
        parse_facet(mesh, part);
      }
    }
  }

 private:
  InputError error(const std::string& message) const {
    return input_error_at(path_, lex_.line(), message);
  }

  void expect(const char* keyword) {
    std::string_view tok;
    if (!lex_.next(tok)) {
      throw error(std::string("end of file where '") + keyword + "' was expected; " +
                  kFacetGrammar);
    }
    if (!iequals(tok, keyword)) {
      throw error(std::string("expected '") + keyword + "', got " + quoted(tok) + "; " +
                  kFacetGrammar);
    }
  }

  double number(const char* what, bool must_be_finite) {
    std::string_view tok;
    if (!lex_.next(tok)) {
      throw error(std::string("end of file where ") + what + " was expected; " + kFacetGrammar);
    }
    char buffer[64];
    double value = 0.0;
    bool ok = tok.size() < sizeof buffer;
    if (ok) {
      std::memcpy(buffer, tok.data(), tok.size());
      buffer[tok.size()] = '\0';
      char* end = nullptr;
      value = std::strtod(buffer, &end);
      ok = end == buffer + tok.size();
    }
    if (!ok) throw error(std::string("expected ") + what + ", a number, got " + quoted(tok));
    if (must_be_finite && !std::isfinite(value)) {
      throw error(std::string(what) + " " + quoted(tok) +
                  " is not finite; vertex coordinates must be finite numbers");
    }
    return value;
  }

  void parse_facet(TriangleMesh& mesh, int part) {
    expect("normal");
    for (int i = 0; i < 3; ++i) number("a facet normal component", false);  // ignored
    expect("outer");
    expect("loop");
    std::array<int, 3> tri;
    for (int k = 0; k < 3; ++k) {
      expect("vertex");
      Vec3 v;
      for (int i = 0; i < 3; ++i) v[i] = number("a vertex coordinate", true);
      tri[k] = static_cast<int>(mesh.vertices.size());
      mesh.vertices.push_back(v);
    }
    expect("endloop");
    expect("endfacet");
    mesh.triangles.push_back(tri);
    mesh.triangle_part.push_back(part);
  }

  static int part_index(TriangleMesh& mesh, const std::string& name) {
    for (std::size_t i = 0; i < mesh.part_names.size(); ++i) {
      if (mesh.part_names[i] == name) return static_cast<int>(i);
    }
    mesh.part_names.push_back(name);
    return static_cast<int>(mesh.part_names.size()) - 1;
  }

  StlLexer lex_;
  const std::string& path_;
  const std::string& stem_;
};

void parse_binary_stl(const std::string& data, const std::string& path, const std::string& stem,
                      TriangleMesh& mesh) {
  const std::uint32_t n = read_le32(data.data() + 80);
  mesh.part_names = {stem};
  mesh.vertices.reserve(3 * static_cast<std::size_t>(n));
  mesh.triangles.reserve(n);
  mesh.triangle_part.assign(n, 0);
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::size_t offset = 84 + 50 * static_cast<std::size_t>(i);
    std::array<int, 3> tri;
    for (int k = 0; k < 3; ++k) {
      Vec3 v;
      for (int c = 0; c < 3; ++c) v[c] = read_le_float(data.data() + offset + 12 + 12 * k + 4 * c);
      if (!v.allFinite()) {
        throw InputError(
            path + ": binary facet " + std::to_string(i) + " (byte " + std::to_string(offset) +
            ") has a non-finite vertex coordinate; coordinates must be finite numbers");
      }
      tri[k] = static_cast<int>(mesh.vertices.size());
      mesh.vertices.push_back(v);
    }
    mesh.triangles.push_back(tri);
  }
}

}  // namespace

// ---- TriangleMesh -----------------------------------------------------------------------------

void TriangleMesh::finalize() {
  const std::size_t nt = triangles.size();
  if (triangle_part.empty()) triangle_part.assign(nt, 0);
  if (part_names.empty()) part_names.push_back("mesh");
  if (triangle_part.size() != nt) {
    throw std::invalid_argument("TriangleMesh: triangle_part has " +
                                std::to_string(triangle_part.size()) + " entries for " +
                                std::to_string(nt) + " triangles");
  }
  for (int p : triangle_part) {
    if (p < 0 || p >= static_cast<int>(part_names.size())) {
      throw std::invalid_argument("TriangleMesh: part id " + std::to_string(p) +
                                  " out of range of part_names");
    }
  }
  for (const auto& tri : triangles) {
    for (int v : tri) {
      if (v < 0 || v >= static_cast<int>(vertices.size())) {
        throw std::invalid_argument("TriangleMesh: vertex id " + std::to_string(v) +
                                    " out of range");
      }
    }
  }
  Vec3 lower = Vec3::Constant(std::numeric_limits<double>::infinity());
  Vec3 upper = -lower;
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    if (!vertices[i].allFinite()) {
      throw InputError("mesh vertex " + std::to_string(i) +
                       " has a non-finite coordinate; coordinates must be finite numbers");
    }
    lower = lower.cwiseMin(vertices[i]);
    upper = upper.cwiseMax(vertices[i]);
  }
  const double tol = vertices.empty() ? 0.0 : kMergeTolerance * (upper - lower).norm();

  std::vector<int> new_id;
  std::vector<Vec3> merged;
  merge_close_vertices(vertices, tol, new_id, merged);
  vertices.swap(merged);
  for (auto& tri : triangles) {
    for (int& v : tri) v = new_id[v];
  }

  for (std::size_t t = 0; t < nt; ++t) {
    const Vec3& a = vertices[triangles[t][0]];
    const Vec3& b = vertices[triangles[t][1]];
    const Vec3& c = vertices[triangles[t][2]];
    const double twice_area = (b - a).cross(c - a).norm();
    const double longest =
        std::sqrt(std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()}));
    // The smallest height is twice the area over the longest edge; a triangle thinner than the
    // merging tolerance has a vertex that is, at that tolerance, on the line of the other two.
    if (!(twice_area > tol * longest)) {
      throw DegenerateTriangleError(
          static_cast<int>(t),
          "triangle " + std::to_string(t) + " (part '" + part_names[triangle_part[t]] +
              "') is degenerate: its smallest height " +
              format_double(longest > 0.0 ? twice_area / longest : 0.0) +
              " is not above the vertex-merging tolerance " + format_double(tol) +
              " (1e-6 of the mesh size); every triangle needs three distinct, non-collinear "
              "vertices");
    }
  }

  // Edges: sort the (lower, higher, triangle, slot) of every triangle side; equal keys are one
  // edge.
  std::vector<std::tuple<int, int, int, int>> sides;
  sides.reserve(3 * nt);
  for (std::size_t t = 0; t < nt; ++t) {
    for (int k = 0; k < 3; ++k) {
      const int a = triangles[t][k];
      const int b = triangles[t][(k + 1) % 3];
      sides.emplace_back(std::min(a, b), std::max(a, b), static_cast<int>(t), k);
    }
  }
  std::sort(sides.begin(), sides.end());
  triangle_edges.assign(nt, {-1, -1, -1});
  edge_vertices.clear();
  edge_triangle_offsets.assign(1, 0);
  edge_triangles.clear();
  edge_triangles.reserve(sides.size());
  for (std::size_t i = 0; i < sides.size(); ++i) {
    const auto [a, b, t, k] = sides[i];
    if (i == 0 || std::get<0>(sides[i - 1]) != a || std::get<1>(sides[i - 1]) != b) {
      edge_vertices.push_back({a, b});
      edge_triangle_offsets.push_back(edge_triangle_offsets.back());
    }
    triangle_edges[t][k] = static_cast<int>(edge_vertices.size()) - 1;
    edge_triangles.push_back(t);
    ++edge_triangle_offsets.back();
  }
  num_edges = static_cast<int>(edge_vertices.size());

  vertex_edge_offsets.assign(vertices.size() + 1, 0);
  for (const auto& ev : edge_vertices) {
    ++vertex_edge_offsets[ev[0] + 1];
    ++vertex_edge_offsets[ev[1] + 1];
  }
  for (std::size_t v = 0; v < vertices.size(); ++v) {
    vertex_edge_offsets[v + 1] += vertex_edge_offsets[v];
  }
  vertex_edges.assign(vertex_edge_offsets.back(), -1);
  std::vector<int> fill(vertex_edge_offsets.begin(), vertex_edge_offsets.end() - 1);
  for (int e = 0; e < num_edges; ++e) {
    vertex_edges[fill[edge_vertices[e][0]]++] = e;
    vertex_edges[fill[edge_vertices[e][1]]++] = e;
  }
}

bool TriangleMesh::is_closed() const {
  if (triangle_edges.size() != triangles.size()) {
    throw std::logic_error("TriangleMesh::is_closed: call finalize() first");
  }
  if (triangles.empty()) return false;
  for (int e = 0; e < num_edges; ++e) {
    if (edge_triangle_offsets[e + 1] - edge_triangle_offsets[e] != 2) return false;
    int forward = 0;
    for (int i = edge_triangle_offsets[e]; i < edge_triangle_offsets[e + 1]; ++i) {
      const int t = edge_triangles[i];
      if (triangles[t][local_edge_index(*this, t, e)] == edge_vertices[e][0]) ++forward;
    }
    if (forward != 1) return false;
  }
  return true;
}

void TriangleMesh::translate(const Vec3& shift) {
  for (Vec3& v : vertices) v += shift;
}

void TriangleMesh::rotate(const Mat3& rotation, const Vec3& about) {
  for (Vec3& v : vertices) v = about + rotation * (v - about);
}

void TriangleMesh::scale(double factor, const Vec3& about) {
  if (!(factor > 0.0) || !std::isfinite(factor)) {
    throw std::invalid_argument("TriangleMesh::scale: factor must be finite and > 0, got " +
                                format_double(factor));
  }
  for (Vec3& v : vertices) v = about + factor * (v - about);
}

Vec3 TriangleMesh::triangle_normal(int triangle) const {
  const auto& tri = triangles[triangle];
  return (vertices[tri[1]] - vertices[tri[0]])
      .cross(vertices[tri[2]] - vertices[tri[0]])
      .normalized();
}

// ---- STL input --------------------------------------------------------------------------------

TriangleMesh read_stl(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) {
    throw InputError(path + ": no such STL file; give the path of an existing, readable .stl file");
  }
  std::ifstream in(path, std::ios::binary);
  std::ostringstream buffer;
  buffer << in.rdbuf();
  if (!in) throw InputError(path + ": cannot read the STL file; check its permissions");
  const std::string data = buffer.str();
  const std::string stem = fs::path(path).stem().string();

  // An ASCII file could only pass the binary size check if its bytes 80..83, read as a count,
  // matched its size; printable bytes there make the count at least 0x20202020, i.e. a file of
  // more than 26 GB, so the size check decides. ASCII STL is text: no NUL bytes.
  const std::size_t size = data.size();
  const bool binary_size_matches =
      size >= 84 && size == 84 + 50 * static_cast<std::size_t>(read_le32(data.data() + 80));
  std::size_t first = 0;
  while (first < size && is_space(data[first])) ++first;
  const bool looks_ascii = size - first >= 5 &&
                           iequals(std::string_view(data).substr(first, 5), "solid") &&
                           data.find('\0') == std::string::npos;

  TriangleMesh mesh;
  std::vector<int> facet_lines;
  if (binary_size_matches) {
    parse_binary_stl(data, path, stem, mesh);
  } else if (looks_ascii) {
    AsciiStlParser(data, path, stem).parse(mesh, facet_lines);
  } else if (size < 84) {
    throw InputError(path + ": " + std::to_string(size) +
                     " bytes is too short for a binary STL (at least 84) and the file does not "
                     "begin with 'solid' as ASCII STL does");
  } else {
    const std::uint32_t n = read_le32(data.data() + 80);
    throw InputError(path + ": truncated or corrupt binary STL: its header declares " +
                     std::to_string(n) + " triangles, which need 84 + 50 * " + std::to_string(n) +
                     " = " + std::to_string(84 + 50 * static_cast<std::uint64_t>(n)) +
                     " bytes, but the file has " + std::to_string(size));
  }
  if (mesh.triangles.empty()) {
    throw InputError(path +
                     ": the STL file has no triangles; a mesh wall needs at least one facet");
  }
  try {
    mesh.finalize();
  } catch (const DegenerateTriangleError& e) {
    const int t = e.triangle();
    if (facet_lines.empty()) {
      throw InputError(path + ": binary facet at byte " + std::to_string(84 + 50 * t) + ": " +
                       e.what());
    }
    throw input_error_at(path, facet_lines[t], e.what());
  }
  return mesh;
}

// ---- box ----------------------------------------------------------------------------------------

TriangleMesh make_box_mesh(const Vec3& lower, const Vec3& upper, bool with_part_names,
                           double bottom_width) {
  if (!(lower.array() < upper.array()).all()) {
    throw InputError("box mesh: the lower corner must be below the upper corner in x, y and z");
  }
  if (bottom_width < 0) throw InputError("box mesh: the bottom width must be >= 0");
  const double yc = 0.5 * (lower.y() + upper.y());
  const double hb = bottom_width > 0 ? 0.5 * bottom_width : 0.5 * (upper.y() - lower.y());
  TriangleMesh mesh;
  for (int i = 0; i < 8; ++i) {  // vertex i has x, y, z from bits 0, 1, 2 of i
    const double y = i & 4 ? (i & 2 ? upper.y() : lower.y()) : (i & 2 ? yc + hb : yc - hb);
    mesh.vertices.emplace_back(i & 1 ? upper.x() : lower.x(), y, i & 4 ? upper.z() : lower.z());
  }
  // Counter-clockwise seen from outside; parts: 0 base, 1 top, 2 sides, 3 ends.
  mesh.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                    {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  if (with_part_names) {
    mesh.part_names = {"base", "top", "sides", "ends"};
    mesh.triangle_part = {0, 0, 1, 1, 2, 2, 2, 2, 3, 3, 3, 3};
  } else {
    mesh.part_names = {"box"};
    mesh.triangle_part.assign(12, 0);
  }
  mesh.finalize();
  return mesh;
}

// ---- mass properties --------------------------------------------------------------------------

MeshMassProperties closed_mesh_mass_properties(const TriangleMesh& mesh) {
  if (!mesh.is_closed()) {
    throw InputError(
        "mass properties need a closed mesh: every edge shared by exactly two consistently "
        "oriented triangles");
  }
  // Integrate about the bounding-box centre: coordinates far from the origin would otherwise
  // cancel catastrophically in the second moments.
  Vec3 lower = mesh.vertices[0], upper = mesh.vertices[0];
  for (const Vec3& v : mesh.vertices) {
    lower = lower.cwiseMin(v);
    upper = upper.cwiseMax(v);
  }
  const Vec3 ref = 0.5 * (lower + upper);

  // Eberly (2002): integrals of 1, x, y, z, x^2, y^2, z^2, xy, yz, zx over the solid, each a sum
  // over triangles of the normal component times a cubic polynomial of the vertex coordinates.
  double intg[10] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0};
  struct Sub {
    double f1, f2, f3, g0, g1, g2;
  };
  const auto subexpressions = [](double w0, double w1, double w2) {
    Sub s;
    const double temp0 = w0 + w1;
    s.f1 = temp0 + w2;
    const double temp1 = w0 * w0;
    const double temp2 = temp1 + w1 * temp0;
    s.f2 = temp2 + w2 * s.f1;
    s.f3 = w0 * temp1 + w1 * temp2 + w2 * s.f2;
    s.g0 = s.f2 + w0 * (s.f1 + w0);
    s.g1 = s.f2 + w1 * (s.f1 + w1);
    s.g2 = s.f2 + w2 * (s.f1 + w2);
    return s;
  };
  for (const auto& tri : mesh.triangles) {
    const Vec3 p0 = mesh.vertices[tri[0]] - ref;
    const Vec3 p1 = mesh.vertices[tri[1]] - ref;
    const Vec3 p2 = mesh.vertices[tri[2]] - ref;
    const Vec3 d = (p1 - p0).cross(p2 - p0);
    const Sub x = subexpressions(p0.x(), p1.x(), p2.x());
    const Sub y = subexpressions(p0.y(), p1.y(), p2.y());
    const Sub z = subexpressions(p0.z(), p1.z(), p2.z());
    intg[0] += d.x() * x.f1;
    intg[1] += d.x() * x.f2;
    intg[2] += d.y() * y.f2;
    intg[3] += d.z() * z.f2;
    intg[4] += d.x() * x.f3;
    intg[5] += d.y() * y.f3;
    intg[6] += d.z() * z.f3;
    intg[7] += d.x() * (p0.y() * x.g0 + p1.y() * x.g1 + p2.y() * x.g2);
    intg[8] += d.y() * (p0.z() * y.g0 + p1.z() * y.g1 + p2.z() * y.g2);
    intg[9] += d.z() * (p0.x() * z.g0 + p1.x() * z.g1 + p2.x() * z.g2);
  }
  const double mult[10] = {1.0 / 6,  1.0 / 24, 1.0 / 24,  1.0 / 24,  1.0 / 60,
                           1.0 / 60, 1.0 / 60, 1.0 / 120, 1.0 / 120, 1.0 / 120};
  for (int i = 0; i < 10; ++i) intg[i] *= mult[i];

  const double volume = intg[0];
  if (!(volume > 0.0)) {
    throw InputError(
        "mass properties: the closed mesh encloses volume " + format_double(volume) +
        "; its triangles must be counter-clockwise seen from outside (outward normals)");
  }
  const Vec3 c(intg[1] / volume, intg[2] / volume, intg[3] / volume);
  Mat3 inertia;
  inertia(0, 0) = intg[5] + intg[6] - volume * (c.y() * c.y() + c.z() * c.z());
  inertia(1, 1) = intg[4] + intg[6] - volume * (c.z() * c.z() + c.x() * c.x());
  inertia(2, 2) = intg[4] + intg[5] - volume * (c.x() * c.x() + c.y() * c.y());
  inertia(0, 1) = inertia(1, 0) = -(intg[7] - volume * c.x() * c.y());
  inertia(1, 2) = inertia(2, 1) = -(intg[8] - volume * c.y() * c.z());
  inertia(0, 2) = inertia(2, 0) = -(intg[9] - volume * c.z() * c.x());
  return {volume, ref + c, inertia};
}

// ---- closest point ----------------------------------------------------------------------------

TriangleClosestPoint closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b,
                                               const Vec3& c) {
  const Vec3 ab = b - a;
  const Vec3 ac = c - a;
  const Vec3 ap = p - a;
  const double d1 = ab.dot(ap);
  const double d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return {a, MeshFeature::Vertex, 0, Vec3(1, 0, 0)};

  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp);
  const double d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return {b, MeshFeature::Vertex, 1, Vec3(0, 1, 0)};

  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
    const double v = d1 / (d1 - d3);
    return {a + v * ab, MeshFeature::Edge, 0, Vec3(1 - v, v, 0)};
  }

  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp);
  const double d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return {c, MeshFeature::Vertex, 2, Vec3(0, 0, 1)};

  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
    const double w = d2 / (d2 - d6);
    return {a + w * ac, MeshFeature::Edge, 2, Vec3(1 - w, 0, w)};
  }

  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return {b + w * (c - b), MeshFeature::Edge, 1, Vec3(0, 1 - w, w)};
  }

  const double denom = 1.0 / (va + vb + vc);
  const double v = vb * denom;
  const double w = vc * denom;
  return {a + ab * v + ac * w, MeshFeature::Face, 0, Vec3(1 - v - w, v, w)};
}

// ---- sphere-mesh contacts ---------------------------------------------------------------------

void sphere_mesh_contacts(const TriangleMesh& mesh, const Vec3& centre, double radius,
                          const int* candidate_triangles, int n_candidates,
                          std::vector<MeshContactPoint>& out) {
  out.clear();
  if (mesh.triangle_edges.size() != mesh.triangles.size()) {
    throw std::logic_error("sphere_mesh_contacts: call TriangleMesh::finalize() first");
  }
  const double r2 = radius * radius;
  for (int i = 0; i < n_candidates; ++i) {
    const int t = candidate_triangles[i];
    const auto& tri = mesh.triangles[t];
    const TriangleClosestPoint closest = closest_point_on_triangle(
        centre, mesh.vertices[tri[0]], mesh.vertices[tri[1]], mesh.vertices[tri[2]]);
    const Vec3 to_centre = centre - closest.point;
    const double d2 = to_centre.squaredNorm();
    // Every edge and vertex of the triangle is at least this far, so none of them touches either.
    if (d2 >= r2) continue;

    // Face: the centre projects into the triangle (all three opposite weights >= 0).
    if (!has_feature(out, MeshFeature::Face, t) &&
        opposite_weight(mesh, t, 0, centre) >= -kRegionSlack &&
        opposite_weight(mesh, t, 1, centre) >= -kRegionSlack &&
        opposite_weight(mesh, t, 2, centre) >= -kRegionSlack) {
      const Vec3 n = mesh.triangle_normal(t);
      const double distance = std::sqrt(d2);
      out.push_back({t, MeshFeature::Face, t, closest.point, to_centre.dot(n) < 0.0 ? -n : n,
                     radius - distance});
    }

    for (int k = 0; k < 3; ++k) {
      const int e = mesh.triangle_edges[t][k];
      if (has_feature(out, MeshFeature::Edge, e)) continue;
      const double s = edge_parameter(mesh, e, centre);
      const Vec3& lo = mesh.vertices[mesh.edge_vertices[e][0]];
      const Vec3& hi = mesh.vertices[mesh.edge_vertices[e][1]];
      const Vec3 point = lo + std::clamp(s, 0.0, 1.0) * (hi - lo);
      const Vec3 from = centre - point;
      const double de2 = from.squaredNorm();
      if (de2 >= r2 || !edge_region_contains(mesh, e, s, centre)) continue;
      const double distance = std::sqrt(de2);
      out.push_back({t, MeshFeature::Edge, e, point, contact_direction(mesh, t, from, distance),
                     radius - distance});
    }

    for (int k = 0; k < 3; ++k) {
      const int v = tri[k];
      if (has_feature(out, MeshFeature::Vertex, v)) continue;
      const Vec3 from = centre - mesh.vertices[v];
      const double dv2 = from.squaredNorm();
      if (dv2 >= r2 || !vertex_region_contains(mesh, v, centre)) continue;
      const double distance = std::sqrt(dv2);
      out.push_back({t, MeshFeature::Vertex, v, mesh.vertices[v],
                     contact_direction(mesh, t, from, distance), radius - distance});
    }
  }

  // Contacts at one position are one contact (a centre on a shared boundary lies in the widened
  // regions of several features); keep the face, whose normal is exact, before an edge or vertex.
  std::size_t kept = 0;
  for (std::size_t j = 0; j < out.size(); ++j) {
    const double edge_j = longest_edge(mesh, out[j].triangle);
    bool merged = false;
    for (std::size_t i = 0; i < kept && !merged; ++i) {
      const double tol =
          kMergeRadius * radius + kMergeEdge * (edge_j + longest_edge(mesh, out[i].triangle));
      if ((out[i].point - out[j].point).squaredNorm() <= tol * tol) {
        if (out[j].feature < out[i].feature) out[i] = out[j];
        merged = true;
      }
    }
    if (!merged) out[kept++] = out[j];
  }
  out.resize(kept);
}

// ---- TriangleGrid -----------------------------------------------------------------------------

void TriangleGrid::build(const TriangleMesh& mesh, double cell) {
  if (!(cell > 0.0) || !std::isfinite(cell)) {
    throw std::invalid_argument("TriangleGrid::build: cell must be finite and > 0, got " +
                                format_double(cell));
  }
  const std::size_t nt = mesh.triangles.size();
  box_lower_.resize(nt);
  box_upper_.resize(nt);
  Vec3 lower = Vec3::Constant(std::numeric_limits<double>::infinity());
  Vec3 upper = -lower;
  for (std::size_t t = 0; t < nt; ++t) {
    const auto& tri = mesh.triangles[t];
    const Vec3& a = mesh.vertices[tri[0]];
    box_lower_[t] = a.cwiseMin(mesh.vertices[tri[1]]).cwiseMin(mesh.vertices[tri[2]]);
    box_upper_[t] = a.cwiseMax(mesh.vertices[tri[1]]).cwiseMax(mesh.vertices[tri[2]]);
    lower = lower.cwiseMin(box_lower_[t]);
    upper = upper.cwiseMax(box_upper_[t]);
  }
  cell_offsets_.assign(1, 0);
  items_.clear();
  dims_ = {0, 0, 0};
  cell_ = cell;
  if (nt == 0) return;
  origin_ = lower;
  const Vec3 extent = upper - lower;
  while (true) {
    long cells = 1;
    for (int k = 0; k < 3; ++k) {
      dims_[k] = static_cast<int>(std::min(std::floor(extent[k] / cell_) + 1.0, 1e9));
      cells *= dims_[k];
      cells = std::min(cells, kMaxCells + 1);
    }
    if (cells <= kMaxCells) break;
    cell_ *= 1.25;  // coarsen until the grid fits; a few steps at most
  }
  const auto cell_range = [&](std::size_t t, std::array<int, 3>& from, std::array<int, 3>& to) {
    for (int k = 0; k < 3; ++k) {
      from[k] =
          std::clamp(static_cast<int>((box_lower_[t][k] - origin_[k]) / cell_), 0, dims_[k] - 1);
      to[k] =
          std::clamp(static_cast<int>((box_upper_[t][k] - origin_[k]) / cell_), 0, dims_[k] - 1);
    }
  };
  const long n_cells = static_cast<long>(dims_[0]) * dims_[1] * dims_[2];
  std::vector<long> counts(n_cells + 1, 0);
  std::array<int, 3> from, to;
  for (std::size_t t = 0; t < nt; ++t) {
    cell_range(t, from, to);
    for (int z = from[2]; z <= to[2]; ++z)
      for (int y = from[1]; y <= to[1]; ++y)
        for (int x = from[0]; x <= to[0]; ++x)
          ++counts[(static_cast<long>(z) * dims_[1] + y) * dims_[0] + x + 1];
  }
  for (long c = 0; c < n_cells; ++c) counts[c + 1] += counts[c];
  if (counts[n_cells] > std::numeric_limits<int>::max()) {
    throw std::invalid_argument("TriangleGrid::build: cell " + format_double(cell_) +
                                " is too small for triangles this large (over 2^31 entries)");
  }
  cell_offsets_.assign(counts.begin(), counts.end());
  items_.assign(counts[n_cells], -1);
  std::vector<int> fill(cell_offsets_.begin(), cell_offsets_.end() - 1);
  for (std::size_t t = 0; t < nt; ++t) {
    cell_range(t, from, to);
    for (int z = from[2]; z <= to[2]; ++z)
      for (int y = from[1]; y <= to[1]; ++y)
        for (int x = from[0]; x <= to[0]; ++x)
          items_[fill[(static_cast<long>(z) * dims_[1] + y) * dims_[0] + x]++] =
              static_cast<int>(t);
  }
}

void TriangleGrid::query(const Vec3& centre, double radius, std::vector<int>& out) const {
  out.clear();
  if (dims_[0] == 0) return;
  std::array<int, 3> from, to;
  for (int k = 0; k < 3; ++k) {
    const double lo = (centre[k] - radius - origin_[k]) / cell_;
    const double hi = (centre[k] + radius - origin_[k]) / cell_;
    if (!(hi >= 0.0 && lo < dims_[k])) return;  // the sphere's box misses the grid
    from[k] = static_cast<int>(std::max(0.0, std::floor(lo)));
    to[k] = static_cast<int>(std::min(dims_[k] - 1.0, std::floor(hi)));
  }
  const double r2 = radius * radius;
  for (int z = from[2]; z <= to[2]; ++z) {
    for (int y = from[1]; y <= to[1]; ++y) {
      for (int x = from[0]; x <= to[0]; ++x) {
        const long c = (static_cast<long>(z) * dims_[1] + y) * dims_[0] + x;
        for (int i = cell_offsets_[c]; i < cell_offsets_[c + 1]; ++i) {
          const int t = items_[i];
          // Distance from the centre to the triangle's bounding box.
          const Vec3 gap = (box_lower_[t] - centre).cwiseMax(centre - box_upper_[t]).cwiseMax(0.0);
          if (gap.squaredNorm() <= r2) out.push_back(t);
        }
      }
    }
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
}

}  // namespace trackbed::dem
