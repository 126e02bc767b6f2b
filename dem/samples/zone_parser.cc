// The recursive-descent parser of zone expressions (grammar: docs/zones.md#grammar). One function
// per rule; every error names the character where the text stops making sense and what would
// have been valid there.
#include <cctype>
#include <charconv>
#include <cmath>
#include <filesystem>

#include "common/input_error.h"
#include "dem/samples/pilot_zone.h"
#include "dem/samples/zone.h"

namespace trackbed::dem {

namespace {

struct ShapeSignature {
  const char* name;
  const char* arguments;  // for messages
};

constexpr ShapeSignature kBox{"box", "box(x0, y0, z0, x1, y1, z1)"};
constexpr ShapeSignature kHalfspace{"halfspace", "halfspace(px, py, pz, nx, ny, nz)"};
constexpr ShapeSignature kSphere{"sphere", "sphere(cx, cy, cz, r)"};
constexpr ShapeSignature kPrism{"prism", "prism(AXIS, lo, hi, u1, v1, u2, v2, u3, v3, ...)"};
constexpr ShapeSignature kPilot{
    "pilot", "pilot(FOLDER_OR_FILES, SLEEPER_DISPLACEMENT, THRESHOLD, DILATION)"};
constexpr const char* kShapeNames = "all, none, box, halfspace, sphere, prism, pilot";

// One argument as written: a number, or the word or path some shapes take first.
struct Argument {
  explicit Argument(std::size_t at) : position(at) {}
  std::size_t position;
  double number = 0;
  std::string word;
};

class Parser {
 public:
  Parser(const std::string& text, const std::string& where, const std::string& base_folder)
      : text_(text), where_(where.empty() ? "zone" : where), base_folder_(base_folder) {}

  ZonePtr parse() {
    skip_space();
    if (at_end())
      fail(pos_, std::string("empty zone expression; valid: a shape (") + kShapeNames +
                     ") or shapes combined with |, +, -, & and parentheses");
    ZonePtr zone = parse_union();
    skip_space();
    if (!at_end())
      fail(pos_,
           "unexpected " + found() +
               " after a complete zone; valid: an operator |, +, -, & or the end of the text");
    return zone;
  }

 private:
  // union = intersection { ("|" | "+" | "-") intersection }  (left-associative)
  ZonePtr parse_union() {
    ZonePtr zone = parse_intersection();
    while (true) {
      skip_space();
      const char c = peek();
      if (c != '|' && c != '+' && c != '-') return zone;
      ++pos_;
      ZonePtr right = parse_intersection();
      zone = c == '-' ? difference_zone(zone, right) : union_zone(zone, right);
    }
  }

  // intersection = primary { "&" primary }
  ZonePtr parse_intersection() {
    ZonePtr zone = parse_primary();
    while (true) {
      skip_space();
      if (peek() != '&') return zone;
      ++pos_;
      zone = intersection_zone(zone, parse_primary());
    }
  }

  // primary = "(" union ")" | shape
  ZonePtr parse_primary() {
    skip_space();
    if (peek() == '(') {
      const std::size_t open = pos_++;
      ZonePtr zone = parse_union();
      skip_space();
      if (peek() != ')')
        fail(pos_, "expected ')' to close the '(' at character " + std::to_string(open + 1) +
                       ", found " + found());
      ++pos_;
      return zone;
    }
    if (!std::isalpha(static_cast<unsigned char>(peek())))
      fail(pos_, std::string("expected a shape (") + kShapeNames + ") or '(', found " + found());
    const std::size_t start = pos_;
    const std::string name = read_word();
    if (name == "all") return all_zone();
    if (name == "none") return no_zone();
    for (const ShapeSignature* s : {&kBox, &kHalfspace, &kSphere, &kPrism, &kPilot})
      if (name == s->name) return parse_shape(*s, start);
    fail(start, "unknown shape '" + name + "'; valid: " + kShapeNames);
  }

  ZonePtr parse_shape(const ShapeSignature& shape, std::size_t start) {
    const std::vector<Argument> args = parse_arguments(shape);
    check_count(shape, start, args);
    const auto number = [&](std::size_t i) { return args[i].number; };
    try {
      if (&shape == &kBox || &shape == &kHalfspace) {
        const Vec3 a(number(0), number(1), number(2)), b(number(3), number(4), number(5));
        return &shape == &kBox ? box_zone(a, b) : halfspace_zone(a, b);
      }
      if (&shape == &kSphere) return sphere_zone(Vec3(number(0), number(1), number(2)), number(3));
      if (&shape == &kPrism) {
        std::vector<Eigen::Vector2d> polygon;
        for (std::size_t i = 3; i + 1 < args.size(); i += 2)
          polygon.emplace_back(number(i), number(i + 1));
        const int axis = static_cast<int>(std::string("xyz").find(args[0].word));
        return prism_zone(axis, number(1), number(2), polygon);
      }
      return pilot(args);
    } catch (const InputError& e) {
      fail(start, e.what());  // the shape's own check: add where and the position
    }
  }

  void check_count(const ShapeSignature& shape, std::size_t start,
                   const std::vector<Argument>& args) const {
    const std::size_t n = args.size();
    if (&shape == &kPrism) {
      if (n < 9)
        fail(start, std::string(shape.arguments) +
                        " takes an axis, lo, hi and at least 3 vertices (u, v); got " +
                        std::to_string(n) + " arguments");
      if (n % 2 == 0)
        fail(start, std::string(shape.arguments) + ": vertex coordinates come in (u, v) " +
                        "pairs; got " + std::to_string(n - 3) + " after AXIS, lo, hi");
      return;
    }
    const std::size_t expected = &shape == &kBox || &shape == &kHalfspace ? 6 : 4;
    if (n != expected)
      fail(start, std::string(shape.arguments) + " takes " + std::to_string(expected) +
                      " arguments, got " + std::to_string(n));
  }

  ZonePtr pilot(const std::vector<Argument>& args) {
    std::filesystem::path path(args[0].word);
    if (path.is_relative() && !base_folder_.empty())
      path = std::filesystem::path(base_folder_) / path;
    try {
      return std::make_shared<PilotZone>(path.string(), pilot_snapshot_files(path.string()),
                                         args[1].number, args[2].number, args[3].number);
    } catch (const InputError& e) {
      throw InputError(std::string("pilot: ") + e.what());
    }
  }

  // "(" argument { "," argument } ")"; the first argument of prism is an axis, of pilot a path.
  std::vector<Argument> parse_arguments(const ShapeSignature& shape) {
    skip_space();
    if (peek() != '(')
      fail(pos_, std::string("expected '(' after ") + shape.name + ", as in " + shape.arguments +
                     ", found " + found());
    ++pos_;
    std::vector<Argument> args;
    while (true) {
      skip_space();
      const std::size_t n = args.size() + 1;
      if (args.empty() && &shape == &kPrism)
        args.push_back(parse_axis(shape));
      else if (args.empty() && &shape == &kPilot)
        args.push_back(parse_path(shape));
      else
        args.push_back(parse_number(shape, n));
      skip_space();
      if (peek() == ')') break;
      if (peek() != ',')
        fail(pos_, "expected ',' or ')' after argument " + std::to_string(n) + " of " +
                       shape.arguments + ", found " + found());
      ++pos_;
    }
    ++pos_;
    return args;
  }

  // number = [ "+" | "-" ] digits [ "." [ digits ] ] | "." digits, then [ ("e" | "E") [ "+" |
  // "-" ] digits ]. The whole run of number-like characters is taken, so "1.2.3" or "2x" is
  // refused as a whole rather than split.
  Argument parse_number(const ShapeSignature& shape, std::size_t n) {
    const std::size_t start = pos_;
    std::size_t end = pos_;
    // Every leading sign joins the token, so that "+-1" is refused as a whole.
    while (end < text_.size() && (text_[end] == '+' || text_[end] == '-')) ++end;
    while (end < text_.size()) {
      const char c = text_[end];
      const bool exponent_sign =
          (c == '+' || c == '-') && end > start && (text_[end - 1] == 'e' || text_[end - 1] == 'E');
      if (!std::isalnum(static_cast<unsigned char>(c)) && c != '.' && c != '_' && !exponent_sign)
        break;
      ++end;
    }
    const std::string token = text_.substr(start, end - start);
    if (token.empty() || token == "+" || token == "-")
      fail(start, "expected a number as argument " + std::to_string(n) + " of " + shape.arguments +
                      ", found " + found_at(end));
    // from_chars takes no '+' sign: skip one, and refuse a second sign after it.
    const std::size_t first = token[0] == '+' ? 1 : 0;
    Argument arg(start);
    const char* e = token.data() + token.size();
    const auto [ptr, ec] = std::from_chars(token.data() + first, e, arg.number);
    if ((first == 1 && token[1] == '-') || ec != std::errc() || ptr != e ||
        !std::isfinite(arg.number))
      fail(start, "'" + token + "' is not a number (argument " + std::to_string(n) + " of " +
                      shape.arguments + "); valid: a decimal number such as 0.35, -1 or 2.5e-3");
    pos_ = end;
    return arg;
  }

  Argument parse_axis(const ShapeSignature& shape) {
    const std::size_t start = pos_;
    if (!std::isalpha(static_cast<unsigned char>(peek())))
      fail(start, std::string("expected the axis x, y or z as argument 1 of ") + shape.arguments +
                      ", found " + found());
    Argument arg(start);
    arg.word = read_word();
    if (arg.word != "x" && arg.word != "y" && arg.word != "z")
      fail(start, "axis '" + arg.word + "'; valid: x, y or z (the prism's extrusion direction)");
    return arg;
  }

  // A path in double quotes (any characters but '"'), or bare: up to a space, ',', '(' or ')'.
  Argument parse_path(const ShapeSignature& shape) {
    Argument arg(pos_);
    if (peek() == '"') {
      const std::size_t close = text_.find('"', pos_ + 1);
      if (close == std::string::npos)
        fail(pos_, "the path opened with '\"' at character " + std::to_string(pos_ + 1) +
                       " has no closing '\"'");
      arg.word = text_.substr(pos_ + 1, close - pos_ - 1);
      pos_ = close + 1;
    } else {
      while (!at_end() && !std::isspace(static_cast<unsigned char>(peek())) &&
             std::string(",()\"").find(peek()) == std::string::npos)
        arg.word += text_[pos_++];
    }
    if (arg.word.empty())
      fail(arg.position, std::string("expected the pilot run's folder or snapshot files as "
                                     "argument 1 of ") +
                             shape.arguments + ", found " + found());
    return arg;
  }

  std::string read_word() {
    std::string word;
    while (!at_end() && (std::isalnum(static_cast<unsigned char>(peek())) || peek() == '_'))
      word += text_[pos_++];
    return word;
  }

  void skip_space() {
    while (!at_end() && std::isspace(static_cast<unsigned char>(peek()))) ++pos_;
  }
  bool at_end() const { return pos_ >= text_.size(); }
  char peek() const { return at_end() ? '\0' : text_[pos_]; }
  std::string found() const { return found_at(pos_); }
  std::string found_at(std::size_t p) const {
    return p >= text_.size() ? "the end of the text" : "'" + std::string(1, text_[p]) + "'";
  }

  // One line: WHERE: character N of "TEXT": MESSAGE (control characters of the text echoed as
  // spaces).
  [[noreturn]] void fail(std::size_t position, const std::string& message) const {
    std::string shown = text_;
    for (char& c : shown)
      if (std::iscntrl(static_cast<unsigned char>(c))) c = ' ';
    throw InputError(where_ + ": character " + std::to_string(position + 1) + " of \"" + shown +
                     "\": " + message);
  }

  const std::string& text_;
  std::string where_;
  std::string base_folder_;
  std::size_t pos_ = 0;
};

}  // namespace

ZonePtr parse_zone(const std::string& text, const std::string& where,
                   const std::string& base_folder) {
  return Parser(text, where, base_folder).parse();
}

}  // namespace trackbed::dem
