#include "dem/samples/clump_fitting.h"

#include <algorithm>
#include <cmath>

namespace trackbed::dem {

ClumpFitter::ClumpFitter(const Particles& p, const TrackSection& section, double sleeper_lift)
    : section_(section),
      sleeper_lift_(sleeper_lift),
      cell_(2 * std::max(p.max_element_radius(), 1e-6)) {
  first_of_body_.push_back(0);
  for (int b = 0; b < p.num_bodies(); ++b) {
    std::vector<SphereShape> elements;
    for (int e = p.first_element[b]; e < p.first_element[b + 1]; ++e)
      elements.push_back({p.pos[e], p.radius[e]});
    add(elements);
    first_of_body_.push_back(static_cast<int>(spheres_.size()));
  }
}

std::int64_t ClumpFitter::key(const Vec3& x) const {
  const auto i = static_cast<std::int64_t>(std::floor(x.x() / cell_));
  const auto j = static_cast<std::int64_t>(std::floor(x.y() / cell_));
  const auto k = static_cast<std::int64_t>(std::floor(x.z() / cell_));
  return (i * 73856093) ^ (j * 19349663) ^ (k * 83492791);
}

void ClumpFitter::insert(const SphereShape& s, int index) {
  grid_[key(s.centre)].push_back(index);
}

void ClumpFitter::add(const std::vector<SphereShape>& spheres) {
  for (const SphereShape& s : spheres) {
    spheres_.push_back(s);
    alive_.push_back(1);
    max_radius_ = std::max(max_radius_, s.radius);
    insert(s, static_cast<int>(spheres_.size()) - 1);
  }
}

void ClumpFitter::remove_body(int b) {
  for (int i = first_of_body_[b]; i < first_of_body_[b + 1]; ++i) alive_[i] = 0;
}

double ClumpFitter::clear_of_sphere(const Vec3& x, const SphereShape& pebble,
                                    const SphereShape& o) const {
  // |g c - d|^2 = (g r + rho)^2 with d = o - x: f(g) = A g^2 + B g + C, f(0) = C > 0 when the
  // clump's centre lies outside the obstacle; the first positive root is where they touch.
  const Vec3 d = o.centre - x;
  const double A = pebble.centre.squaredNorm() - pebble.radius * pebble.radius;
  const double B = -2 * (pebble.centre.dot(d) + pebble.radius * o.radius);
  const double C = d.squaredNorm() - o.radius * o.radius;
  if (C <= 0) return 0;
  double first = 1;
  if (std::abs(A) < 1e-300) {
    if (B < 0) first = -C / B;
  } else {
    const double disc = B * B - 4 * A * C;
    if (disc < 0) return 1;  // A > 0 here: never touching
    const double q = std::sqrt(disc);
    for (double g : {(-B - q) / (2 * A), (-B + q) / (2 * A)})
      if (g > 0) first = std::min(first, g);
  }
  return std::min(first, 1.0);
}

double ClumpFitter::clear_of_sleeper(const Vec3& x, const SphereShape& pebble) const {
  auto gap = [&](double g) {
    return section_.distance_to_sleeper(x + g * pebble.centre, sleeper_lift_) - g * pebble.radius;
  };
  if (gap(1) >= 0) return 1;
  if (gap(0) <= 0) return 0;
  double lo = 0, hi = 1;  // gap(lo) > 0 >= gap(hi)
  for (int k = 0; k < 40; ++k) {
    const double mid = 0.5 * (lo + hi);
    (gap(mid) > 0 ? lo : hi) = mid;
  }
  return lo;
}

double ClumpFitter::fit(const Vec3& x, const std::vector<SphereShape>& offsets) const {
  double g = 1;
  double reach = 0;
  for (const SphereShape& s : offsets) reach = std::max(reach, s.centre.norm() + s.radius);
  const int n = static_cast<int>(std::ceil((reach + max_radius_) / cell_));
  const double half_length = 0.5 * section_.length;
  for (const SphereShape& s : offsets) {
    // The base (z >= 0) and the crib walls: linear in g.
    const double below = s.radius - s.centre.z();
    if (below > 0) g = std::min(g, x.z() / below);
    if (!section_.periodic) {
      if (s.centre.y() + s.radius > 0)
        g = std::min(g, std::max(0.0, half_length - x.y()) / (s.centre.y() + s.radius));
      if (s.centre.y() - s.radius < 0)
        g = std::min(g, std::max(0.0, half_length + x.y()) / (s.radius - s.centre.y()));
    }
    if (section_.side_walls) {
      const double half_width = section_.half_base_width();
      if (s.centre.x() + s.radius > 0)
        g = std::min(g, std::max(0.0, half_width - x.x()) / (s.centre.x() + s.radius));
      if (s.centre.x() - s.radius < 0)
        g = std::min(g, std::max(0.0, half_width + x.x()) / (s.radius - s.centre.x()));
    }
    g = std::min(g, clear_of_sleeper(x, s));
  }
  for (int i = -n; i <= n; ++i)
    for (int j = -n; j <= n; ++j)
      for (int k = -n; k <= n; ++k) {
        const auto it = grid_.find(key(x + cell_ * Vec3(i, j, k)));
        if (it == grid_.end()) continue;
        for (const int o : it->second) {
          if (!alive_[o]) continue;
          const SphereShape& obstacle = spheres_[o];
          if ((obstacle.centre - x).norm() > reach + obstacle.radius) continue;
          for (const SphereShape& s : offsets) g = std::min(g, clear_of_sphere(x, s, obstacle));
        }
      }
  return std::max(g, 0.0);
}

}  // namespace trackbed::dem
