#include "dem/samples/ballast_stone.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <sstream>
#include <vector>

#include "common/input_error.h"
#include "dem/samples/closed_surface.h"
#include "dem/samples/convex_hull.h"

namespace trackbed::dem {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Union-find with path halving: the triangles of one plane face end up under one root.
int find_root(std::vector<int>& parent, int i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

// Uniform in [0, 1) from the top 53 bits: std::uniform_real_distribution is implementation
// defined, this is not.
double uniform(std::mt19937_64& rng) {
  return static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

double uniform(std::mt19937_64& rng, double lo, double hi) {
  return lo + (hi - lo) * uniform(rng);
}

int uniform_int(std::mt19937_64& rng, int lo, int hi) {
  return std::min(hi, lo + static_cast<int>(uniform(rng) * (hi - lo + 1)));
}

// A uniformly distributed unit vector (Archimedes: z is uniform on [-1, 1]).
Vec3 random_direction(std::mt19937_64& rng) {
  const double z = uniform(rng, -1.0, 1.0);
  const double phi = uniform(rng, 0.0, 2.0 * kPi);
  const double s = std::sqrt(std::max(0.0, 1.0 - z * z));
  return Vec3(s * std::cos(phi), s * std::sin(phi), z);
}

// The shape's knobs (docs/templates.md gives the resulting indices and the ballast they mimic).
// The ellipsoid has semi-axes 1 >= b >= c with b = elongation and c = b * flatness. Six points lie
// near the ends of its axes (moved off them by kAxisTilt), so that the stone's L : I : S follow
// 1 : b : c, and 4 to 10 more anywhere on it; each is pushed in or out by up to kRadialJitter.
// Up to kMaxCuts caps, each a share kMinCutDepth to kMaxCutDepth of the stone's width along a
// random direction, are cut off as crushed faces.
constexpr double kMinElongation = 0.55, kMaxElongation = 0.9;
constexpr double kMinFlatness = 0.55, kMaxFlatness = 0.9;
constexpr double kAxisTilt = 0.15;
constexpr int kMinPoints = 4, kMaxPoints = 10;
constexpr double kRadialJitter = 0.12;
constexpr int kMaxCuts = 3;
constexpr double kMinCutDepth = 0.08, kMaxCutDepth = 0.2;

// The hull of the mesh's part on the inner side of the plane n.x = offset: its vertices there
// and the points where its edges cross the plane.
TriangleMesh cut(const TriangleMesh& mesh, const Vec3& n, double offset) {
  std::vector<Vec3> kept;
  for (const Vec3& v : mesh.vertices) {
    if (n.dot(v) <= offset) kept.push_back(v);
  }
  for (const auto& e : mesh.edge_vertices) {
    const Vec3& a = mesh.vertices[e[0]];
    const Vec3& b = mesh.vertices[e[1]];
    const double da = n.dot(a) - offset, db = n.dot(b) - offset;
    if (da * db < 0.0) kept.push_back(a + (b - a) * (da / (da - db)));
  }
  return convex_hull(kept);
}

void check_settings(const BallastStoneSettings& s) {
  if (!(std::isfinite(s.min_sieve_size) && std::isfinite(s.max_sieve_size) &&
        s.min_sieve_size > 0.0 && s.min_sieve_size <= s.max_sieve_size)) {
    std::ostringstream msg;
    msg << "ballast stone: sieve sizes " << s.min_sieve_size << " to " << s.max_sieve_size
        << " m are not valid; they must be finite with 0 < min <= max";
    throw InputError(msg.str());
  }
}

}  // namespace

double box_sieve_size(double a, double b, double c) {
  double e[3] = {a, b, c};
  std::sort(e, e + 3);  // shortest, intermediate, longest
  return std::min(e[1], (e[1] + e[0]) / std::sqrt(2.0));
}

double clump_sieve_size(const ClumpTemplate& clump) {
  Vec3 lo = Vec3::Constant(INFINITY), hi = Vec3::Constant(-INFINITY);
  for (const SphereShape& s : clump.spheres) {
    lo = lo.cwiseMin(s.centre - Vec3::Constant(s.radius));
    hi = hi.cwiseMax(s.centre + Vec3::Constant(s.radius));
  }
  const Vec3 extent = hi - lo;
  return box_sieve_size(extent.x(), extent.y(), extent.z());
}

ShapeIndices shape_indices(const TriangleMesh& closed_surface) {
  const TriangleMesh& mesh = closed_surface;
  const MassProperties mp = surface_mass_properties(mesh);
  ShapeIndices s;

  Vec3 extent;
  for (int k = 0; k < 3; ++k) {
    double lo = mp.principal_axes.col(k).dot(mesh.vertices[0]), hi = lo;
    for (const Vec3& v : mesh.vertices) {
      const double x = mp.principal_axes.col(k).dot(v);
      lo = std::min(lo, x);
      hi = std::max(hi, x);
    }
    extent[k] = hi - lo;
  }
  std::sort(extent.data(), extent.data() + 3);
  s.longest = extent[2];
  s.intermediate = extent[1];
  s.shortest = extent[0];
  s.elongation = s.intermediate / s.longest;
  s.flatness = s.shortest / s.intermediate;
  s.sieve_size = box_sieve_size(s.longest, s.intermediate, s.shortest);

  double area = 0.0;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& tri = mesh.triangles[t];
    area += 0.5 * (mesh.vertices[tri[1]] - mesh.vertices[tri[0]])
                      .cross(mesh.vertices[tri[2]] - mesh.vertices[tri[0]])
                      .norm();
  }
  s.sphericity = std::cbrt(36.0 * kPi * mp.volume * mp.volume) / area;

  // Every edge of a closed surface has two triangles; the exterior dihedral angle is the angle
  // between their normals.
  const double flat = kFlatEdgeAngleDegrees * kPi / 180.0;
  std::vector<int> parent(mesh.triangles.size());
  std::iota(parent.begin(), parent.end(), 0);
  double weighted = 0.0, creased_length = 0.0;
  for (int e = 0; e < mesh.num_edges; ++e) {
    const int t1 = mesh.edge_triangles[mesh.edge_triangle_offsets[e]];
    const int t2 = mesh.edge_triangles[mesh.edge_triangle_offsets[e] + 1];
    const Vec3 n1 = mesh.triangle_normal(t1), n2 = mesh.triangle_normal(t2);
    const double angle = std::atan2(n1.cross(n2).norm(), n1.dot(n2));
    if (angle < flat) {
      parent[find_root(parent, t1)] = find_root(parent, t2);
      continue;
    }
    const double length =
        (mesh.vertices[mesh.edge_vertices[e][1]] - mesh.vertices[mesh.edge_vertices[e][0]]).norm();
    weighted += length * angle;
    creased_length += length;
  }
  s.angularity = creased_length > 0.0 ? weighted / creased_length * 180.0 / kPi : 0.0;
  for (std::size_t t = 0; t < parent.size(); ++t) {
    if (find_root(parent, static_cast<int>(t)) == static_cast<int>(t)) ++s.faces;
  }
  return s;
}

TriangleMesh make_ballast_stone(std::uint64_t seed, const BallastStoneSettings& settings) {
  check_settings(settings);
  std::mt19937_64 rng(seed);
  const double b = uniform(rng, kMinElongation, kMaxElongation);
  const double c = b * uniform(rng, kMinFlatness, kMaxFlatness);
  const auto on_ellipsoid = [&](const Vec3& direction) {
    const double radial = 1.0 + uniform(rng, -kRadialJitter, kRadialJitter);
    return Vec3(radial * direction.x(), radial * b * direction.y(), radial * c * direction.z());
  };
  std::vector<Vec3> points;
  for (int k = 0; k < 6; ++k) {
    Vec3 axis = Vec3::Zero();
    axis[k / 2] = k % 2 == 0 ? 1.0 : -1.0;
    points.push_back(on_ellipsoid(axis + kAxisTilt * random_direction(rng)));
  }
  const int n_points = uniform_int(rng, kMinPoints, kMaxPoints);
  for (int i = 0; i < n_points; ++i) points.push_back(on_ellipsoid(random_direction(rng)));
  TriangleMesh stone = convex_hull(points);

  const int n_cuts = uniform_int(rng, 0, kMaxCuts);
  for (int i = 0; i < n_cuts; ++i) {
    const Vec3 n = random_direction(rng);
    double lo = n.dot(stone.vertices[0]), hi = lo;
    for (const Vec3& v : stone.vertices) {
      lo = std::min(lo, n.dot(v));
      hi = std::max(hi, n.dot(v));
    }
    stone = cut(stone, n, hi - uniform(rng, kMinCutDepth, kMaxCutDepth) * (hi - lo));
  }

  // Principal frame of the solid, then the drawn sieve size.
  const MassProperties mp = surface_mass_properties(stone);
  stone.translate(-mp.centroid);
  stone.rotate(mp.principal_axes.transpose(), Vec3::Zero());
  const double sieve = uniform(rng, settings.min_sieve_size, settings.max_sieve_size);
  stone.scale(sieve / shape_indices(stone).sieve_size, Vec3::Zero());
  stone.part_names = {"stone"};
  return stone;
}

}  // namespace trackbed::dem
