// The contact history of a Simulation (its springs), shared by the files that implement the
// class: simulation.cc (forces) and contact_state.cc (saving and restoring the springs). Not for
// use outside the engine.
#pragma once

#include <vector>

#include "dem/engine/simulation.h"

namespace trackbed::dem {

// History of the particle-particle springs, aligned with the neighbour list.
struct Simulation::PairHistory {
  std::vector<Vec3> shear;
  std::vector<Vec3> roll;  // empty unless some pair has rolling resistance
  std::vector<double> fn;  // normal force of the last step (0: not touching)
};

// Candidates of one wall: elements within reach at the last build, with their history. For a
// mesh, an element can touch up to kSlots features at once (a concave corner).
struct Simulation::WallHistory {
  static constexpr int kSlots = 4;
  std::vector<int> element;
  // Plane walls: one slot. Meshes: kSlots per element, plus the candidate triangles.
  std::vector<Vec3> shear, roll, normal;
  std::vector<double> fn;
  std::vector<int> triangle_offsets, triangles;
};

}  // namespace trackbed::dem
