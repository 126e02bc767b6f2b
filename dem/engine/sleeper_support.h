// Where a sleeper (or any mesh body) gets its support: per named part of its mesh (a sleeper's
// base, top, sides, ends) the contacts the particles make with it and the load they put on it,
// and how the load on the base is spread along its length. Read from the contact forces of the
// last step, so the loads of the parts sum to the body's contact force (MeshBody::contact_force)
// up to the contact dashpots, which vanish at rest.
//
// A rigid sleeper seated on stiff stones rests on the few that stand highest under it
// (docs/samples.md, "The sleeper seated"): the number of base contacts, the largest contact's
// share and the load by fifths of the length tell a user whether a sample's sleeper is carried
// along its length or balanced on a handful of stones.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "dem/engine/simulation.h"

namespace trackbed::dem {

struct SleeperSupport {
  struct Part {
    std::string name;
    int contacts = 0;
    Vec3 force = Vec3::Zero();  // on the body, N
  };
  static constexpr int kBins = 5;
  std::vector<Part> parts;  // the mesh's parts, in its order
  // The base's contacts by fifths of the body's extent along x (the sleeper's length in a
  // section, track_section.h): their number, and the upward load they carry, N.
  std::array<int, kBins> base_contacts{};
  std::array<double, kBins> base_load{};
  double largest_base_contact = 0;  // the largest upward load of one base contact, N

  // The part of that name, or nullptr.
  const Part* part(const std::string& name) const;
  // The upward load of all parts, N.
  double vertical_load() const;
};

// The support of mesh body `mesh` of a stepped model; the base is the part named `base_part`
// (no base part: the bins stay empty).
SleeperSupport sleeper_support(const Simulation& sim, int mesh,
                               const std::string& base_part = "base");

}  // namespace trackbed::dem
