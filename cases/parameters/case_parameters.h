// The contents of a case file (.prm, deal.II ParameterHandler syntax) as plain data. Only
// case_parameters.cc sees deal.II; everything else reads this struct. Parameters, units and
// defaults: docs/user-guide.md, and `trackbed --print-parameters`.
#pragma once

#include <array>
#include <cstdint>
#include <iosfwd>
#include <string>
#include <vector>

#include "cases/runs/push_test.h"
#include "coupling/parameters.h"
#include "dem/engine/material.h"
#include "dem/engine/mesh_body.h"
#include "dem/engine/types.h"

namespace trackbed::cases {

struct PairParameters {
  std::string material_a, material_b;
  dem::ContactProperties properties;
};

struct PlaneParameters {
  std::string name, material;
  dem::Vec3 point, normal, velocity;
};

struct MeshParameters {
  std::string name, material;
  std::string file;             // STL; empty: use `box`
  std::array<double, 6> box{};  // lower x,y,z, upper x,y,z (when no file)
  bool named_box_parts = true;  // box faces named base, top, sides, ends
  bool from_sample = false;  // geometry, pose, mass and inertia of the sample's mesh of this name
  double scale = 1;
  dem::Vec3 translation = dem::Vec3::Zero();
  double density = 0;  // kg/m^3; > 0: mass and inertia from the closed mesh
  double mass = 0;     // kg; > 0 overrides the mass (inertia scaled to match)
  bool weight = false;
  std::array<dem::DofControl, 6> dof{};
};

struct GeneratorParameters {
  int count = 0;
  std::array<double, 6> region{};
  double radius_min = 0.0112, radius_max = 0.0315;
  double clump_fraction = 0;
  std::string clump_template, material;
};

struct CaseParameters {
  std::string file;  // the case file this came from
  // Every parameter that changes what the run computes, as read: one "subsection/name = value"
  // line each (a resumed run checks that its case is the one it started from).
  std::string fingerprint;
  std::string mode = "dem";
  // simulation
  double time_step = 0, critical_fraction = 0.2;
  bool allow_supercritical = false;
  double end_time = 0.5;
  long number_of_steps = 0, warmup_steps = 0;
  int threads = 0;
  double skin = 0.004;
  bool track_energy = true;
  double energy_error_limit = 0.1;  // the run stops as blown up above this balance error
  std::uint64_t seed = 1;
  dem::Vec3 gravity = dem::Vec3(0, 0, -9.81);
  // model
  std::vector<dem::Material> materials;
  std::vector<PairParameters> pairs;
  std::vector<PlaneParameters> planes;
  std::vector<MeshParameters> meshes;
  std::string particle_file;
  std::string sample_file;     // a sample built by `trackbed build-sample` (HDF5)
  bool sample_walls = true;    // add the sample's plane walls
  std::string clump_material;  // material of the sample's clumps; empty: the sample's
  std::vector<std::pair<std::string, std::string>> templates;  // name, CSV file
  GeneratorParameters generator;
  PushTestParameters push;  // push.mesh empty: no push test
  // mode = coupled: the scheme and the FE subgrade under the sample's ballast bed
  coupling::QuasiStaticParameters coupling;
  coupling::SubgradeParameters subgrade;
  // output
  std::string output_folder = "results/default";
  double history_interval = 1e-3, vtu_interval = 0, snapshot_interval = 0, progress_interval = 2;
  double checkpoint_interval = 600;  // wall seconds; 0: none (but on interruption)
  std::vector<long> tracked_bodies;
  bool plot = true;
};

// Reads and validates a case file. A relative path in it resolves against the folder of the file
// that set it (the case file or a file it includes). Throws InputError with one line naming
// the file, line or parameter.
CaseParameters read_case_file(const std::string& path);
// Writes every parameter with its default value and documentation, in .prm syntax, or as JSON
// with each entry's pattern (type and valid range) for tools.
void print_parameters(std::ostream& out, bool json = false);

}  // namespace trackbed::cases
