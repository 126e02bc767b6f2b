#include "dem/engine/material.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "common/input_error.h"

namespace trackbed::dem {

namespace {

// The checks shared by a material's entity values and an explicit pair's values.
void check_contact_values(const std::string& where, double kn, double ks, double mu, double mu_roll,
                          double ratio_n, double ratio_s, double rate_n) {
  check_range(where + "normal stiffness", kn, 1e-12, 1e15);
  check_range(where + "shear stiffness", ks, 0, 1e15);
  check_range(where + "friction", mu, 0, 100);
  check_range(where + "rolling friction", mu_roll, 0, 100);
  check_range(where + "normal damping ratio", ratio_n, 0, 1);
  check_range(where + "shear damping ratio", ratio_s, 0, 1);
  check_range(where + "normal damping rate", rate_n, 0, 1e9);
  if (ratio_n > 0 && rate_n > 0)
    throw InputError(where +
                     "normal damping ratio and normal damping rate are both set; give one of them");
}

}  // namespace

int MaterialTable::add(const Material& m) {
  const std::string where = "material '" + m.name + "': ";
  if (m.name.empty()) throw InputError("material name is empty; give every material a name");
  for (const auto& other : materials_)
    if (other.name == m.name) throw InputError(where + "defined twice; names must be unique");
  check_range(where + "density", m.density, 1e-12, 1e6);
  check_contact_values(where, m.normal_stiffness, m.shear_stiffness, m.friction, m.rolling_friction,
                       m.normal_damping_ratio, m.shear_damping_ratio, m.normal_damping_rate);
  check_range(where + "local damping", m.local_damping, 0, 0.999);
  materials_.push_back(m);
  rebuild_defaults();
  return size() - 1;
}

ContactProperties MaterialTable::combine(const Material& a, const Material& b) const {
  auto series = [](double x, double y) { return x + y > 0 ? x * y / (x + y) : 0.0; };
  ContactProperties p;
  p.kn = series(a.normal_stiffness, b.normal_stiffness);
  p.ks = series(a.shear_stiffness, b.shear_stiffness);
  p.mu = std::min(a.friction, b.friction);
  p.mu_roll = std::min(a.rolling_friction, b.rolling_friction);
  p.normal_damping_ratio = std::max(a.normal_damping_ratio, b.normal_damping_ratio);
  p.shear_damping_ratio = std::max(a.shear_damping_ratio, b.shear_damping_ratio);
  p.normal_damping_rate = std::max(a.normal_damping_rate, b.normal_damping_rate);
  return p;
}

void MaterialTable::rebuild_defaults() {
  // Explicit pairs survive the growth of the table; the others follow the series rule.
  const int n = size(), old = n - 1;
  std::vector<ContactProperties> pairs(n * n);
  std::vector<bool> expl(n * n, false);
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < n; ++b) {
      if (a < old && b < old && explicit_[a * old + b]) {
        pairs[a * n + b] = pairs_[a * old + b];
        expl[a * n + b] = true;
      } else {
        pairs[a * n + b] = combine(materials_[a], materials_[b]);
      }
    }
  pairs_.swap(pairs);
  explicit_.swap(expl);
}

void MaterialTable::set_pair(int a, int b, const ContactProperties& p) {
  const std::string where = "contact pair " + materials_[a].name + "-" + materials_[b].name + ": ";
  check_contact_values(where, p.kn, p.ks, p.mu, p.mu_roll, p.normal_damping_ratio,
                       p.shear_damping_ratio, p.normal_damping_rate);
  const int n = size();
  pairs_[a * n + b] = pairs_[b * n + a] = p;
  explicit_[a * n + b] = explicit_[b * n + a] = true;
}

int MaterialTable::index_of(const std::string& name) const {
  for (int i = 0; i < size(); ++i)
    if (materials_[i].name == name) return i;
  std::string known;
  for (const auto& m : materials_) known += (known.empty() ? "" : ", ") + m.name;
  throw InputError("unknown material '" + name + "'; defined materials: " + known);
}

void MaterialTable::validate() const {
  for (int a = 0; a < size(); ++a)
    for (int b = a; b < size(); ++b) {
      const ContactProperties& p = pair(a, b);
      if (p.normal_damping_ratio > 0 && p.normal_damping_rate > 0)
        throw InputError("contact " + materials_[a].name + "-" + materials_[b].name +
                         ": one material gives a normal damping ratio, the other a normal "
                         "damping rate; valid: one form, or an explicit value in 'contact pairs'");
    }
}

}  // namespace trackbed::dem
