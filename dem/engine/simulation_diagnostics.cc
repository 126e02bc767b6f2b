// Simulation: the critical time step, the energy ledger, the contact list for outputs and the
// checks of a run's state (docs/theory.md, sections 8-10).
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "common/input_error.h"
#include "dem/engine/contact_history.h"
#include "dem/engine/simulation.h"
#include "dem/engine/simulation_internals.h"

namespace trackbed::dem {

// ---------------------------------------------------------------------------------------------
// Diagnostics

double Simulation::critical_timestep() const {
  const std::vector<double> steps = body_critical_steps();
  double dt = std::numeric_limits<double>::infinity();
  for (int b = 0; b < static_cast<int>(steps.size()); ++b)
    dt = std::min(dt, steps[b] * std::sqrt(inertia_scale(b)));
  return dt;
}

double Simulation::scale_density_for_step(double dt, double fraction, bool within_skin) {
  // sqrt(s m / k) = sqrt(s) t_b: the body's step is fraction sqrt(s) t_b >= dt.
  const std::vector<double> steps = body_critical_steps(within_skin);
  inertia_scale_.assign(steps.size(), 1.0);
  double largest = 1;
  for (std::size_t b = 0; b < steps.size(); ++b) {
    inertia_scale_[b] = std::max(1.0, std::pow(dt / (fraction * steps[b]), 2));
    largest = std::max(largest, inertia_scale_[b]);
  }
  set_time_step(dt);
  return largest;
}

namespace {

// Half the stability limit of one degree of freedom of mass m on a spring k with a dashpot c,
// its velocity lagging half a step as the leapfrog update has it: the limit is
// 2 (sqrt(1 + zeta^2) - zeta) sqrt(m / k), zeta = c / (2 sqrt(m k)) (docs/theory.md, "Critical
// timestep"); undamped, sqrt(m / k).
double damped_half_limit(double m, double k, double c) {
  if (!(k > 0)) return std::numeric_limits<double>::infinity();
  const double zeta = c / (2 * std::sqrt(m * k));
  return (std::sqrt(1 + zeta * zeta) - zeta) * std::sqrt(m / k);
}

// Per body and degree of freedom (translation along and rotation about each world axis), the
// springs and the dashpots of its contacts summed.
struct DofSums {
  explicit DofSums(int bodies) : kt(bodies, Vec3::Zero()), kr(kt), ct(kt), cr(kt) {}
  // One contact of body b with normal n, lever from the body's centre to the contact point and
  // rolling radius r: K = k_n n n^T + k_s (I - n n^T) along e_a gives e_a^T K e_a, about e_a
  // u^T K u with u = e_a x lever (the contact point's displacement per unit rotation), plus the
  // rolling stiffness k_s r^2; the dashpots, C = c_n n n^T + c_s (I - n n^T), alike (rolling
  // has none).
  void add(int b, const ContactProperties& pr, double m_eff, const Vec3& n, const Vec3& lever,
           double r) {
    const double cn = normal_dashpot(pr, m_eff), cs = shear_dashpot(pr, m_eff);
    for (int a = 0; a < 3; ++a) {
      kt[b][a] += pr.kn * n[a] * n[a] + pr.ks * (1 - n[a] * n[a]);
      ct[b][a] += cn * n[a] * n[a] + cs * (1 - n[a] * n[a]);
      const Vec3 u = Vec3::Unit(a).cross(lever);
      const double un = u.dot(n);
      kr[b][a] += pr.kn * un * un + pr.ks * (u.squaredNorm() - un * un) +
                  (pr.has_rolling() ? pr.ks * r * r : 0.0);
      cr[b][a] += cn * un * un + cs * (u.squaredNorm() - un * un);
    }
  }
  // A body touching nothing yet: one contact with its own material, its first touch, at `lever`
  // from its centre (with the dashpots of a touch on a wall, m_eff = m: the largest).
  void add_first_touch(int b, const ContactProperties& pr, double mass, double lever) {
    const double cn = normal_dashpot(pr, mass), cs = shear_dashpot(pr, mass);
    kt[b].array() += std::max(pr.kn, pr.ks);
    ct[b].array() += pr.kn >= pr.ks ? cn : cs;
    kr[b].array() += pr.ks * (lever * lever);
    cr[b].array() += cs * (lever * lever);
  }
  // The smallest damped half limit over the body's degrees of freedom; rotations with its
  // smallest principal moment.
  double step(int b, double mass, double inertia) const {
    double step = std::numeric_limits<double>::infinity();
    for (int a = 0; a < 3; ++a) {
      step = std::min(step, damped_half_limit(mass, kt[b][a], ct[b][a]));
      step = std::min(step, damped_half_limit(inertia, kr[b][a], cr[b][a]));
    }
    return step;
  }
  std::vector<Vec3> kt, kr, ct, cr;
};

}  // namespace

std::vector<double> Simulation::body_critical_steps(bool within_skin) const {
  // PFC takes sqrt(m / k) and sqrt(I / k_rot) with the springs of a body's contacts summed, the
  // smallest over bodies and DOFs; the dashpots shorten each by sqrt(1 + zeta^2) - zeta.
  const int nb = p_.num_bodies();
  DofSums sums(nb);
  // Whether a body touches anything now: one that does not gets the free-body contact below, in
  // both ways of counting, so that the within-skin count never has fewer springs than the count
  // a step is checked with (its neighbours' levers may be shorter than the free-body rule's).
  std::vector<char> touches(nb, 0);
  for (int i = 0; i < p_.num_elements(); ++i)
    for (int k = list_.offsets[i]; k < list_.offsets[i + 1]; ++k) {
      const int j = list_.partners[k];
      const Vec3 d = p_.pos[j] - p_.pos[i];
      const bool touching = d.norm() < p_.radius[i] + p_.radius[j];
      if (!touching && !within_skin) continue;
      const int bi = p_.body[i], bj = p_.body[j];
      if (touching) touches[bi] = touches[bj] = 1;
      const Vec3 n = d.normalized();
      const ContactProperties& pr = materials_.pair(p_.material[i], p_.material[j]);
      const double reff = p_.radius[i] * p_.radius[j] / (p_.radius[i] + p_.radius[j]);
      const double m_eff = p_.mass[bi] * p_.mass[bj] / (p_.mass[bi] + p_.mass[bj]);
      sums.add(bi, pr, m_eff, n, p_.pos[i] + n * p_.radius[i] - p_.x[bi], reff);
      sums.add(bj, pr, m_eff, n, p_.pos[j] - n * p_.radius[j] - p_.x[bj], reff);
    }
  for (std::size_t w = 0; w < planes_.size(); ++w)
    for (int e : plane_history_[w].element) {
      if (planes_[w].distance(p_.pos[e]) >= p_.radius[e]) continue;
      const ContactProperties& pr = materials_.pair(planes_[w].material, p_.material[e]);
      const int b = p_.body[e];
      touches[b] = 1;
      sums.add(b, pr, p_.mass[b], planes_[w].normal,
               p_.pos[e] - planes_[w].normal * p_.radius[e] - p_.x[b], p_.radius[e]);
    }
  visit_mesh_contacts([&](int m, int, int e, const MeshContactPoint& pt, int) {
    const int b = p_.body[e];
    touches[b] = 1;
    sums.add(b, materials_.pair(meshes_[m].material, p_.material[e]), p_.mass[b], pt.normal,
             pt.point - p_.x[b], p_.radius[e]);
  });
  std::vector<double> steps(nb);
  for (int b = 0; b < nb; ++b) {
    if (!touches[b]) {
      const int e = p_.first_element[b];
      sums.add_first_touch(b, materials_.pair(p_.material[e], p_.material[e]), p_.mass[b],
                           (p_.pos[e] - p_.x[b]).norm() + p_.radius[e]);
    }
    steps[b] = sums.step(b, p_.mass[b], p_.inertia[b].minCoeff());
  }
  return steps;
}

double Simulation::closing_wall_work() const {
  double work = 0;
  for (std::size_t k = 0; k < last_wall_motion_.size(); ++k) {
    const auto& [move, turn] = last_wall_motion_[k];
    if (k < planes_.size())
      work -= 0.5 * planes_[k].force.dot(move);
    else {
      const MeshBody& m = meshes_[k - planes_.size()];
      work -= 0.5 * (m.contact_force.dot(move) + m.contact_moment.dot(turn));
      for (std::size_t v = 0; m.deformable && v < m.deformation.load.size(); ++v)
        work -= 0.5 * m.deformation.load[v].dot(m.deformation.pending_move[v]);
    }
  }
  return work;
}

EnergyBudget Simulation::energy() const {
  EnergyBudget e = tally_;
  // The last step's motion, its second half with the forces at its start standing in for those
  // at its end (not computed before the next step).
  e.wall_work += closing_wall_work();
  e.kinetic = p_.kinetic_energy();
  double strain = 0;
  const PairHistory& h = *pair_history_;
  const bool rolling = !h.roll.empty();
  for (int i = 0; i < p_.num_elements(); ++i)
    for (int k = list_.offsets[i]; k < list_.offsets[i + 1]; ++k) {
      const int j = list_.partners[k];
      const double overlap = p_.radius[i] + p_.radius[j] - (p_.pos[j] - p_.pos[i]).norm();
      if (overlap <= 0) continue;
      const double reff = p_.radius[i] * p_.radius[j] / (p_.radius[i] + p_.radius[j]);
      strain += contact_strain_energy(materials_.pair(p_.material[i], p_.material[j]), overlap,
                                      h.shear[k], rolling ? h.roll[k] : Vec3::Zero(), reff);
    }
  for (std::size_t w = 0; w < planes_.size(); ++w) {
    const WallHistory& wh = plane_history_[w];
    for (std::size_t c = 0; c < wh.element.size(); ++c) {
      const int el = wh.element[c];
      const double overlap = p_.radius[el] - planes_[w].distance(p_.pos[el]);
      if (overlap <= 0) continue;
      strain += contact_strain_energy(materials_.pair(planes_[w].material, p_.material[el]),
                                      overlap, wh.shear[c], wh.roll[c], p_.radius[el]);
    }
  }
  constexpr int S = WallHistory::kSlots;
  visit_mesh_contacts([&](int m, int c, int el, const MeshContactPoint& pt, int slot) {
    const WallHistory& wh = plane_history_[planes_.size() + m];
    strain +=
        contact_strain_energy(materials_.pair(meshes_[m].material, p_.material[el]), pt.overlap,
                              wh.shear[c * S + slot], wh.roll[c * S + slot], p_.radius[el]);
  });
  e.strain = strain;
  return e;
}

void Simulation::for_each_contact(const std::function<void(const ContactRecord&)>& f) const {
  const PairHistory& h = *pair_history_;
  for (int i = 0; i < p_.num_elements(); ++i)
    for (int k = list_.offsets[i]; k < list_.offsets[i + 1]; ++k) {
      if (h.fn[k] <= 0) continue;
      const int j = list_.partners[k];
      const Vec3 d = p_.pos[j] - p_.pos[i];
      const Vec3 n = d.normalized();
      const double overlap = p_.radius[i] + p_.radius[j] - d.norm();
      ContactRecord r{i, j, -1, p_.pos[i] + n * (p_.radius[i] - 0.5 * overlap),
                      h.fn[k] * n + h.shear[k]};
      f(r);
    }
  for (std::size_t w = 0; w < planes_.size(); ++w) {
    const WallHistory& wh = plane_history_[w];
    for (std::size_t c = 0; c < wh.element.size(); ++c) {
      if (wh.fn[c] <= 0) continue;
      const int e = wh.element[c];
      const Vec3 pt = p_.pos[e] - planes_[w].distance(p_.pos[e]) * planes_[w].normal;
      f(ContactRecord{-1, e, static_cast<int>(w), pt, wh.fn[c] * planes_[w].normal + wh.shear[c]});
    }
  }
  constexpr int S = WallHistory::kSlots;
  std::vector<MeshContactPoint> now;
  for (std::size_t m = 0; m < meshes_.size(); ++m) {
    const WallHistory& wh = plane_history_[planes_.size() + m];
    const TriangleMesh& mesh = meshes_[m].world;
    for (std::size_t c = 0; c < wh.element.size(); ++c) {
      const int e = wh.element[c];
      mesh_points_now(m, c, now);
      for (int a = 0; a < S; ++a) {
        const int k = static_cast<int>(c) * S + a;
        if (wh.fn[k] <= 0) continue;
        ContactRecord r{-1, e, static_cast<int>(planes_.size() + m),
                        p_.pos[e] - wh.normal[k] * p_.radius[e],
                        wh.fn[k] * wh.normal[k] + wh.shear[k]};
        // The part of the triangle touched now whose normal is the stored one's (the positions
        // moved by one step since the forces; the same matching as mesh_forces' springs).
        double best_dot = 0.5;
        for (const MeshContactPoint& pt : now)
          if (const double dot = pt.normal.dot(wh.normal[k]); dot > best_dot)
            best_dot = dot, r.part = mesh.triangle_part[pt.triangle];
        f(r);
      }
    }
  }
}

int Simulation::num_contacts() const {
  int n = 0;
  for (double fn : pair_history_->fn) n += fn > 0;
  for (const auto& wh : plane_history_)
    for (double fn : wh.fn) n += fn > 0;
  return n;
}

double Simulation::max_particle_contact_force() const {
  double m = 0;
  const PairHistory& h = *pair_history_;
  for (std::size_t k = 0; k < h.fn.size(); ++k)
    if (h.fn[k] > 0) m = std::max(m, std::hypot(h.fn[k], h.shear[k].norm()));
  return m;
}

double Simulation::max_wall_contact_force() const {
  double m = 0;
  for (const auto& wh : plane_history_)
    for (std::size_t k = 0; k < wh.fn.size(); ++k)
      if (wh.fn[k] > 0) m = std::max(m, std::hypot(wh.fn[k], wh.shear[k].norm()));
  return m;
}

double Simulation::unbalanced_force_ratio() const {
  const int nb = p_.num_bodies();
  std::vector<double> applied(nb, 0.0);
  for_each_contact([&](const ContactRecord& c) {
    const double f = c.force.norm();
    applied[p_.body[c.element_j]] += f;
    if (c.element_i >= 0) applied[p_.body[c.element_i]] += f;
  });
  double unbalanced = 0, total = 0;
  for (int b = 0; b < nb; ++b) {
    const Vec3 weight = p_.mass[b] * settings_.gravity;
    unbalanced += (p_.f[b] + weight).norm();
    total += applied[b] + weight.norm();
  }
  return total > 0 ? unbalanced / total : 0.0;
}

double EnergyBudget::balance_error(const EnergyBudget& initial) const {
  const double scale = std::max({std::abs(kinetic) + strain, dissipated(), std::abs(gravity_work),
                                 std::abs(wall_work), initial.kinetic + initial.strain, 1e-300});
  return (total() - initial.total()) / scale;
}

void Simulation::check_energy(const EnergyBudget& initial, const EnergyBudget& now) const {
  const double error = now.balance_error(initial);
  const double limit = settings_.max_energy_error;
  if (error <= limit) return;
  int worst = 0;
  double largest = -1;
  for (int b = 0; b < p_.num_bodies(); ++b) {
    const double e = p_.mass[b] * p_.v[b].squaredNorm();
    if (e > largest) largest = e, worst = b;
  }
  std::ostringstream s;
  s << "the model blew up at t = " << time_ << " s (step " << steps_
    << "): energy from nowhere, its energy balance off by " << error
    << " of its largest term (limit " << limit << "), particle " << p_.id[worst]
    << " the fastest at " << p_.v[worst].norm() << " m/s: reduce the time step (critical "
    << critical_timestep() << " s)";
  throw std::runtime_error(s.str());
}

void Simulation::check_finite() const {
  for (int b = 0; b < p_.num_bodies(); ++b)
    if (!p_.x[b].allFinite() || !p_.v[b].allFinite() || !p_.w[b].allFinite()) {
      std::ostringstream s;
      s << "particle " << p_.id[b] << " has a non-finite position or velocity at t = " << time_
        << " s (step " << steps_ << "); the model blew up: reduce the time step (critical "
        << critical_timestep() << " s) or check stiffness and loading";
      throw std::runtime_error(s.str());
    }
}

}  // namespace trackbed::dem
