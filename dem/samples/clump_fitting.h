// Fitting clumps into a packing without overlaps (docs/samples.md, "Converting balls to clumps"):
// a clump about to replace a ball may start at the largest scale g <= 1 at which its pebbles,
// shrunk about its centroid, clear every other body as it stands, the base, the crib walls, a
// box's side walls and the sleeper. The conversion tries several random orientations and keeps the
// one that fits largest, so the clumps start touching their neighbours and the bed never loses its
// support.
#pragma once

#include <cstdint>
#include <unordered_map>
#include <vector>

#include "common/track_section.h"
#include "dem/engine/particles.h"

namespace trackbed::dem {

class ClumpFitter {
 public:
  // Obstacles: every element of `p`; the section gives the base, the crib walls (unless
  // periodic), the side walls (a box) and the sleeper, standing `sleeper_lift` above its design
  // position.
  ClumpFitter(const Particles& p, const TrackSection& section, double sleeper_lift);

  // Removes body b of the particles given at construction (the ball being replaced).
  void remove_body(int b);
  // Adds spheres (world frame) as obstacles.
  void add(const std::vector<SphereShape>& spheres);
  // The largest g in [0, 1] at which the spheres centred at x + g c_k with radii g r_k clear
  // every obstacle (c_k: offsets in the world frame, already rotated).
  double fit(const Vec3& x, const std::vector<SphereShape>& offsets) const;

 private:
  std::int64_t key(const Vec3& x) const;
  void insert(const SphereShape& s, int index);
  // The largest g with sphere (x + g c, g r) clear of obstacle sphere o, or of the sleeper.
  double clear_of_sphere(const Vec3& x, const SphereShape& pebble, const SphereShape& o) const;
  double clear_of_sleeper(const Vec3& x, const SphereShape& pebble) const;

  TrackSection section_;
  double sleeper_lift_;
  double cell_;
  std::vector<SphereShape> spheres_;
  std::vector<char> alive_;
  std::vector<int> first_of_body_;  // obstacle indices of body b: [first[b], first[b + 1])
  std::unordered_map<std::int64_t, std::vector<int>> grid_;
  double max_radius_ = 0;
};

}  // namespace trackbed::dem
