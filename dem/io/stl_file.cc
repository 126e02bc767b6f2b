#include "dem/io/stl_file.h"

#include <cctype>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string_view>

#include "common/input_error.h"

namespace trackbed::dem {

namespace {

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

}  // namespace trackbed::dem
