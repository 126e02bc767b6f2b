// HDF5 snapshots of the model state (format: docs/formats.md). A snapshot holds bodies, elements,
// walls and the clock; it is written under a temporary name and renamed.
#pragma once

#include <string>

namespace trackbed::dem {

class Simulation;

void write_snapshot(const std::string& path, const Simulation& sim);
// Restores body, plane and mesh states and the clock into a simulation built from the same
// input (same bodies in the same order); throws InputError if the file does not match.
void read_snapshot(const std::string& path, Simulation& sim);

}  // namespace trackbed::dem
