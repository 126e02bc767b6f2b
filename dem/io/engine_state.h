// The complete state of a set-up DEM model, for checkpoints: everything a step reads that the
// model's input does not give. Bodies and elements in their current order, the motion, controls
// and loads of walls and meshes, the clock, the energy tallies, and the neighbour list with its
// contact springs as they stand. The list is saved, not rebuilt on restore: a list rebuilt from
// other positions lists other pairs and sums the forces in another order, and the run would part
// from the original at round-off. A model built from the same input and given this state steps
// on bit for bit as the saved one (with the same number of threads). Format: docs/formats.md,
// "Checkpoints".
#pragma once

#include <hdf5.h>

#include <array>
#include <string>
#include <utility>
#include <vector>

#include "dem/engine/mesh_body.h"
#include "dem/engine/particles.h"
#include "dem/engine/plane_wall.h"
#include "dem/engine/simulation.h"

namespace trackbed::dem {

struct EngineState {
  Particles particles;
  double time = 0, time_step = 0;
  long steps = 0;
  int builds = 0;
  Vec3 gravity = Vec3::Zero();
  EnergyBudget tally;  // dissipation and work accumulated (kinetic and strain are recomputed)

  // Planes: their motion and last loads (name, normal and material come from the input).
  struct Plane {
    std::string name;
    Vec3 point, velocity, force, moment;
  };
  std::vector<Plane> planes;
  // Meshes: pose, motion, controls and last loads (geometry, mass and material from the input).
  struct Mesh {
    std::string name;
    Vec3 x, v, w;
    Quat q;
    std::array<DofControl, 6> dof;
    Vec3 contact_force, contact_moment, contact_stiffness, contact_rotational_stiffness;
    std::vector<Vec3> part_force, part_moment;
    // A deformable mesh's vertices and their state (empty vertices: a rigid mesh).
    std::vector<Vec3> vertices;
    MeshDeformation deformation;
  };
  std::vector<Mesh> meshes;
  // Each wall's (planes, then meshes) motion of the last step, whose work is completed with the
  // next step's loads.
  std::vector<Vec3> wall_move, wall_turn;

  // The neighbour list (CSR by element) and the springs aligned with it.
  std::vector<int> list_offsets, list_partners;
  std::vector<Vec3> pair_shear, pair_roll;  // pair_roll empty without rolling resistance
  std::vector<double> pair_fn;
  // The candidates of each wall (planes, then meshes) with their springs.
  struct WallContacts {
    std::vector<int> element, triangle_offsets, triangles;
    std::vector<Vec3> shear, roll, normal;
    std::vector<double> fn;
  };
  std::vector<WallContacts> walls;
  // What the next rebuild decision compares with.
  std::vector<Vec3> pos_at_build;
  std::vector<double> radius_at_build;
  double growth_since_build = 0;
  std::vector<Vec3> wall_point_at_build;  // planes' points, then meshes' reference points
  std::vector<Quat> mesh_q_at_build;
};

// Writes the state into an open HDF5 group, and reads it back (InputError naming `file` for a
// missing or inconsistent dataset).
void write_engine_state(hid_t group, const EngineState& s);
EngineState read_engine_state(hid_t group, const std::string& file);

}  // namespace trackbed::dem
