// Saving and restoring the springs of a Simulation (Simulation::contact_state and
// Simulation::restore_contact_state; the history arrays are in contact_history.h).
#include <algorithm>
#include <unordered_map>

#include "dem/engine/contact_history.h"
#include "dem/engine/simulation.h"

namespace trackbed::dem {

namespace {

ElementKey key_of(const Particles& p, int e) {
  const int b = p.body[e];
  return {p.id[b], e - p.first_element[b]};
}

// Element index of a key in the current particles, or -1 if its body or element is gone.
class ElementFinder {
 public:
  explicit ElementFinder(const Particles& p) : p_(p) {
    for (int b = 0; b < p.num_bodies(); ++b) body_of_id_[p.id[b]] = b;
  }
  int operator()(const ElementKey& k) const {
    const auto it = body_of_id_.find(k.body_id);
    if (it == body_of_id_.end()) return -1;
    const int b = it->second;
    const int e = p_.first_element[b] + k.rank;
    return k.rank >= 0 && e < p_.first_element[b + 1] ? e : -1;
  }

 private:
  const Particles& p_;
  std::unordered_map<std::int64_t, int> body_of_id_;
};

// The smallest positive force marks a restored contact as live until its first step computes it.
constexpr double kLive = 1e-300;

}  // namespace

ContactState Simulation::contact_state() const {
  ContactState state;
  const PairHistory& h = *pair_history_;
  const bool rolling = !h.roll.empty();
  for (int i = 0; i < p_.num_elements(); ++i)
    for (int k = list_.offsets[i]; k < list_.offsets[i + 1]; ++k) {
      if (h.fn[k] <= 0) continue;
      state.pairs.push_back({key_of(p_, i), key_of(p_, list_.partners[k]), h.shear[k],
                             rolling ? h.roll[k] : Vec3::Zero()});
    }
  const int nplanes = static_cast<int>(planes_.size());
  for (std::size_t w = 0; w < plane_history_.size(); ++w) {
    const WallHistory& wh = plane_history_[w];
    const int slots = static_cast<int>(w) < nplanes ? 1 : WallHistory::kSlots;
    for (std::size_t c = 0; c < wh.element.size(); ++c)
      for (int s = 0; s < slots; ++s) {
        const std::size_t k = c * slots + s;
        if (wh.fn[k] <= 0) continue;
        state.walls.push_back({static_cast<int>(w), s, key_of(p_, wh.element[c]), wh.shear[k],
                               wh.roll[k], slots > 1 ? wh.normal[k] : Vec3::Zero()});
      }
  }
  return state;
}

int Simulation::restore_contact_state(const ContactState& state) {
  if (!ready_) setup();
  const ElementFinder find(p_);
  PairHistory& h = *pair_history_;
  const bool rolling = !h.roll.empty();
  int restored = 0;
  for (const SavedPairContact& c : state.pairs) {
    int i = find(c.i), j = find(c.j);
    if (i < 0 || j < 0) continue;
    Vec3 shear = c.shear, roll = c.roll;
    if (i > j) {
      // The list holds (i, j) with i < j; the spring seen from the other side is opposite.
      std::swap(i, j);
      shear = -shear, roll = -roll;
    }
    const int k = list_.find(i, j);
    if (k < 0) continue;
    h.shear[k] = shear;
    if (rolling) h.roll[k] = roll;
    h.fn[k] = kLive;
    ++restored;
  }
  const int nplanes = static_cast<int>(planes_.size());
  for (const SavedWallContact& c : state.walls) {
    if (c.wall < 0 || c.wall >= static_cast<int>(plane_history_.size())) continue;
    WallHistory& wh = plane_history_[c.wall];
    const int slots = c.wall < nplanes ? 1 : WallHistory::kSlots;
    const int e = find(c.element);
    if (e < 0 || c.slot < 0 || c.slot >= slots) continue;
    const auto it = std::lower_bound(wh.element.begin(), wh.element.end(), e);
    if (it == wh.element.end() || *it != e) continue;
    const std::size_t k = (it - wh.element.begin()) * slots + c.slot;
    wh.shear[k] = c.shear;
    wh.roll[k] = c.roll;
    if (slots > 1) wh.normal[k] = c.normal;
    wh.fn[k] = kLive;
    ++restored;
  }
  return restored;
}

}  // namespace trackbed::dem
