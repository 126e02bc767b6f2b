#include "dem/samples/zone.h"

#include <algorithm>
#include <charconv>
#include <utility>

#include "common/input_error.h"
#include "common/number_text.h"

namespace trackbed::dem {

namespace {

using Vec2 = Eigen::Vector2d;

void print_call(std::string& out, const std::string& name, const std::vector<double>& args) {
  out += name + "(";
  for (std::size_t i = 0; i < args.size(); ++i) out += (i ? ", " : "") + exact_number_text(args[i]);
  out += ")";
}

class AllZone final : public Zone {
 public:
  bool contains(const Vec3&) const override { return true; }
  std::optional<Bounds> bounds() const override { return std::nullopt; }
  void print(std::string& out) const override { out += "all"; }
};

class NoZone final : public Zone {
 public:
  bool contains(const Vec3&) const override { return false; }
  std::optional<Bounds> bounds() const override { return Bounds(); }
  void print(std::string& out) const override { out += "none"; }
};

class BoxZone final : public Zone {
 public:
  explicit BoxZone(const Bounds& box) : box_(box) {}
  bool contains(const Vec3& x) const override { return box_.contains(x); }
  std::optional<Bounds> bounds() const override { return box_; }
  void print(std::string& out) const override {
    const Vec3 a = box_.min(), b = box_.max();
    print_call(out, "box", {a.x(), a.y(), a.z(), b.x(), b.y(), b.z()});
  }

 private:
  Bounds box_;
};

class HalfspaceZone final : public Zone {
 public:
  HalfspaceZone(const Vec3& p, const Vec3& n) : p_(p), n_(n) {}
  bool contains(const Vec3& x) const override { return (x - p_).dot(n_) <= 0; }
  std::optional<Bounds> bounds() const override { return std::nullopt; }
  void print(std::string& out) const override {
    print_call(out, "halfspace", {p_.x(), p_.y(), p_.z(), n_.x(), n_.y(), n_.z()});
  }

 private:
  Vec3 p_, n_;
};

class SphereZone final : public Zone {
 public:
  SphereZone(const Vec3& c, double r) : c_(c), r_(r) {}
  bool contains(const Vec3& x) const override { return (x - c_).squaredNorm() <= r_ * r_; }
  std::optional<Bounds> bounds() const override {
    return Bounds(c_ - Vec3::Constant(r_), c_ + Vec3::Constant(r_));
  }
  void print(std::string& out) const override {
    print_call(out, "sphere", {c_.x(), c_.y(), c_.z(), r_});
  }

 private:
  Vec3 c_;
  double r_;
};

// ---- polygons of prisms ----

double cross(const Vec2& a, const Vec2& b) {
  return a.x() * b.y() - a.y() * b.x();
}

// p on the closed segment ab (exactly, in floating point).
bool on_segment(const Vec2& p, const Vec2& a, const Vec2& b) {
  return cross(b - a, p - a) == 0 && std::min(a.x(), b.x()) <= p.x() &&
         p.x() <= std::max(a.x(), b.x()) && std::min(a.y(), b.y()) <= p.y() &&
         p.y() <= std::max(a.y(), b.y());
}

int orientation(const Vec2& a, const Vec2& b, const Vec2& c) {
  const double o = cross(b - a, c - a);
  return (o > 0) - (o < 0);
}

// The closed segments ab and cd share a point (Cormen et al., Introduction to Algorithms,
// section 33.1: straddle tests, with the collinear cases settled by on_segment).
bool segments_meet(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
  const int o1 = orientation(a, b, c), o2 = orientation(a, b, d);
  const int o3 = orientation(c, d, a), o4 = orientation(c, d, b);
  if (o1 * o2 < 0 && o3 * o4 < 0) return true;
  return on_segment(c, a, b) || on_segment(d, a, b) || on_segment(a, c, d) || on_segment(b, c, d);
}

std::string edge_name(int i, int n) {
  return "edge " + std::to_string(i + 1) + " (vertices " + std::to_string(i + 1) + "-" +
         std::to_string((i + 1) % n + 1) + ")";
}

// Refuses a polygon that is not simple: repeated consecutive vertices, two edges at one vertex
// that fold back onto each other, or two edges that are not neighbours and meet.
void check_simple(const std::vector<Vec2>& poly) {
  const int n = static_cast<int>(poly.size());
  const std::string valid = "; valid: a simple polygon, whose edges meet only at shared vertices";
  for (int i = 0; i < n; ++i) {
    const Vec2& a = poly[i];
    const Vec2& b = poly[(i + 1) % n];
    const Vec2& c = poly[(i + 2) % n];
    if (a == b)
      throw InputError("vertices " + std::to_string(i + 1) + " and " +
                       std::to_string((i + 1) % n + 1) + " coincide" + valid);
    if (orientation(a, b, c) == 0 && (a - b).dot(c - b) > 0)
      throw InputError(edge_name(i, n) + " and " + edge_name((i + 1) % n, n) +
                       " fold back onto each other" + valid);
  }
  for (int i = 0; i < n; ++i)
    for (int j = i + 2; j < n; ++j) {
      if (i == 0 && j == n - 1) continue;  // neighbours through vertex 1
      if (segments_meet(poly[i], poly[(i + 1) % n], poly[j], poly[(j + 1) % n]))
        throw InputError(edge_name(i, n) + " and " + edge_name(j, n) + " cross or touch" + valid);
    }
}

class PrismZone final : public Zone {
 public:
  PrismZone(int axis, double lo, double hi, std::vector<Vec2> polygon)
      : axis_(axis), lo_(lo), hi_(hi), poly_(std::move(polygon)) {
    u_ = axis == 0 ? 1 : 0;
    v_ = axis == 2 ? 1 : 2;
  }

  bool contains(const Vec3& x) const override {
    if (x[axis_] < lo_ || x[axis_] > hi_) return false;
    const Vec2 p(x[u_], x[v_]);
    // Crossing number (Franklin's pnpoly rule: an edge counts when it straddles the horizontal
    // line through p, upper end excluded, and crosses it right of p); the boundary itself is
    // tested first so that the prism is closed like every other shape.
    bool inside = false;
    const std::size_t n = poly_.size();
    for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
      const Vec2 &a = poly_[j], &b = poly_[i];
      if (on_segment(p, a, b)) return true;
      if ((a.y() > p.y()) != (b.y() > p.y()) &&
          p.x() < a.x() + (p.y() - a.y()) * (b.x() - a.x()) / (b.y() - a.y()))
        inside = !inside;
    }
    return inside;
  }

  std::optional<Bounds> bounds() const override {
    Bounds b;
    for (const auto& q : poly_) {
      Vec3 lo, hi;
      lo[axis_] = lo_, hi[axis_] = hi_;
      lo[u_] = hi[u_] = q.x();
      lo[v_] = hi[v_] = q.y();
      b.extend(lo), b.extend(hi);
    }
    return b;
  }

  void print(std::string& out) const override {
    out += std::string("prism(") + "xyz"[axis_] + ", " + exact_number_text(lo_) + ", " +
           exact_number_text(hi_);
    for (const auto& q : poly_)
      out += ", " + exact_number_text(q.x()) + ", " + exact_number_text(q.y());
    out += ")";
  }

 private:
  int axis_, u_ = 0, v_ = 1;
  double lo_, hi_;
  std::vector<Vec2> poly_;
};

// ---- set operations ----

enum class SetOperation { Union, Intersection, Difference };

class CombinedZone final : public Zone {
 public:
  CombinedZone(SetOperation op, ZonePtr a, ZonePtr b)
      : op_(op), a_(std::move(a)), b_(std::move(b)) {}

  bool contains(const Vec3& x) const override {
    switch (op_) {
      case SetOperation::Union:
        return a_->contains(x) || b_->contains(x);
      case SetOperation::Intersection:
        return a_->contains(x) && b_->contains(x);
      case SetOperation::Difference:
        return a_->contains(x) && !b_->contains(x);
    }
    return false;
  }

  std::optional<Bounds> bounds() const override {
    const auto a = a_->bounds(), b = b_->bounds();
    switch (op_) {
      case SetOperation::Union:
        if (!a || !b) return std::nullopt;
        return a->merged(*b);
      case SetOperation::Intersection:
        if (!a) return b;
        if (!b) return a;
        return a->intersection(*b);
      case SetOperation::Difference:
        return a;
    }
    return std::nullopt;
  }

  int precedence() const override { return op_ == SetOperation::Intersection ? 2 : 1; }

  // Left-associative operators: the left operand needs parentheses when it binds more loosely,
  // the right one also when it binds as loosely (a - (b - c), a & (b & c)).
  void print(std::string& out) const override {
    print_operand(out, *a_, a_->precedence() < precedence());
    out += op_ == SetOperation::Union ? " | " : op_ == SetOperation::Intersection ? " & " : " - ";
    print_operand(out, *b_, b_->precedence() <= precedence());
  }

  void collect_pilot_summaries(std::vector<PilotSummary>& out) const override {
    a_->collect_pilot_summaries(out);
    b_->collect_pilot_summaries(out);
  }

 private:
  static void print_operand(std::string& out, const Zone& z, bool parenthesise) {
    if (parenthesise) out += "(";
    z.print(out);
    if (parenthesise) out += ")";
  }

  SetOperation op_;
  ZonePtr a_, b_;
};

const char* kAxisNames[3] = {"x", "y", "z"};

}  // namespace

std::string Zone::to_string() const {
  std::string out;
  print(out);
  return out;
}

std::vector<PilotSummary> Zone::pilot_summaries() const {
  std::vector<PilotSummary> out;
  collect_pilot_summaries(out);
  return out;
}

ZonePtr all_zone() {
  return std::make_shared<AllZone>();
}
ZonePtr no_zone() {
  return std::make_shared<NoZone>();
}

ZonePtr box_zone(const Vec3& lower, const Vec3& upper) {
  for (int k = 0; k < 3; ++k)
    if (!(upper[k] > lower[k]))
      throw InputError(std::string("box: upper ") + kAxisNames[k] + " " +
                       exact_number_text(upper[k]) + " is not above lower " + kAxisNames[k] + " " +
                       exact_number_text(lower[k]) +
                       "; valid: box(x0, y0, z0, x1, y1, z1) with x1 > x0, y1 > y0, z1 > z0");
  return std::make_shared<BoxZone>(Bounds(lower, upper));
}

ZonePtr halfspace_zone(const Vec3& point, const Vec3& outward_normal) {
  if (outward_normal == Vec3::Zero())
    throw InputError(
        "halfspace: the normal (0, 0, 0) has no direction; valid: a non-zero normal (nx, ny, nz) "
        "pointing away from the solid side");
  return std::make_shared<HalfspaceZone>(point, outward_normal);
}

ZonePtr sphere_zone(const Vec3& centre, double radius) {
  if (!(radius > 0))
    throw InputError("sphere: radius " + exact_number_text(radius) +
                     " is not valid; valid: a radius > 0 (m)");
  return std::make_shared<SphereZone>(centre, radius);
}

ZonePtr prism_zone(int axis, double lo, double hi, const std::vector<Eigen::Vector2d>& polygon) {
  if (axis < 0 || axis > 2)
    throw InputError("prism: axis " + std::to_string(axis) + "; valid: x, y or z");
  if (!(hi > lo))
    throw InputError("prism: hi " + exact_number_text(hi) + " is not above lo " +
                     exact_number_text(lo) + "; valid: hi > lo along the axis");
  if (polygon.size() < 3)
    throw InputError("prism: " + std::to_string(polygon.size()) +
                     " vertices; valid: at least 3 (u, v) vertices");
  try {
    check_simple(polygon);
  } catch (const InputError& e) {
    throw InputError(std::string("prism: ") + e.what());
  }
  return std::make_shared<PrismZone>(axis, lo, hi, polygon);
}

ZonePtr union_zone(ZonePtr a, ZonePtr b) {
  return std::make_shared<CombinedZone>(SetOperation::Union, std::move(a), std::move(b));
}
ZonePtr intersection_zone(ZonePtr a, ZonePtr b) {
  return std::make_shared<CombinedZone>(SetOperation::Intersection, std::move(a), std::move(b));
}
ZonePtr difference_zone(ZonePtr a, ZonePtr b) {
  return std::make_shared<CombinedZone>(SetOperation::Difference, std::move(a), std::move(b));
}

}  // namespace trackbed::dem
