// Materials and the contact properties of every pair of materials.
//
// A material carries per-entity properties (density, stiffnesses, friction, damping). The
// properties of a contact between materials a and b come from one of two rules:
//   - series combination of the entity stiffnesses, as older PFC versions did:
//       k = k_a k_b / (k_a + k_b), friction = min(mu_a, mu_b), rolling friction = min(...)
//   - an explicit per-pair value, which overrides the rule for that pair (e.g. ballast-sleeper).
// See docs/theory.md, "Contact properties".
#pragma once

#include "common/input_error.h"

#include <string>
#include <vector>

namespace trackbed::dem {

struct Material {
  std::string name;
  double density = 2800.0;          // kg/m^3
  double normal_stiffness = 2e7;    // N/m (entity value for series combination)
  double shear_stiffness = 2e7;     // N/m
  double friction = 0.5;            // Coulomb coefficient, -
  double rolling_friction = 0.0;    // mu_r, -
  double normal_damping_ratio = 0;  // fraction of critical, [0, 1]
  double shear_damping_ratio = 0;   // fraction of critical, [0, 1]
  double normal_damping_rate = 0;   // gamma_n in 1/s: F = -gamma_n m_eff v_n (LAMMPS style)
  double local_damping = 0.0;       // alpha, [0, 1)
};

// Everything the contact kernel needs for one pair of materials, precomputed.
struct ContactProperties {
  double kn = 0, ks = 0, mu = 0, mu_roll = 0;
  double normal_damping_ratio = 0, shear_damping_ratio = 0, normal_damping_rate = 0;
  bool has_rolling() const { return mu_roll > 0; }
};

class MaterialTable {
 public:
  // Adds a material and returns its index; names must be unique. Values are validated here so
  // every code path that builds materials gets the same checks.
  int add(const Material& m);
  // Overrides the combined properties of one pair (order-independent).
  void set_pair(int a, int b, const ContactProperties& p);

  int index_of(const std::string& name) const;  // throws InputError listing the known names
  const Material& operator[](int i) const { return materials_[i]; }
  int size() const { return static_cast<int>(materials_.size()); }
  const ContactProperties& pair(int a, int b) const { return pairs_[a * size() + b]; }
  // Throws InputError for a pair whose normal dashpot got both forms (a material with a ratio
  // meeting one with a rate, and no explicit pair value).
  void validate() const;

 private:
  void rebuild_defaults();
  ContactProperties combine(const Material& a, const Material& b) const;

  std::vector<Material> materials_;
  std::vector<ContactProperties> pairs_;  // size()^2, symmetric
  std::vector<bool> explicit_;            // pair set by set_pair
};

}  // namespace trackbed::dem
