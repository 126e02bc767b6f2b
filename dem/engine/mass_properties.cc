#include "dem/engine/mass_properties.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <tuple>
#include <utility>

#include <Eigen/Eigenvalues>

#include "common/input_error.h"

namespace trackbed::dem {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Columns per edge of a cut leaf cube. Each column is integrated exactly along its axis, so a
// leaf only approximates across it; 2 x 2 midpoint columns already make the rule exact for a
// plane cut, and refining the octree one level is cheaper than adding columns to every leaf.
constexpr int kColumnsPerEdge = 2;
// Empirical constant of the leading error term, relative error ~ kErrorConstant * s^2 *
// sum(4 pi r) / sum(V) for column spacing s (fitted 0.03 to 0.1 on overlapping pairs and random
// clumps, volume and inertia; docs/clumps.md). It only picks the starting depth, so erring low
// costs one extra coarse level (1/16 of the work) and erring high up to 4 times the work;
// convergence itself is checked, not assumed.
constexpr double kErrorConstant = 0.05;
// Bounds the refinement loop. The finest accepted tolerance, 1e-6, converges at depth 11 or 12
// for ballast-like clumps (about a second); each further level costs four times as much.
constexpr int kMaxLeafDepth = 16;

// Volume, first and second moments about a fixed origin, accumulated as plain sums.
struct Moments {
  double v = 0.0;
  Vec3 s = Vec3::Zero();
  Mat3 j = Mat3::Zero();  // integral of r r^T
};

// Mass properties from moments about `origin`, with the inertia moved to the centroid.
MassProperties from_moments(const Moments& m, const Vec3& origin) {
  MassProperties mp;
  mp.volume = m.v;
  const Vec3 c = m.s / m.v;
  mp.centroid = origin + c;
  const Mat3 jc = m.j - m.v * c * c.transpose();
  mp.inertia = jc.trace() * Mat3::Identity() - jc;
  mp.inertia = 0.5 * (mp.inertia + mp.inertia.transpose());
  set_principal_frame(mp);
  return mp;
}

// Trace of the inertia about the centroid, 2 tr(J - V c c^T): twice the polar moment.
double inertia_trace(const Moments& m) {
  return 2.0 * (m.j.trace() - m.s.squaredNorm() / m.v);
}

// Exact moments of spheres that do not overlap: a sum of solid spheres.
Moments disjoint_sphere_moments(const std::vector<SphereShape>& spheres, const Vec3& origin) {
  Moments m;
  for (const SphereShape& sp : spheres) {
    const double r2 = sp.radius * sp.radius;
    const double v = 4.0 / 3.0 * kPi * r2 * sp.radius;
    const Vec3 c = sp.centre - origin;
    m.v += v;
    m.s += v * c;
    // A solid sphere's integral of x^2 about its centre is V r^2 / 5 per axis.
    m.j += v * (c * c.transpose() + r2 / 5.0 * Mat3::Identity());
  }
  return m;
}

// Drops spheres that lie inside another sphere: they add nothing to the union and would only
// slow the cubature down. Of identical spheres, the first is kept.
std::vector<SphereShape> without_contained_spheres(const std::vector<SphereShape>& spheres) {
  std::vector<size_t> order(spheres.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  // Largest first, so a sphere can only be contained in one already kept.
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return spheres[a].radius > spheres[b].radius; });
  std::vector<SphereShape> kept;
  for (size_t i : order) {
    const SphereShape& sp = spheres[i];
    const bool contained = std::any_of(kept.begin(), kept.end(), [&](const SphereShape& k) {
      return (sp.centre - k.centre).norm() + sp.radius <= k.radius;
    });
    if (!contained) kept.push_back(sp);
  }
  return kept;
}

bool any_overlap(const std::vector<SphereShape>& spheres) {
  for (size_t i = 0; i < spheres.size(); ++i) {
    for (size_t k = i + 1; k < spheres.size(); ++k) {
      const double reach = spheres[i].radius + spheres[k].radius;
      if ((spheres[i].centre - spheres[k].centre).squaredNorm() < reach * reach) return true;
    }
  }
  return false;
}

// Adaptive octree cubature of the union of spheres, all leaves at one depth. A cube inside one
// sphere or outside all of them is integrated exactly; a cube still cut at the leaf depth is
// integrated by 2 x 2 columns, each exact along its axis (the union of the spheres' chords,
// clipped to the cube) and sampled at its midpoint across it.
class OctreeCubature {
 public:
  // `spheres` are relative to the centre of the root cube of half-size `root_half`.
  OctreeCubature(const std::vector<SphereShape>& spheres, double root_half)
      : spheres_(spheres), root_half_(root_half) {}

  Moments integrate(int leaf_depth) {
    leaf_depth_ = leaf_depth;
    m_ = Moments();
    candidates_.assign(leaf_depth + 2, std::vector<int>(spheres_.size()));
    intervals_.resize(spheres_.size());
    for (size_t i = 0; i < spheres_.size(); ++i) candidates_[0][i] = static_cast<int>(i);
    visit(Vec3::Zero(), root_half_, 0, static_cast<int>(spheres_.size()));
    m_.j = m_.j.selfadjointView<Eigen::Upper>();
    return m_;
  }

 private:
  // `ncand` spheres in candidates_[depth] may meet this cube; all others are known to miss it.
  void visit(const Vec3& c, double half, int depth, int ncand) {
    const std::vector<int>& cand = candidates_[depth];
    std::vector<int>& cut = candidates_[depth + 1];
    int ncut = 0;
    for (int i = 0; i < ncand; ++i) {
      const SphereShape& sp = spheres_[cand[i]];
      const Vec3 d = (sp.centre - c).cwiseAbs();
      const double r2 = sp.radius * sp.radius;
      if ((d.array() + half).matrix().squaredNorm() <= r2) {
        add_full_cube(c, half);
        return;
      }
      if ((d.array() - half).max(0.0).matrix().squaredNorm() < r2) cut[ncut++] = cand[i];
    }
    if (ncut == 0) return;
    if (depth == leaf_depth_) {
      add_columns(c, half, ncut);
      return;
    }
    const double h = 0.5 * half;
    for (int octant = 0; octant < 8; ++octant) {
      const Vec3 child(c.x() + ((octant & 1) ? h : -h), c.y() + ((octant & 2) ? h : -h),
                       c.z() + ((octant & 4) ? h : -h));
      visit(child, h, depth + 1, ncut);
    }
  }

  void add_full_cube(const Vec3& c, double half) {
    const double edge = 2.0 * half;
    const double v = edge * edge * edge;
    m_.v += v;
    m_.s += v * c;
    m_.j.triangularView<Eigen::Upper>() +=
        v * (c * c.transpose() + edge * edge / 12.0 * Mat3::Identity());
  }

  // The cut spheres are candidates_[leaf_depth_ + 1][0, ncut). Columns run along the axis
  // closest to the normal of the nearest sphere surface: there the surface is a smooth graph over
  // the column footprint, whereas columns grazing a sphere's silhouette see a square-root
  // singularity that makes the midpoint rule's error erratic instead of second order.
  void add_columns(const Vec3& c, double half, int ncut) {
    const std::vector<int>& cut = candidates_[leaf_depth_ + 1];
    Vec3 normal = Vec3::UnitZ();
    double nearest = std::numeric_limits<double>::infinity();
    for (int k = 0; k < ncut; ++k) {
      const Vec3 d = c - spheres_[cut[k]].centre;
      const double gap = std::abs(d.norm() - spheres_[cut[k]].radius);
      if (gap < nearest) {
        nearest = gap;
        normal = d;
      }
    }
    Eigen::Index w = 2;
    normal.cwiseAbs().maxCoeff(&w);
    const Eigen::Index u = (w + 1) % 3, t = (w + 2) % 3;

    const double spacing = 2.0 * half / kColumnsPerEdge;
    const double area = spacing * spacing;
    const double w_lo = c(w) - half;
    const double w_hi = c(w) + half;
    for (int iu = 0; iu < kColumnsPerEdge; ++iu) {
      const double x = c(u) - half + (iu + 0.5) * spacing;
      for (int it = 0; it < kColumnsPerEdge; ++it) {
        const double y = c(t) - half + (it + 0.5) * spacing;
        int n = 0;
        for (int k = 0; k < ncut; ++k) {
          const SphereShape& sp = spheres_[cut[k]];
          const double dx = x - sp.centre(u);
          const double dy = y - sp.centre(t);
          const double chord2 = sp.radius * sp.radius - dx * dx - dy * dy;
          if (chord2 <= 0.0) continue;
          const double half_chord = std::sqrt(chord2);
          const double lo = std::max(sp.centre(w) - half_chord, w_lo);
          const double hi = std::min(sp.centre(w) + half_chord, w_hi);
          if (lo < hi) intervals_[n++] = {lo, hi};
        }
        if (n == 0) continue;
        // Union of the chords: sort by start, merge overlaps, integrate 1, z, z^2 exactly.
        std::sort(intervals_.begin(), intervals_.begin() + n);
        double length = 0.0, z1 = 0.0, z2 = 0.0;
        double lo = intervals_[0].first, hi = intervals_[0].second;
        for (int k = 1; k <= n; ++k) {
          if (k < n && intervals_[k].first <= hi) {
            hi = std::max(hi, intervals_[k].second);
            continue;
          }
          length += hi - lo;
          z1 += 0.5 * (hi * hi - lo * lo);
          z2 += (hi * hi * hi - lo * lo * lo) / 3.0;
          if (k < n) std::tie(lo, hi) = intervals_[k];
        }
        // (x, y, z) are the column's (u, t, w) coordinates. The column's own width adds
        // spacing^2 / 12 to the second moments across it, as for a full cube.
        const double v = area * length;
        const double width_term = spacing * spacing / 12.0;
        m_.v += v;
        m_.s(u) += x * v;
        m_.s(t) += y * v;
        m_.s(w) += area * z1;
        m_.j(u, u) += v * (x * x + width_term);
        m_.j(t, t) += v * (y * y + width_term);
        m_.j(w, w) += area * z2;
        m_.j(std::min(u, t), std::max(u, t)) += v * x * y;
        m_.j(std::min(u, w), std::max(u, w)) += area * x * z1;
        m_.j(std::min(t, w), std::max(t, w)) += area * y * z1;
      }
    }
  }

  const std::vector<SphereShape>& spheres_;
  const double root_half_;
  int leaf_depth_ = 0;
  Moments m_;
  // candidates_[d]: spheres that may meet the cube being visited at depth d (a stack, one row
  // per depth, so the recursion allocates nothing).
  std::vector<std::vector<int>> candidates_;
  std::vector<std::pair<double, double>> intervals_;
};

void validate(const std::vector<SphereShape>& spheres, double relative_tolerance) {
  if (spheres.empty()) {
    throw InputError("clump has no spheres; a clump needs at least one sphere");
  }
  for (size_t i = 0; i < spheres.size(); ++i) {
    const SphereShape& sp = spheres[i];
    std::ostringstream where;
    where << "clump sphere " << i + 1 << " of " << spheres.size() << ": ";
    if (!(std::isfinite(sp.radius) && sp.radius > 0.0)) {
      where << "radius " << sp.radius << " is not valid; a radius must be finite and > 0";
      throw InputError(where.str());
    }
    if (!sp.centre.allFinite()) {
      where << "centre (" << sp.centre.transpose() << ") is not valid; coordinates must be finite";
      throw InputError(where.str());
    }
  }
  if (!(relative_tolerance >= 1e-6 && relative_tolerance <= 0.1)) {
    std::ostringstream msg;
    msg << "clump mass properties: relative tolerance " << relative_tolerance
        << " is not valid; it must be in [1e-6, 0.1]";
    throw InputError(msg.str());
  }
}

}  // namespace

void set_principal_frame(MassProperties& mp) {
  const Eigen::SelfAdjointEigenSolver<Mat3> solver(mp.inertia);
  mp.principal_moments = solver.eigenvalues();
  Mat3 axes = solver.eigenvectors();
  for (int k = 0; k < 2; ++k) {
    Eigen::Index largest = 0;
    axes.col(k).cwiseAbs().maxCoeff(&largest);
    if (axes(largest, k) < 0.0) axes.col(k) = -axes.col(k);
  }
  axes.col(2) = axes.col(0).cross(axes.col(1)).normalized();
  mp.principal_axes = axes;
}

MassProperties sphere_union_mass_properties(const std::vector<SphereShape>& spheres,
                                            double relative_tolerance) {
  validate(spheres, relative_tolerance);
  const std::vector<SphereShape> kept = without_contained_spheres(spheres);

  Vec3 lo = kept[0].centre.array() - kept[0].radius;
  Vec3 hi = kept[0].centre.array() + kept[0].radius;
  double sum_radii = 0.0, sum_volumes = 0.0;
  for (const SphereShape& sp : kept) {
    lo = lo.cwiseMin((sp.centre.array() - sp.radius).matrix());
    hi = hi.cwiseMax((sp.centre.array() + sp.radius).matrix());
    sum_radii += sp.radius;
    sum_volumes += 4.0 / 3.0 * kPi * std::pow(sp.radius, 3);
  }
  // Moments are taken about the box centre so that a clump far from the origin loses no digits
  // to cancellation when the inertia is moved to the centroid.
  const Vec3 origin = 0.5 * (lo + hi);
  if (!any_overlap(kept)) return from_moments(disjoint_sphere_moments(kept, origin), origin);

  std::vector<SphereShape> local = kept;
  for (SphereShape& sp : local) sp.centre -= origin;
  const double root_half = 0.5 * (hi - lo).maxCoeff();
  OctreeCubature cubature(local, root_half);

  // Starting depth from the error model (docs/clumps.md): the absolute error is about
  // kErrorConstant * s^2 * sum(4 pi r), s the column spacing. Solved for the s at which the
  // relative error meets the tolerance, with the sum of sphere volumes standing in for the
  // union's; the first estimate is one level coarser, as the check compares two levels.
  const double target_spacing =
      std::sqrt(relative_tolerance * sum_volumes / (4.0 * kPi * kErrorConstant * sum_radii));
  const double columns_per_root_edge = 2.0 * root_half / target_spacing;
  int depth = std::max(
      1, static_cast<int>(std::ceil(std::log2(columns_per_root_edge / kColumnsPerEdge))) - 1);

  // Successive refinement. Each level halves the column spacing and the error, second order in
  // it, drops fourfold (observed ratios 3.6 to 4.9), so (fine - coarse) / 3 estimates the error
  // of `fine`; refinement stops when that estimate meets the tolerance in volume and in the trace
  // of the inertia. The returned Richardson extrapolation, fine + (fine - coarse) / 3, removes
  // the s^2 term and is more accurate than that estimate (tests: by a factor 10 or more).
  Moments coarse = cubature.integrate(depth);
  for (++depth; depth <= kMaxLeafDepth; ++depth) {
    const Moments fine = cubature.integrate(depth);
    const double trace_coarse = inertia_trace(coarse), trace_fine = inertia_trace(fine);
    if (std::abs(fine.v - coarse.v) / 3.0 <= relative_tolerance * fine.v &&
        std::abs(trace_fine - trace_coarse) / 3.0 <= relative_tolerance * trace_fine) {
      Moments extrapolated;
      extrapolated.v = fine.v + (fine.v - coarse.v) / 3.0;
      extrapolated.s = fine.s + (fine.s - coarse.s) / 3.0;
      extrapolated.j = fine.j + (fine.j - coarse.j) / 3.0;
      return from_moments(extrapolated, origin);
    }
    coarse = fine;
  }
  std::ostringstream msg;
  msg << "clump of " << spheres.size() << " spheres: mass properties did not converge to relative"
      << " tolerance " << relative_tolerance << " at octree depth " << kMaxLeafDepth
      << "; use a larger tolerance (at most 0.1)";
  throw InputError(msg.str());
}

}  // namespace trackbed::dem
