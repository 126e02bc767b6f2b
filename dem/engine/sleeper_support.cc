#include "dem/engine/sleeper_support.h"

#include <algorithm>
#include <stdexcept>

namespace trackbed::dem {

const SleeperSupport::Part* SleeperSupport::part(const std::string& name) const {
  for (const Part& p : parts)
    if (p.name == name) return &p;
  return nullptr;
}

double SleeperSupport::vertical_load() const {
  double z = 0;
  for (const Part& p : parts) z += p.force.z();
  return z;
}

SleeperSupport sleeper_support(const Simulation& sim, int mesh, const std::string& base_part) {
  if (mesh < 0 || mesh >= static_cast<int>(sim.meshes().size()))
    throw std::out_of_range("sleeper_support: no mesh body " + std::to_string(mesh));
  const TriangleMesh& world = sim.meshes()[mesh].world;
  SleeperSupport s;
  for (const std::string& name : world.part_names) s.parts.push_back({name});
  const auto base_it = std::find(world.part_names.begin(), world.part_names.end(), base_part);
  const int base =
      base_it == world.part_names.end() ? -1 : static_cast<int>(base_it - world.part_names.begin());
  double x_lo = world.vertices.front().x(), x_hi = x_lo;
  for (const Vec3& v : world.vertices) x_lo = std::min(x_lo, v.x()), x_hi = std::max(x_hi, v.x());
  const int wall = static_cast<int>(sim.planes().size()) + mesh;
  sim.for_each_contact([&](const ContactRecord& c) {
    if (c.wall != wall || c.part < 0) return;
    const Vec3 on_body = -c.force;  // the record's force acts on the particle
    SleeperSupport::Part& p = s.parts[c.part];
    ++p.contacts;
    p.force += on_body;
    if (c.part != base) return;
    const int bin =
        std::clamp(static_cast<int>(SleeperSupport::kBins * (c.point.x() - x_lo) / (x_hi - x_lo)),
                   0, SleeperSupport::kBins - 1);
    ++s.base_contacts[bin];
    s.base_load[bin] += on_body.z();
    s.largest_base_contact = std::max(s.largest_base_contact, on_body.z());
  });
  return s;
}

}  // namespace trackbed::dem
