// The particles of a DEM model: rigid bodies (balls and clumps) and their sphere elements, in flat
// arrays (one array per quantity) so the hot loops stream through memory.
//
// A ball is a body with one element at its centre. A clump is a body with several elements fixed
// in its principal frame. Bodies carry the dynamics (position of the centre of mass, velocity,
// orientation, angular momentum); elements carry the geometry the contact search sees.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "dem/engine/clump_template.h"
#include "dem/engine/types.h"

namespace trackbed::dem {

struct Particles {
  // ---- bodies ----
  std::vector<Vec3> x;             // centre of mass, m
  std::vector<Vec3> v;             // velocity, m/s (mid-step in the leapfrog scheme)
  std::vector<Quat> q;             // principal frame -> world
  std::vector<Vec3> w;             // angular velocity in the world frame, rad/s
  std::vector<Vec3> L;             // angular momentum in the world frame (clumps), kg m^2/s
  std::vector<Vec3> f;             // resultant force, N
  std::vector<Vec3> t;             // resultant moment about the centre of mass, N m
  std::vector<double> mass;        // kg
  std::vector<Vec3> inertia;       // principal moments, kg m^2
  std::vector<int> body_material;  // for local damping and output
  std::vector<int> first_element;  // elements of body b: [first_element[b], first_element[b+1])
  std::vector<std::int64_t> id;    // user-visible id (row of the particle file)
  std::vector<std::uint8_t> is_clump;

  // ---- elements (spheres) ----
  std::vector<Vec3> pos;     // world position of the sphere centre
  std::vector<Vec3> offset;  // centre in the body's principal frame
  std::vector<double> radius;
  std::vector<int> body;  // owning body
  std::vector<int> material;

  int num_bodies() const { return static_cast<int>(x.size()); }
  int num_elements() const { return static_cast<int>(pos.size()); }
  int num_clumps() const;

  // Adds a ball; returns its body index.
  int add_ball(const Vec3& centre, double r, int mat, double density, std::int64_t user_id);
  // Adds a clump made from a template (already in its principal frame, see clump_template.h),
  // with its centroid at `centre` and principal frame rotated by `orientation`.
  int add_clump(const ClumpTemplate& tmpl, const Vec3& centre, const Quat& orientation, int mat,
                double density, std::int64_t user_id);
  // Adds a body given completely: centre of mass, orientation of its principal frame, mass,
  // principal moments and its elements (centres in the principal frame, radii; one material).
  // A ball is a body with one element at offset zero and is_clump false. Used to restore a
  // saved sample exactly.
  int add_body_with_elements(const Vec3& centre, const Quat& orientation, double m, const Vec3& I,
                             int mat, bool clump, std::int64_t user_id,
                             const std::vector<SphereShape>& elements);
  // The bodies with keep[b] true, in their current order, with their full state.
  Particles subset(const std::vector<char>& keep) const;

  // The first broken invariant of a state read from a file, in words ("" when it holds): array
  // sizes, the element ranges and owners, material indices below `num_materials`, finite state,
  // positive mass, inertia and radii, unit quaternions, distinct non-negative ids. A damaged file
  // must be refused before an index or a NaN reaches the engine.
  std::string defect(int num_materials) const;

  // Reorders the bodies (and their elements) along a space-filling order of cells of size
  // `cell`, so that neighbours in space are neighbours in memory: the contact loop then reads
  // mostly from cache. Ids are kept; only indices change.
  void sort_spatially(double cell);
  // Recomputes element world positions from the body state: of all bodies, of body b.
  void update_element_positions(bool parallel = true);
  void update_body_elements(int b);
  // World-frame inertia tensor of body b.
  Mat3 world_inertia(int b) const;
  double kinetic_energy() const;
  double max_element_radius() const;
  // Largest distance of a point of body b's elements from its centre of mass.
  double bounding_radius(int b) const;

 private:
  int add_body(const Vec3& centre, const Quat& q, double m, const Vec3& I, int mat, bool clump,
               std::int64_t user_id);
};

}  // namespace trackbed::dem
