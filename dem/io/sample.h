// A ballast sample: the bodies of a built track bed with their shapes and sizes, the walls and
// meshes it rests against, and the springs of its contacts. Built once
// (dem/samples/sample_builder.h), saved as HDF5 and reloaded by any case, so the costly deposition
// is done once. Format: docs/formats.md, "Sample files".
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "dem/engine/contact_state.h"
#include "dem/engine/mesh_body.h"
#include "dem/engine/particles.h"
#include "dem/engine/plane_wall.h"

namespace trackbed::dem {

struct Sample {
  // Bodies and elements; material indices refer to `materials`.
  Particles particles;
  std::vector<std::string> materials;
  // Per body: the index of its shape in `shapes` (-1: a ball) and its sieve size (m), the
  // smallest square aperture it passes (a ball: its diameter).
  std::vector<int> shape;
  std::vector<double> sieve_size;
  std::vector<std::string> shapes;
  // Walls and meshes (geometry and pose; a case gives their degrees of freedom). Wall contacts in
  // `contacts` number planes first, then meshes, in these orders.
  std::vector<PlaneWall> planes;
  std::vector<MeshBody> meshes;
  ContactState contacts;
  // How the sample was built, as "key = value" lines (section, grading, zone, counts, ...).
  std::vector<std::pair<std::string, std::string>> info;

  int num_balls() const { return particles.num_bodies() - particles.num_clumps(); }
  // The info value for key, or "" if absent.
  std::string info_value(const std::string& key) const;
};

// Written under a temporary name and renamed. Throws std::runtime_error if writing fails.
void write_sample(const std::string& path, const Sample& sample);
// Throws InputError naming the file for a missing, foreign or inconsistent file.
Sample read_sample(const std::string& path);

}  // namespace trackbed::dem
