#include "cases/runs/push_test.h"

#include <algorithm>
#include <cmath>
#include <iomanip>

#include "common/input_error.h"
#include "dem/engine/sleeper_support.h"
#include "dem/io/atomic_file.h"

namespace trackbed::cases {

namespace {
const char* const kAxes = "xyz";
}

PushTest::PushTest(PushTestParameters prm, dem::Simulation& sim, const std::string& case_file)
    : prm_(std::move(prm)) {
  const auto& meshes = sim.meshes();
  mesh_ = sim.mesh_index(prm_.mesh);
  const std::string where = case_file + ": push test/mesh = " + prm_.mesh;
  if (mesh_ < 0)
    throw InputError(where + ": no mesh of this name in 'meshes'" +
                     (meshes.empty() ? "" : "; valid: " + meshes.front().name));
  const dem::MeshBody& body = meshes[mesh_];
  const dem::DofControl& dof = body.dof[prm_.axis];
  if (dof.mode != dem::DofMode::velocity || dof.value == 0)
    throw InputError(where + ": its 'dof " + std::string(1, kAxes[prm_.axis]) +
                     "' must be 'velocity V' with V != 0 (the push velocity, m/s)");
  velocity_ = dof.value;
  weight_ = body.mass * sim.settings().gravity.norm();
  parts_ = body.local.part_names;
  start_ = body.x[prm_.axis];  // held: the push DOF does not move during the hold
  if (prm_.free_during_hold && body.mass <= 0)
    throw InputError(where +
                     ": push test/hold along the push = free needs the mesh's mass; "
                     "valid: 'fixed', or a mesh with a mass (a sample's sleeper, a density)");
  if (prm_.path.empty()) prm_.path = {prm_.distance};
}

double PushTest::path_length() const {
  double length = 0, at = 0;
  for (const double d : prm_.path) length += std::abs(d - at), at = d;
  return length;
}

double PushTest::expected_end(const dem::Simulation& sim) const {
  const double start = pushing() ? push_start_ : std::max(sim.time(), prm_.min_hold);
  return start + path_length() / std::abs(velocity_);
}

bool PushTest::finished() const {
  return leg_ >= prm_.path.size();
}

void PushTest::control(dem::Simulation& sim, bool foundation_settled) {
  constexpr long kCheckEvery = 200;
  constexpr int kConfirmations = 3;
  if (!pushing() && sim.time() >= prm_.min_hold && sim.step_count() % kCheckEvery == 0) {
    hold_ratio_ = sim.unbalanced_force_ratio();
    const bool at_rest = hold_ratio_ < prm_.equilibrium_ratio && foundation_settled;
    confirmations_ = at_rest ? confirmations_ + 1 : 0;
    hold_converged_ = confirmations_ >= kConfirmations;
    if (hold_converged_ || sim.time() >= prm_.max_hold) {
      push_start_ = sim.time();
      start_ = sim.meshes()[mesh_].x[prm_.axis];  // where a free body came to rest
      start_support_ = support_now(sim);
      record(sim);  // the first row of push.csv, at zero displacement
    }
  }
  double v = 0;
  if (pushing()) {
    // Toward the current point at the push speed; the last step of a leg is shortened to land on
    // the point, so that each leg moves exactly its length.
    const double speed = std::abs(velocity_), dt = sim.time_step();
    const double tolerance = 1e-6 * speed * dt;  // far above rounding of the position
    while (leg_ < prm_.path.size() && std::abs(prm_.path[leg_] - displacement(sim)) <= tolerance)
      ++leg_;
    if (leg_ < prm_.path.size()) {
      const double remaining = prm_.path[leg_] - displacement(sim);
      v = std::copysign(std::min(speed, std::abs(remaining) / dt), remaining * velocity_);
    }
  }
  dem::DofControl& dof = sim.meshes()[mesh_].dof[prm_.axis];
  dof.mode = prm_.free_during_hold && !pushing() ? dem::DofMode::free : dem::DofMode::velocity;
  dof.value = v;
}

double PushTest::displacement(const dem::Simulation& sim) const {
  return std::copysign(1.0, velocity_) * (sim.meshes()[mesh_].x[prm_.axis] - start_);
}

std::vector<double> PushTest::support_now(const dem::Simulation& sim) const {
  const dem::SleeperSupport support = dem::sleeper_support(sim, mesh_);
  // Shares of an upward load only: a body the bed does not carry (a plate pushing balls) has none.
  const double load = support.vertical_load();
  const double per_load = load > 0 ? 1 / load : NAN;
  std::vector<double> v;
  for (const auto& part : support.parts)
    v.insert(v.end(), {double(part.contacts), part.force.z() * per_load});
  v.push_back(support.part("base") ? support.largest_base_contact * per_load : NAN);
  return v;
}

void PushTest::record(const dem::Simulation& sim) {
  if (!pushing()) return;
  const dem::MeshBody& body = sim.meshes()[mesh_];
  const double e = std::copysign(1.0, velocity_);
  Row r;
  r.time = sim.time();
  r.displacement = displacement(sim);
  r.resistance = -e * body.contact_force[prm_.axis];
  r.vertical_load = body.contact_force.z();
  for (const auto& f : body.part_force) r.part_resistance.push_back(-e * f[prm_.axis]);
  r.max_particle_force = sim.max_particle_contact_force();
  const int wall = static_cast<int>(sim.planes().size()) + mesh_;
  double m = 0;
  sim.for_each_contact([&](const dem::ContactRecord& c) {
    if (c.wall == wall) m = std::max(m, c.force.norm());
  });
  r.max_body_force = m;
  // The particles are (nearly) at rest, so what the pushed body puts into the bed along e
  // leaves it through the other walls: the sum of all wall loads along e is ~0 on average.
  r.unbalance = 0;
  for (const auto& p : sim.planes()) r.unbalance += e * p.force[prm_.axis];
  for (const auto& b : sim.meshes()) r.unbalance += e * b.contact_force[prm_.axis];
  rows_.push_back(std::move(r));
}

void PushTest::write_csv(const std::string& path) const {
  dem::AtomicFile f(path);
  auto& s = f.stream();
  s << "time_s,displacement_m,resistance_n,vertical_load_n";
  for (const auto& p : parts_) s << ",resistance_" << p << "_n";
  s << ",max_particle_contact_force_n,max_body_contact_force_n,wall_load_sum_n\n";
  s << std::setprecision(10);
  for (const auto& r : rows_) {
    s << r.time << "," << r.displacement << "," << r.resistance << "," << r.vertical_load;
    for (double v : r.part_resistance) s << "," << v;
    s << "," << r.max_particle_force << "," << r.max_body_force << "," << r.unbalance << "\n";
  }
  f.commit();
}

PushTest::Progress PushTest::progress() const {
  Progress p{start_,         push_start_,     hold_ratio_, static_cast<long>(leg_),
             confirmations_, hold_converged_, {},          start_support_};
  for (const Row& r : rows_) {
    std::vector<double> v = {r.time, r.displacement, r.resistance, r.vertical_load};
    v.insert(v.end(), r.part_resistance.begin(), r.part_resistance.end());
    v.insert(v.end(), {r.max_particle_force, r.max_body_force, r.unbalance});
    p.rows.push_back(std::move(v));
  }
  return p;
}

void PushTest::resume(const Progress& p) {
  const std::size_t columns = 7 + parts_.size();
  for (const auto& v : p.rows)
    if (v.size() != columns)
      throw InputError("push test: a saved row has " + std::to_string(v.size()) +
                       " numbers; valid: " + std::to_string(columns) + " for the mesh '" +
                       prm_.mesh + "' and its parts");
  if (!p.start_support.empty() && p.start_support.size() != 2 * parts_.size() + 1)
    throw InputError("push test: the saved support at the push start has " +
                     std::to_string(p.start_support.size()) +
                     " numbers; valid: " + std::to_string(2 * parts_.size() + 1) +
                     " for the mesh '" + prm_.mesh + "' and its parts");
  if (p.leg < 0 || p.leg > static_cast<long>(prm_.path.size()))
    throw InputError("push test: the saved leg " + std::to_string(p.leg) +
                     " is not one of the path's " + std::to_string(prm_.path.size()));
  start_ = p.start, push_start_ = p.push_start, hold_ratio_ = p.hold_ratio;
  leg_ = static_cast<std::size_t>(p.leg), confirmations_ = p.confirmations;
  hold_converged_ = p.hold_converged;
  start_support_ = p.start_support;
  rows_.clear();
  for (const auto& v : p.rows) {
    const std::size_t n = parts_.size();
    rows_.push_back({v[0], v[1], v[2], v[3], std::vector<double>(v.begin() + 4, v.begin() + 4 + n),
                     v[4 + n], v[5 + n], v[6 + n]});
  }
}

double PushTest::interpolated_at(const std::vector<double>& curve, double d) const {
  for (std::size_t k = 1; k < rows_.size(); ++k) {
    const Row &a = rows_[k - 1], &b = rows_[k];
    if (b.displacement >= d && a.displacement <= d) {
      const double span = b.displacement - a.displacement;
      const double w = span > 0 ? (d - a.displacement) / span : 1.0;
      return curve[k - 1] + w * (curve[k] - curve[k - 1]);
    }
  }
  return NAN;
}

std::pair<std::size_t, std::size_t> PushTest::window(std::size_t k) const {
  const double d = rows_[k].displacement, h = 0.5 * prm_.smoothing;
  std::size_t first = k, last = k + 1;
  while (first > 0 && std::abs(rows_[first - 1].displacement - d) <= h) --first;
  while (last < rows_.size() && std::abs(rows_[last].displacement - d) <= h) ++last;
  return {first, last};
}

template <class Value>
std::vector<double> PushTest::smoothed(Value value) const {
  // Running mean over a window of `smoothing` in displacement, centred, shortened at the ends.
  std::vector<double> out(rows_.size());
  for (std::size_t k = 0; k < rows_.size(); ++k) {
    const auto [first, last] = window(k);
    double sum = 0;
    for (std::size_t j = first; j < last; ++j) sum += value(rows_[j]);
    out[k] = sum / double(last - first);
  }
  return out;
}

std::vector<SummaryItem> PushTest::summary() const {
  std::vector<SummaryItem> items;
  if (rows_.empty()) return items;
  const std::vector<double> smooth = smoothed([](const Row& r) { return r.resistance; });
  // What of the resistance reaches the walls (the base's friction, for a sleeper): the rest is
  // taken by local damping and the inertia of the stones that move (docs/validation.md, "What
  // makes the clump bed's resistance depend on the velocity").
  const std::vector<double> to_walls =
      smoothed([](const Row& r) { return r.resistance + r.unbalance; });
  const std::size_t peak = std::max_element(smooth.begin(), smooth.end()) - smooth.begin();
  const auto raw = std::max_element(rows_.begin(), rows_.end(), [](const Row& a, const Row& b) {
    return a.resistance < b.resistance;
  });
  const Row& last = rows_.back();
  double max_particle = 0, max_body = 0, load = 0, resistance = 0, unbalance = 0;
  for (const auto& r : rows_) {
    max_particle = std::max(max_particle, r.max_particle_force);
    max_body = std::max(max_body, r.max_body_force);
    load += r.vertical_load / rows_.size();
    resistance += r.resistance;
    unbalance += r.unbalance;
  }
  const std::string mm = std::to_string(std::lround(prm_.report_at * 1e3));
  // A push along x or y meets the bed's lateral resistance; one along z (the ballast box) its
  // vertical resistance.
  // vertical: the weight and the bed's own weight enter the load and the balance, which are then
  // not reported.
  const bool vertical = prm_.axis == 2;
  const std::string kind = vertical ? "vertical" : "lateral";
  bool reverses = false;  // a path that comes back (the ballast box)
  for (std::size_t k = 1; k < prm_.path.size(); ++k) reverses |= prm_.path[k] < prm_.path[k - 1];
  items = {
      {"hold_time_s", "hold before the push", "s", push_start_},
      {"hold_converged", "hold reached equilibrium (1 yes, 0 no)", "", hold_converged_ ? 1. : 0.},
      {"hold_unbalanced_ratio", "unbalanced force ratio at the push start", "", hold_ratio_},
      {"push_velocity_m_s", "push velocity", "m/s", std::abs(velocity_)},
      {"push_distance_m", "push displacement at the end", "m", last.displacement},
      {"push_path_m", "push path length", "m", path_length()},
      {"peak_" + kind + "_force_n", "peak " + kind + " force (window mean)", "N", smooth[peak]},
      {"displacement_at_peak_m", "displacement at the peak", "m", rows_[peak].displacement},
      {"peak_" + kind + "_force_raw_n", "peak " + kind + " force (single row)", "N",
       raw->resistance},
      {kind + "_force_at_" + mm + "mm_n", kind + " force at " + mm + " mm (window mean)", "N",
       interpolated_at(smooth, prm_.report_at)},
      {"final_" + kind + "_force_n", kind + " force at the end (window mean)", "N", smooth.back()},
      {"peak_reverse_" + kind + "_force_n",
       "peak " + kind + " force against the reverse legs (window mean)", "N",
       reverses ? -*std::min_element(smooth.begin(), smooth.end()) : NAN},
      {"max_particle_contact_force_end_n", "max particle-particle contact force at the end", "N",
       last.max_particle_force},
      {"max_particle_contact_force_push_n", "max particle-particle contact force in the push", "N",
       max_particle},
      {"max_sleeper_contact_force_end_n", "max particle-" + prm_.mesh + " contact force at the end",
       "N", last.max_body_force},
      {"max_sleeper_contact_force_push_n",
       "max particle-" + prm_.mesh + " contact force in the push", "N", max_body},
      {"mean_vertical_load_over_weight", "mean vertical contact load / weight", "",
       weight_ > 0 && !vertical ? load / weight_ : NAN},
      {"horizontal_balance_error", "horizontal force balance error (push mean)", "",
       resistance != 0 && !vertical ? std::abs(unbalance) / resistance : NAN},
      {"walls_" + kind + "_force_at_peak_n", kind + " force reaching the walls at the peak", "N",
       vertical ? NAN : to_walls[peak]},
      {"walls_" + kind + "_force_at_" + mm + "mm_n",
       kind + " force reaching the walls at " + mm + " mm", "N",
       vertical ? NAN : interpolated_at(to_walls, prm_.report_at)},
  };
  const std::vector<SummaryItem> parts = part_items(peak);
  items.insert(items.end(), parts.begin(), parts.end());
  return items;
}

std::vector<SummaryItem> PushTest::part_items(std::size_t peak) const {
  // Shares at the peak, from the parts' forces averaged over the window of the peak's value.
  std::vector<double> part(parts_.size(), 0.0);
  double total = 0;
  const auto [first, last] = window(peak);
  for (std::size_t j = first; j < last; ++j) {
    total += rows_[j].resistance;
    for (std::size_t k = 0; k < part.size(); ++k) part[k] += rows_[j].part_resistance[k];
  }
  std::vector<SummaryItem> items;
  for (std::size_t k = 0; k < parts_.size(); ++k)
    items.push_back({"share_" + parts_[k], "share of " + parts_[k] + " at the peak", "",
                     total != 0 ? part[k] / total : NAN});
  for (std::size_t k = 0; k < parts_.size() && !start_support_.empty(); ++k) {
    items.push_back({"start_" + parts_[k] + "_contacts", "push start: " + parts_[k] + " contacts",
                     "", start_support_[2 * k]});
    items.push_back({"start_" + parts_[k] + "_load_share",
                     "push start: " + parts_[k] + " share of vertical load", "",
                     start_support_[2 * k + 1]});
  }
  if (!start_support_.empty())
    items.push_back({"start_largest_base_contact_share", "push start: largest base contact share",
                     "", start_support_.back()});
  return items;
}

}  // namespace trackbed::cases
