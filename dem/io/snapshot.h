// HDF5 snapshots of the model state (format: docs/formats.md). A snapshot holds bodies, elements,
// walls and the clock; it is written under a temporary name and renamed.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "dem/engine/types.h"

namespace trackbed::dem {

class Simulation;

void write_snapshot(const std::string& path, const Simulation& sim);
// Restores body, plane and mesh states and the clock into a simulation built from the same
// input (same bodies in the same order); throws InputError if the file does not match.
void read_snapshot(const std::string& path, Simulation& sim);

// The clock of a snapshot: cheap to read, to put a run's snapshots in step order.
struct SnapshotClock {
  double time = 0;  // s
  long step = 0;
};
SnapshotClock read_snapshot_clock(const std::string& path);

// What tools outside a run (a pilot zone, a report) need of a snapshot, read without a Simulation.
// Bodies are in the file's order; `id` maps them to particle-file rows.
struct SnapshotBodies {
  double time = 0;  // s
  long step = 0;
  std::vector<std::int64_t> id;
  std::vector<Vec3> position;  // centre of mass, m
  // Per body: max over its elements of |element centre - body centre| + element radius, m (the
  // radius of the smallest sphere about the centre of mass holding the body).
  std::vector<double> bounding_radius;
  std::vector<Vec3> mesh_position;  // reference point of each mesh body, in mesh order, m
};
// Both readers throw InputError for a missing file, a file that is not HDF5, and one that is not
// a trackbed snapshot (a missing group or dataset, inconsistent sizes, an element of no body).
SnapshotBodies read_snapshot_bodies(const std::string& path);

}  // namespace trackbed::dem
