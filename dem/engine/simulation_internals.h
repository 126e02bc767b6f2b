// What the files that implement Simulation share and its users need not see: the per-thread
// force accumulators and the walk over the live mesh contacts.
#pragma once

#include <algorithm>
#include <vector>

#include "dem/engine/contact_history.h"
#include "dem/engine/simulation.h"

namespace trackbed::dem {

// Per-thread force accumulators (thread 0 writes the real arrays).
struct Simulation::ThreadScratch {
  // Thread 0 accumulates into the particles' own force and moment arrays, the others into these.
  std::vector<Vec3> f, t;
  std::vector<Vec3> wall_f, wall_t;               // per plane, then per mesh body
  std::vector<Vec3> wall_k, wall_kr;              // contact stiffness along each DOF
  std::vector<std::vector<Vec3>> part_f, part_t;  // per mesh body, per part
  std::vector<std::vector<Vec3>> vertex_f;  // per mesh body, per vertex (deformable ones only)
  Dissipation dissipation;
  double max_overlap_ratio = 0;
  int worst_i = -1, worst_j = -1;  // worst_i = -2 - wall index for a wall contact
  std::vector<MeshContactPoint> mesh_points;
};

// Calls visit(mesh, contact, element, point, slot) for every contact point of every mesh contact
// as it is now (used in the set-up checks and the diagnostics).
template <class Visitor>
void Simulation::visit_mesh_contacts(Visitor&& visit) const {
  std::vector<MeshContactPoint> points;
  for (std::size_t m = 0; m < meshes_.size(); ++m) {
    const WallHistory& h = plane_history_[planes_.size() + m];
    for (std::size_t c = 0; c < h.element.size(); ++c) {
      const int e = h.element[c];
      mesh_points_now(m, c, points);
      const int used = std::min<int>(static_cast<int>(points.size()), WallHistory::kSlots);
      for (int a = 0; a < used; ++a)
        visit(static_cast<int>(m), static_cast<int>(c), e, points[a], a);
    }
  }
}

}  // namespace trackbed::dem
