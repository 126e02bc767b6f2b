#include "dem/simulation.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "dem/contact_history.h"
#include "dem/input_error.h"
#include "dem/rigid_rotation.h"
#include "dem/work_split.h"

namespace trackbed::dem {

// Per-thread force accumulators (thread 0 writes the real arrays).
struct Simulation::ThreadScratch {
  // Thread 0 accumulates into the particles' own force and moment arrays, the others into these.
  std::vector<Vec3> f, t;
  std::vector<Vec3> wall_f, wall_t;               // per plane, then per mesh body
  std::vector<Vec3> wall_k, wall_kr;              // contact stiffness along each DOF
  std::vector<std::vector<Vec3>> part_f, part_t;  // per mesh body, per part
  Dissipation dissipation;
  double max_overlap_ratio = 0;
  int worst_i = -1, worst_j = -1;  // worst_i = -2 - wall index for a wall contact
  std::vector<MeshContactPoint> mesh_points;
};

namespace {

// The normal force stored for a touching contact: a contact whose dashpot cancels its spring
// (force 0) still exists (its overlap is positive), so it is kept as the smallest positive
// number; 0 means "not in contact".
inline double live_contact_force(double fn) {
  return std::max(fn, std::numeric_limits<double>::min());
}

// Velocity of the material point x of a rigid body.
inline Vec3 point_velocity(const Vec3& v, const Vec3& w, const Vec3& lever) {
  return v + w.cross(lever);
}

}  // namespace

Simulation::Simulation(MaterialTable materials, Particles particles, SimulationSettings settings)
    : materials_(std::move(materials)),
      p_(std::move(particles)),
      settings_(settings),
      pair_history_(std::make_unique<PairHistory>()),
      scratch_(std::make_unique<std::vector<ThreadScratch>>()) {
  materials_.validate();
  check_range("simulation: time step", settings_.time_step, 0.0, 1.0);
  check_range("simulation: critical timestep fraction", settings_.critical_fraction, 1e-6, 1.0);
  check_range("simulation: verlet skin", settings_.skin, 0.0, 1e3);
}

Simulation::~Simulation() = default;
Simulation::Simulation(Simulation&&) noexcept = default;
Simulation& Simulation::operator=(Simulation&&) noexcept = default;

int Simulation::add_plane(const PlaneWall& wall) {
  PlaneWall w = wall;
  const double len = w.normal.norm();
  if (!(len > 0) || !std::isfinite(len))
    throw InputError("plane wall '" + w.name + "': normal has zero length; give a direction");
  w.normal /= len;
  planes_.push_back(w);
  return static_cast<int>(planes_.size()) - 1;
}

int Simulation::mesh_index(const std::string& name) const {
  for (std::size_t k = 0; k < meshes_.size(); ++k)
    if (meshes_[k].name == name) return static_cast<int>(k);
  return -1;
}

int Simulation::add_mesh_body(MeshBody body) {
  body.update_world_mesh();
  body.part_force.assign(body.local.part_names.size(), Vec3::Zero());
  body.part_moment.assign(body.local.part_names.size(), Vec3::Zero());
  meshes_.push_back(std::move(body));
  return static_cast<int>(meshes_.size()) - 1;
}

// ---------------------------------------------------------------------------------------------
// Set-up and contact detection

void Simulation::setup() {
  parallel_ = p_.num_elements() >= settings_.parallel_threshold;
  // Neighbours in space become neighbours in memory before any index is handed out.
  if (settings_.spatial_sort) p_.sort_spatially(2 * p_.max_element_radius() + settings_.skin);
  for (int b = 0; b < p_.num_bodies(); ++b)
    if (p_.is_clump[b]) p_.L[b] = p_.world_inertia(b) * p_.w[b];
  p_.update_element_positions();
  rebuild();
  check_initial_overlaps();
  if (settings_.time_step == 0)
    settings_.time_step = settings_.critical_fraction * critical_timestep();
  set_time_step(settings_.time_step);
  ready_ = true;
}

void Simulation::set_time_step(double dt) {
  const double dt_crit = critical_timestep();
  if (!(dt > 0) || (dt > dt_crit && !settings_.allow_supercritical_step)) {
    std::ostringstream s;
    s << "simulation: time step = " << dt << " s is above the critical timestep " << dt_crit
      << " s of this model (PFC estimate); valid: a time step <= " << dt_crit
      << " s, or set 'allow timestep above critical = true' to force it";
    throw InputError(s.str());
  }
  settings_.time_step = dt;
}

void Simulation::particles_changed() {
  if (!ready_) return;  // setup() will see the new geometry
  for (int b = 0; b < p_.num_bodies(); ++b)
    if (p_.is_clump[b]) p_.L[b] = p_.world_inertia(b) * p_.w[b];
  p_.update_element_positions(parallel_);
  // Growth spends the skin like motion does: a pair whose radii grew by g each is still listed
  // while motion + growth stays within skin/2 per element.
  double growth = 0;
  for (int e = 0; e < p_.num_elements(); ++e)
    growth = std::max(growth, p_.radius[e] - radius_at_build_[e]);
  growth_since_build_ = growth;
  if (needs_rebuild()) rebuild();
}

void Simulation::set_materials(MaterialTable materials) {
  if (materials.size() != materials_.size())
    throw std::invalid_argument("Simulation::set_materials: the number of materials changed");
  materials.validate();
  materials_ = std::move(materials);
  // Switching rolling resistance on or off resizes the rolling springs.
  if (ready_) rebuild();
}

void Simulation::rebuild() {
  const double skin = settings_.skin;
  // Keep the old list and history to carry the springs of surviving pairs over.
  NeighborList old_list = std::move(list_);
  PairHistory old = std::move(*pair_history_);
  list_.build(p_, skin, parallel_);
  const int npairs = list_.num_pairs();
  PairHistory& h = *pair_history_;
  rolling_ = rolling_in_use(p_);
  h.shear.assign(npairs, Vec3::Zero());
  h.roll.assign(rolling_ ? npairs : 0, Vec3::Zero());
  h.fn.assign(npairs, 0.0);
  if (!old_list.offsets.empty()) {
    const int n = p_.num_elements();
#pragma omp parallel for schedule(static) if (parallel_)
    for (int i = 0; i < n; ++i) {
      // Both lists are sorted by partner: a merge walk finds the survivors.
      int a = old_list.offsets[i], b = list_.offsets[i];
      const int ae = old_list.offsets[i + 1], be = list_.offsets[i + 1];
      while (a < ae && b < be) {
        if (old_list.partners[a] < list_.partners[b]) {
          ++a;
        } else if (old_list.partners[a] > list_.partners[b]) {
          ++b;
        } else {
          h.shear[b] = old.shear[a];
          if (rolling_ && !old.roll.empty()) h.roll[b] = old.roll[a];
          h.fn[b] = old.fn[a];
          ++a, ++b;
        }
      }
    }
  }

  // Plane walls: every element closer than r + skin (or behind the plane).
  plane_history_.resize(planes_.size() + meshes_.size());
  for (std::size_t w = 0; w < planes_.size(); ++w) {
    WallHistory fresh;
    const WallHistory& prev = plane_history_[w];
    std::size_t k = 0;
    for (int e = 0; e < p_.num_elements(); ++e) {
      if (planes_[w].distance(p_.pos[e]) >= p_.radius[e] + skin) continue;
      fresh.element.push_back(e);
      while (k < prev.element.size() && prev.element[k] < e) ++k;
      const bool kept = k < prev.element.size() && prev.element[k] == e;
      fresh.shear.push_back(kept ? prev.shear[k] : Vec3::Zero());
      fresh.roll.push_back(kept ? prev.roll[k] : Vec3::Zero());
      fresh.fn.push_back(kept ? prev.fn[k] : 0.0);
    }
    plane_history_[w] = std::move(fresh);
  }

  // Meshes: candidate triangles of every element within r + skin of the mesh.
  for (std::size_t m = 0; m < meshes_.size(); ++m) {
    const MeshBody& body = meshes_[m];
    const WallHistory& prev = plane_history_[planes_.size() + m];
    WallHistory fresh;
    fresh.triangle_offsets.push_back(0);
    TriangleGrid grid;
    grid.build(body.world, 2 * p_.max_element_radius() + skin);
    std::vector<int> found;
    std::size_t k = 0;
    constexpr int S = WallHistory::kSlots;
    for (int e = 0; e < p_.num_elements(); ++e) {
      grid.query(p_.pos[e], p_.radius[e] + skin, found);
      if (found.empty()) continue;
      fresh.element.push_back(e);
      fresh.triangles.insert(fresh.triangles.end(), found.begin(), found.end());
      fresh.triangle_offsets.push_back(static_cast<int>(fresh.triangles.size()));
      while (k < prev.element.size() && prev.element[k] < e) ++k;
      const bool kept = k < prev.element.size() && prev.element[k] == e;
      for (int s = 0; s < S; ++s) {
        fresh.shear.push_back(kept ? prev.shear[k * S + s] : Vec3::Zero());
        fresh.roll.push_back(kept ? prev.roll[k * S + s] : Vec3::Zero());
        fresh.normal.push_back(kept ? prev.normal[k * S + s] : Vec3::Zero());
        fresh.fn.push_back(kept ? prev.fn[k * S + s] : 0.0);
      }
    }
    plane_history_[planes_.size() + m] = std::move(fresh);
  }

  pos_at_build_ = p_.pos;
  radius_at_build_ = p_.radius;
  growth_since_build_ = 0;
  plane_point_at_build_.clear();
  for (const auto& w : planes_) plane_point_at_build_.push_back(w.point);
  for (const auto& m : meshes_) plane_point_at_build_.push_back(m.x);
  mesh_q_at_build_.clear();
  for (const auto& m : meshes_) mesh_q_at_build_.push_back(m.q);
  pair_ranges_.clear();  // made again for the new list (compute_forces)
  ++builds_;
}

double Simulation::rebuild_distance() const {
  return 0.5 * settings_.skin - growth_since_build_;
}

bool Simulation::needs_rebuild() const {
  const double half = rebuild_distance();
  if (half <= 0) return true;
  const double limit = half * half;
  const int n = p_.num_elements();
  int moved = 0;
#pragma omp parallel for schedule(static) reduction(max : moved) if (parallel_)
  for (int e = 0; e < n; ++e)
    if (moved_farther_than(e, limit)) moved = 1;
  return moved || walls_moved(half);
}

bool Simulation::walls_moved(double half) const {
  for (std::size_t w = 0; w < planes_.size(); ++w)
    if (std::abs((planes_[w].point - plane_point_at_build_[w]).dot(planes_[w].normal)) > half)
      return true;
  for (std::size_t m = 0; m < meshes_.size(); ++m) {
    const MeshBody& b = meshes_[m];
    // A bound on any vertex's displacement: translation plus rotation angle times reach.
    const double angle = b.q.angularDistance(mesh_q_at_build_[m]);
    const double d = (b.x - plane_point_at_build_[planes_.size() + m]).norm() + angle * b.reach();
    if (d > half) return true;
  }
  return false;
}

bool Simulation::rolling_in_use(const Particles& p) const {
  // The materials the elements carry, then every pair they can form with each other or a wall.
  const int nmat = materials_.size();
  std::vector<char> carried(nmat, 0);
  for (int m : p.material) carried[m] = 1;
  std::vector<int> partners;
  for (int m = 0; m < nmat; ++m)
    if (carried[m]) partners.push_back(m);
  for (const auto& w : planes_) partners.push_back(w.material);
  for (const auto& m : meshes_) partners.push_back(m.material);
  for (int a = 0; a < nmat; ++a)
    if (carried[a])
      for (int b : partners)
        if (materials_.pair(a, b).has_rolling()) return true;
  return false;
}

void Simulation::check_initial_overlaps() const {
  const double tol = settings_.initial_overlap_ratio;
  for (int i = 0; i < p_.num_elements(); ++i)
    for (int k = list_.offsets[i]; k < list_.offsets[i + 1]; ++k) {
      const int j = list_.partners[k];
      const double overlap = p_.radius[i] + p_.radius[j] - (p_.pos[j] - p_.pos[i]).norm();
      if (overlap > tol * std::min(p_.radius[i], p_.radius[j])) {
        std::ostringstream s;
        s << "particles " << p_.id[p_.body[i]] << " and " << p_.id[p_.body[j]] << " overlap by "
          << overlap << " m at start (more than " << tol
          << " of the smaller radius); valid: a packing with overlaps below that, e.g. a "
             "settled sample";
        throw InputError(s.str());
      }
    }
  for (std::size_t w = 0; w < planes_.size(); ++w)
    for (int e : plane_history_[w].element) {
      const double overlap = p_.radius[e] - planes_[w].distance(p_.pos[e]);
      if (overlap > tol * p_.radius[e]) {
        std::ostringstream s;
        s << "particle " << p_.id[p_.body[e]] << " overlaps wall '" << planes_[w].name << "' by "
          << overlap << " m at start (more than " << tol
          << " of its radius); valid: every particle on the inner side of every wall";
        throw InputError(s.str());
      }
    }
  visit_mesh_contacts([&](int m, int, int e, const MeshContactPoint& pt, int) {
    if (pt.overlap <= tol * p_.radius[e]) return;
    std::ostringstream s;
    s << "particle " << p_.id[p_.body[e]] << " overlaps mesh '" << meshes_[m].name << "' by "
      << pt.overlap << " m at start (more than " << tol
      << " of its radius); valid: particles clear of the mesh at start";
    throw InputError(s.str());
  });
}

void Simulation::mesh_points_now(std::size_t m, std::size_t c,
                                 std::vector<MeshContactPoint>& points) const {
  const WallHistory& h = plane_history_[planes_.size() + m];
  const int e = h.element[c];
  sphere_mesh_contacts(meshes_[m].world, p_.pos[e], p_.radius[e],
                       h.triangles.data() + h.triangle_offsets[c],
                       h.triangle_offsets[c + 1] - h.triangle_offsets[c], points);
}

template <class Visitor>
void Simulation::visit_mesh_contacts(Visitor&& visit) const {
  std::vector<MeshContactPoint> points;
  for (std::size_t m = 0; m < meshes_.size(); ++m) {
    const WallHistory& h = plane_history_[planes_.size() + m];
    for (std::size_t c = 0; c < h.element.size(); ++c) {
      const int e = h.element[c];
      mesh_points_now(m, c, points);
      const int used = std::min<int>(static_cast<int>(points.size()), WallHistory::kSlots);
      for (int a = 0; a < used; ++a)
        visit(static_cast<int>(m), static_cast<int>(c), e, points[a], a);
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Forces

template <bool Rolling, bool Energy>
void Simulation::pair_forces(ThreadScratch& s) {
  // This thread's rows of the list: a share of the work, not of the elements (the contacts are
  // denser in some parts of a bed than in others).
  const int t = omp_get_thread_num();
  const int first = pair_ranges_[t], last = pair_ranges_[t + 1];
  const double dt = settings_.time_step;
  const double ratio_limit = settings_.max_overlap_ratio;
  PairHistory& h = *pair_history_;
  const int nmat = materials_.size();
  const ContactProperties* props = &materials_.pair(0, 0);

  auto [F, T] = body_load_arrays(s);
  Dissipation d;
  Vec3 unused_roll, roll_moment = Vec3::Zero();
  for (int i = first; i < last; ++i) {
    const Vec3 xi = p_.pos[i];
    const double ri = p_.radius[i];
    const int bi = p_.body[i];
    const int mi = p_.material[i];
    for (int k = list_.offsets[i]; k < list_.offsets[i + 1]; ++k) {
      const int j = list_.partners[k];
      const Vec3 dx = p_.pos[j] - xi;
      const double rsum = ri + p_.radius[j];
      const double d2 = dx.squaredNorm();
      if (d2 >= rsum * rsum) {
        // Separated: the springs relax (PFC deletes the contact). fn marks a live contact, so
        // pairs that were apart already cost no write (and no cache line of history).
        if (h.fn[k] != 0) {
          h.shear[k].setZero();
          if constexpr (Rolling) h.roll[k].setZero();
          h.fn[k] = 0;
        }
        continue;
      }
      const int bj = p_.body[j];
      const double dist = std::sqrt(d2);
      ContactKinematics kin;
      kin.n = dx / dist;
      kin.overlap = rsum - dist;
      const double rj = p_.radius[j];
      if (kin.overlap > ratio_limit * std::min(ri, rj)) {
        const double r = kin.overlap / std::min(ri, rj);
        if (r > s.max_overlap_ratio) s.max_overlap_ratio = r, s.worst_i = i, s.worst_j = j;
      }
      // Contact point in the middle of the overlap.
      const Vec3 c = xi + kin.n * (ri - 0.5 * kin.overlap);
      const Vec3 lever_i = c - p_.x[bi], lever_j = c - p_.x[bj];
      kin.v_rel =
          point_velocity(p_.v[bj], p_.w[bj], lever_j) - point_velocity(p_.v[bi], p_.w[bi], lever_i);
      kin.m_eff = p_.mass[bi] * p_.mass[bj] / (p_.mass[bi] + p_.mass[bj]);
      if constexpr (Rolling) {
        kin.w_rel = p_.w[bj] - p_.w[bi];
        kin.r_eff = ri * rj / rsum;
      }
      const ContactProperties& prop = props[mi * nmat + p_.material[j]];
      const Vec3 force = linear_contact<Rolling, Energy>(
          prop, kin, dt, h.shear[k], Rolling ? h.roll[k] : unused_roll, roll_moment, d);
      h.fn[k] = live_contact_force(force.dot(kin.n));
      F[bj] += force;
      F[bi] -= force;
      T[bj] += lever_j.cross(force);
      T[bi] -= lever_i.cross(force);
      if constexpr (Rolling) {
        T[bj] += roll_moment;
        T[bi] -= roll_moment;
      }
    }
  }
  s.dissipation += d;
}

template <bool Rolling, bool Energy>
void Simulation::plane_forces(ThreadScratch& s) {
  const double dt = settings_.time_step;
  const int nplanes = static_cast<int>(planes_.size());
  auto [F, T] = body_load_arrays(s);
  Dissipation d;
  Vec3 roll_moment = Vec3::Zero();
  for (int w = 0; w < nplanes; ++w) {
    const PlaneWall& wall = planes_[w];
    WallHistory& h = plane_history_[w];
    const int nc = static_cast<int>(h.element.size());
#pragma omp for schedule(static) nowait
    for (int c = 0; c < nc; ++c) {
      const int e = h.element[c];
      const double r = p_.radius[e];
      const double dist = wall.distance(p_.pos[e]);
      if (dist >= r) {
        h.shear[c].setZero();
        h.roll[c].setZero();
        h.fn[c] = 0;
        continue;
      }
      const int b = p_.body[e];
      ContactKinematics kin;
      kin.n = wall.normal;  // from the wall (side i) to the particle (side j)
      kin.overlap = r - dist;
      if (kin.overlap > settings_.max_overlap_ratio * r) {
        const double ratio = kin.overlap / r;
        if (ratio > s.max_overlap_ratio)
          s.max_overlap_ratio = ratio, s.worst_i = -2 - w, s.worst_j = e;
      }
      const Vec3 c_pt = p_.pos[e] - dist * wall.normal;  // the touched point of the plane
      const Vec3 lever = c_pt - p_.x[b];
      kin.v_rel = point_velocity(p_.v[b], p_.w[b], lever) - wall.velocity;
      kin.w_rel = p_.w[b];
      kin.m_eff = p_.mass[b];
      kin.r_eff = r;
      const ContactProperties& prop = materials_.pair(wall.material, p_.material[e]);
      const Vec3 force =
          linear_contact<Rolling, Energy>(prop, kin, dt, h.shear[c], h.roll[c], roll_moment, d);
      h.fn[c] = live_contact_force(force.dot(kin.n));
      F[b] += force;
      T[b] += lever.cross(force);
      if constexpr (Rolling) T[b] += roll_moment;
      s.wall_f[w] -= force;
      s.wall_t[w] -= (c_pt - wall.point).cross(force) + (Rolling ? roll_moment : Vec3::Zero());
    }
  }
  s.dissipation += d;
}

template <bool Rolling, bool Energy>
void Simulation::mesh_forces(ThreadScratch& s) {
  const double dt = settings_.time_step;
  constexpr int S = WallHistory::kSlots;
  const int nplanes = static_cast<int>(planes_.size());
  auto [F, T] = body_load_arrays(s);
  Dissipation d;
  Vec3 roll_moment = Vec3::Zero();
  for (std::size_t m = 0; m < meshes_.size(); ++m) {
    const MeshBody& body = meshes_[m];
    WallHistory& h = plane_history_[nplanes + m];
    const int slot_wall = nplanes + static_cast<int>(m);
    const int nc = static_cast<int>(h.element.size());
#pragma omp for schedule(static) nowait
    for (int c = 0; c < nc; ++c) {
      const int e = h.element[c];
      const double r = p_.radius[e];
      sphere_mesh_contacts(body.world, p_.pos[e], r, h.triangles.data() + h.triangle_offsets[c],
                           h.triangle_offsets[c + 1] - h.triangle_offsets[c], s.mesh_points);
      // Each new contact inherits the spring of the old contact of this element whose normal
      // is closest (within 60 degrees): a particle sliding over an edge keeps its history.
      Vec3 shear[S], roll[S], normal[S];
      double fn[S];
      const int used = std::min<int>(static_cast<int>(s.mesh_points.size()), S);
      const int b = p_.body[e];
      for (int a = 0; a < used; ++a) {
        const MeshContactPoint& pt = s.mesh_points[a];
        int best = -1;
        double best_dot = 0.5;
        for (int o = 0; o < S; ++o) {
          if (h.fn[c * S + o] <= 0 && h.shear[c * S + o].squaredNorm() == 0) continue;
          const double dot = h.normal[c * S + o].dot(pt.normal);
          if (dot > best_dot) best_dot = dot, best = o;
        }
        shear[a] = best >= 0 ? h.shear[c * S + best] : Vec3::Zero();
        roll[a] = best >= 0 ? h.roll[c * S + best] : Vec3::Zero();
        normal[a] = pt.normal;

        ContactKinematics kin;
        kin.n = pt.normal;
        kin.overlap = pt.overlap;
        if (kin.overlap > settings_.max_overlap_ratio * r) {
          const double ratio = kin.overlap / r;
          if (ratio > s.max_overlap_ratio)
            s.max_overlap_ratio = ratio, s.worst_i = -2 - slot_wall, s.worst_j = e;
        }
        const Vec3 lever = pt.point - p_.x[b];
        const Vec3 wall_lever = pt.point - body.x;
        kin.v_rel =
            point_velocity(p_.v[b], p_.w[b], lever) - point_velocity(body.v, body.w, wall_lever);
        kin.w_rel = p_.w[b] - body.w;
        kin.m_eff = p_.mass[b];
        kin.r_eff = r;
        const ContactProperties& prop = materials_.pair(body.material, p_.material[e]);
        const Vec3 force =
            linear_contact<Rolling, Energy>(prop, kin, dt, shear[a], roll[a], roll_moment, d);
        fn[a] = live_contact_force(force.dot(kin.n));
        F[b] += force;
        T[b] += lever.cross(force);
        if constexpr (Rolling) T[b] += roll_moment;
        const Vec3 moment = wall_lever.cross(force) + (Rolling ? roll_moment : Vec3::Zero());
        s.wall_f[slot_wall] -= force;
        s.wall_t[slot_wall] -= moment;
        s.wall_k[slot_wall] += prop.kn * kin.n.cwiseAbs2();
        s.wall_kr[slot_wall] += prop.kn * wall_lever.cross(kin.n).cwiseAbs2();
        const int part = body.world.triangle_part[pt.triangle];
        s.part_f[m][part] -= force;
        s.part_t[m][part] -= moment;
      }
      for (int a = 0; a < S; ++a) {
        const bool live = a < used;
        h.shear[c * S + a] = live ? shear[a] : Vec3::Zero();
        h.roll[c * S + a] = live ? roll[a] : Vec3::Zero();
        h.normal[c * S + a] = live ? normal[a] : Vec3::Zero();
        h.fn[c * S + a] = live ? fn[a] : 0.0;
      }
    }
  }
  s.dissipation += d;
}

std::pair<Vec3*, Vec3*> Simulation::body_load_arrays(ThreadScratch& s) {
  if (omp_get_thread_num() == 0) return {p_.f.data(), p_.t.data()};
  return {s.f.data(), s.t.data()};
}

void Simulation::compute_forces() {
  const int nthreads = team_size();
  scratch_->resize(nthreads);
  if (static_cast<int>(pair_ranges_.size()) != nthreads + 1) {
    pair_ranges_ = list_.balanced_ranges(pos_at_build_, radius_at_build_, nthreads);
  }
  // One parallel region for the whole pass, with one barrier: each thread clears its own
  // buffers, runs its share of the pair, plane and mesh loops one after the other (it writes only
  // its buffers and its own contacts' history, so they need no barrier between them) and, once
  // every thread is done, adds the other threads' body loads to its share of the bodies. A
  // region or a barrier costs microseconds, a tenth of a step in a model of a few thousand
  // elements (docs/benchmarks.md, "Threads on a small model").
#pragma omp parallel if (parallel_)
  {
    ThreadScratch& s = (*scratch_)[omp_get_thread_num()];
    clear_thread_loads(s);
    if (rolling_)
      settings_.track_energy ? contact_forces<true, true>(s) : contact_forces<true, false>(s);
    else
      settings_.track_energy ? contact_forces<false, true>(s) : contact_forces<false, false>(s);
    if (nthreads > 1) {
#pragma omp barrier
      add_thread_body_loads();
    }
  }
  reduce_thread_wall_loads();
}

template <bool Rolling, bool Energy>
void Simulation::contact_forces(ThreadScratch& s) {
  pair_forces<Rolling, Energy>(s);
  plane_forces<Rolling, Energy>(s);
  mesh_forces<Rolling, Energy>(s);
}

void Simulation::clear_thread_loads(ThreadScratch& s) {
  const int nb = p_.num_bodies();
  const std::size_t nwalls = planes_.size() + meshes_.size();
  if (omp_get_thread_num() == 0) {  // its loads go to the bodies' own arrays
    std::fill(p_.f.begin(), p_.f.end(), Vec3::Zero());
    std::fill(p_.t.begin(), p_.t.end(), Vec3::Zero());
  } else {
    s.f.assign(nb, Vec3::Zero());
    s.t.assign(nb, Vec3::Zero());
  }
  s.wall_f.assign(nwalls, Vec3::Zero());
  s.wall_t.assign(nwalls, Vec3::Zero());
  s.wall_k.assign(nwalls, Vec3::Zero());
  s.wall_kr.assign(nwalls, Vec3::Zero());
  s.part_f.resize(meshes_.size());
  s.part_t.resize(meshes_.size());
  for (std::size_t m = 0; m < meshes_.size(); ++m) {
    s.part_f[m].assign(meshes_[m].local.part_names.size(), Vec3::Zero());
    s.part_t[m].assign(meshes_[m].local.part_names.size(), Vec3::Zero());
  }
  s.dissipation = Dissipation();
  s.max_overlap_ratio = 0;
}

void Simulation::add_thread_body_loads() {
  const auto& scratch = *scratch_;
  const int nthreads = static_cast<int>(scratch.size());
  const int nb = p_.num_bodies();
#pragma omp for schedule(static)
  for (int b = 0; b < nb; ++b)
    for (int t = 1; t < nthreads; ++t) {
      p_.f[b] += scratch[t].f[b];
      p_.t[b] += scratch[t].t[b];
    }
}

void Simulation::reduce_thread_wall_loads() {
  // Walls, dissipation and the runaway check, summed in thread order (deterministic).
  const auto& scratch = *scratch_;
  for (auto& w : planes_) w.force.setZero(), w.moment.setZero();
  for (auto& m : meshes_) {
    m.contact_force.setZero();
    m.contact_moment.setZero();
    m.contact_stiffness.setZero();
    m.contact_rotational_stiffness.setZero();
    for (auto& v : m.part_force) v.setZero();
    for (auto& v : m.part_moment) v.setZero();
  }
  double worst = 0;
  int wi = -1, wj = -1;
  for (const auto& s : scratch) {
    for (std::size_t w = 0; w < planes_.size(); ++w) {
      planes_[w].force += s.wall_f[w];
      planes_[w].moment += s.wall_t[w];
    }
    for (std::size_t m = 0; m < meshes_.size(); ++m) {
      meshes_[m].contact_force += s.wall_f[planes_.size() + m];
      meshes_[m].contact_moment += s.wall_t[planes_.size() + m];
      meshes_[m].contact_stiffness += s.wall_k[planes_.size() + m];
      meshes_[m].contact_rotational_stiffness += s.wall_kr[planes_.size() + m];
      for (std::size_t k = 0; k < meshes_[m].part_force.size(); ++k) {
        meshes_[m].part_force[k] += s.part_f[m][k];
        meshes_[m].part_moment[k] += s.part_t[m][k];
      }
    }
    tally_.friction += s.dissipation.friction;
    tally_.rolling += s.dissipation.rolling;
    tally_.dashpot += s.dissipation.dashpot;
    if (s.max_overlap_ratio > worst) worst = s.max_overlap_ratio, wi = s.worst_i, wj = s.worst_j;
  }
  if (worst > 0) {
    const int nplanes = static_cast<int>(planes_.size());
    std::string other;
    if (wi <= -2) {
      const int w = -2 - wi;
      other = w < nplanes ? "wall '" + planes_[w].name + "'"
                          : "mesh '" + meshes_[w - nplanes].name + "'";
    }
    runaway(wi, wj, worst, other);
  }
}

void Simulation::runaway(int ei, int ej, double ratio, const std::string& other) const {
  std::ostringstream s;
  s << "runaway overlap at t = " << time_ << " s (step " << steps_ << "): ";
  if (other.empty())
    s << "particles " << p_.id[p_.body[ei]] << " and " << p_.id[p_.body[ej]];
  else
    s << "particle " << p_.id[p_.body[ej]] << " and " << other;
  s << " overlap by " << ratio << " of the smaller radius (limit " << settings_.max_overlap_ratio
    << "); the model is unstable: reduce the time step (critical " << critical_timestep()
    << " s) or the loading rate, or raise the stiffness";
  throw std::runtime_error(s.str());
}

// ---------------------------------------------------------------------------------------------
// Time integration

bool Simulation::integrate_bodies() {
  const int nb = p_.num_bodies();
  const double dt = settings_.time_step;
  const Vec3 g = settings_.gravity;
  const double half = rebuild_distance();
  const double limit = half * half;
  const int nthreads = team_size();
  if (static_cast<int>(body_ranges_.size()) != nthreads + 1 || body_ranges_.back() != nb)
    body_ranges_ = body_work_ranges(nthreads);
  // Per-thread partial sums added in thread order: the tallies are reproducible bit for bit.
  // Each thread sums in registers and stores once (neighbouring slots share a cache line).
  std::vector<double> local(nthreads, 0.0), gravity_work(nthreads, 0.0);
  std::vector<int> moved_by(nthreads, 0);
  // One region for the bodies' motion, their elements' positions and the Verlet check of those
  // elements (body by body: each touches only its own elements).
#pragma omp parallel if (parallel_)
  {
    const int t = omp_get_thread_num();
    double my_local = 0, my_gravity_work = 0;
    int my_moved = 0;
    for (int b = body_ranges_[t]; b < body_ranges_[t + 1]; ++b) {
      const double m = p_.mass[b];
      const double scale = inertia_scale(b);  // density scaling: accelerated as s m, s I
      const double alpha = materials_[p_.body_material[b]].local_damping;
      Vec3 F = p_.f[b] + m * g;
      Vec3 M = p_.t[b];
      // Local damping (PFC): each component of the unbalanced force and moment is reduced by
      // alpha |F_k| against the sign of the matching velocity component.
      Vec3 Fd = Vec3::Zero(), Md = Vec3::Zero();
      if (alpha > 0) {
        for (int k = 0; k < 3; ++k) {
          Fd[k] = -alpha * std::abs(F[k]) * ((p_.v[b][k] > 0) - (p_.v[b][k] < 0));
          Md[k] = -alpha * std::abs(M[k]) * ((p_.w[b][k] > 0) - (p_.w[b][k] < 0));
        }
        F += Fd;
        M += Md;
      }
      p_.v[b] += F * (dt / (scale * m));
      const Vec3 dx = p_.v[b] * dt;
      p_.x[b] += dx;
      my_gravity_work += m * g.dot(dx);
      if (p_.is_clump[b]) {
        // L stays the true I w: d(s I w)/dt = M.
        p_.L[b] += M * (dt / scale);
        // w = R I^-1 R^T L, with R^T L as the free rotation leaves it.
        const Vec3 inv_inertia = p_.inertia[b].cwiseInverse();
        const Vec3 pi = free_rotation(p_.q[b], p_.L[b], inv_inertia, dt);
        p_.w[b] = p_.q[b] * pi.cwiseProduct(inv_inertia);
      } else {
        p_.w[b] += M * (dt / (scale * p_.inertia[b][0]));
      }
      my_local -= Fd.dot(dx) + Md.dot(p_.w[b]) * dt;
      p_.update_body_elements(b);
      for (int e = p_.first_element[b]; e < p_.first_element[b + 1]; ++e)
        if (moved_farther_than(e, limit)) my_moved = 1;
    }
    local[t] = my_local;
    gravity_work[t] = my_gravity_work;
    moved_by[t] = my_moved;
  }
  bool moved = half <= 0;
  for (int t = 0; t < nthreads; ++t) {
    tally_.local_damping += local[t];
    tally_.gravity_work += gravity_work[t];
    moved = moved || moved_by[t];
  }
  return moved;
}

std::vector<int> Simulation::body_work_ranges(int parts) const {
  // In units of placing and checking one element: a body's motion 2, a clump's free rotation 12
  // more. A clump of 8.4 elements then weighs 22.4, and took 756 instructions a step (callgrind,
  // docs/benchmarks.md, "DEM throughput"): about 34 a unit; a ball's 3 units (about 100
  // instructions) are estimated from its operations, not measured.
  constexpr long long kBodyMotionWork = 2, kClumpRotationWork = 12;
  const int nb = p_.num_bodies();
  std::vector<long long> work(nb + 1, 0);
  for (int b = 0; b < nb; ++b)
    work[b + 1] = work[b] + kBodyMotionWork + (p_.first_element[b + 1] - p_.first_element[b]) +
                  (p_.is_clump[b] ? kClumpRotationWork : 0);
  return split_by_work(work, parts);
}

void Simulation::move_walls() {
  // Work of a wall on the particles: minus the particles' force on it times its motion, by the
  // trapezoidal rule, each step's motion d_n with the mean force at its ends (F_n + F_n+1)/2,
  // exact for linear springs (docs/theory.md, "Energy budget"). The rectangle rule F_n . d_n
  // misses k d_n^2 / 2 every step, with the same sign whichever way the wall moves, so a wall
  // that jitters (a servo) piles it up. The step's first half is added now and the second half
  // with the next step's forces (closing_wall_work).
  const double dt = settings_.time_step;
  tally_.wall_work += closing_wall_work();
  last_wall_motion_.resize(planes_.size() + meshes_.size(), {Vec3::Zero(), Vec3::Zero()});
  auto tally = [&](std::size_t k, const Vec3& force, const Vec3& moment, const Vec3& move,
                   const Vec3& turn) {
    tally_.wall_work -= 0.5 * (force.dot(move) + moment.dot(turn));
    last_wall_motion_[k] = {move, turn};
  };
  for (std::size_t k = 0; k < planes_.size(); ++k) {
    PlaneWall& w = planes_[k];
    tally(k, w.force, Vec3::Zero(), w.velocity * dt, Vec3::Zero());
    w.point += w.velocity * dt;
  }
  for (std::size_t k = 0; k < meshes_.size(); ++k) {
    MeshBody& m = meshes_[k];
    const Vec3 x0 = m.x;
    m.integrate(dt, settings_.gravity);
    tally(planes_.size() + k, m.contact_force, m.contact_moment, m.x - x0, m.w * dt);
  }
}

void Simulation::step() {
  if (!ready_) setup();
  compute_forces();
  const bool elements_moved = integrate_bodies();
  move_walls();
  time_ += settings_.time_step;
  ++steps_;
  if (elements_moved || walls_moved(rebuild_distance())) rebuild();
}

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

std::vector<double> Simulation::body_critical_steps(bool within_skin) const {
  // Stiffness per body and DOF, summed over its contacts with K = k_n n n^T + k_s (I - n n^T):
  // translation along e_a: e_a^T K e_a; rotation about e_a: u^T K u with u = e_a x lever (the
  // contact point's displacement per unit rotation), plus the rolling stiffness k_s R_eff^2.
  // PFC takes sqrt(m / k) and sqrt(I / k_rot), the smallest over bodies and DOFs.
  const int nb = p_.num_bodies();
  std::vector<Vec3> kt(nb, Vec3::Zero()), kr(nb, Vec3::Zero());
  auto add = [&](int b, const ContactProperties& pr, const Vec3& n, const Vec3& lever, double r) {
    for (int a = 0; a < 3; ++a) {
      kt[b][a] += pr.kn * n[a] * n[a] + pr.ks * (1 - n[a] * n[a]);
      const Vec3 u = Vec3::Unit(a).cross(lever);
      const double un = u.dot(n);
      kr[b][a] += pr.kn * un * un + pr.ks * (u.squaredNorm() - un * un) +
                  (pr.has_rolling() ? pr.ks * r * r : 0.0);
    }
  };
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
      if (touching) touches[p_.body[i]] = touches[p_.body[j]] = 1;
      const Vec3 n = d.normalized();
      const ContactProperties& pr = materials_.pair(p_.material[i], p_.material[j]);
      const double reff = p_.radius[i] * p_.radius[j] / (p_.radius[i] + p_.radius[j]);
      add(p_.body[i], pr, n, p_.pos[i] + n * p_.radius[i] - p_.x[p_.body[i]], reff);
      add(p_.body[j], pr, n, p_.pos[j] - n * p_.radius[j] - p_.x[p_.body[j]], reff);
    }
  for (std::size_t w = 0; w < planes_.size(); ++w)
    for (int e : plane_history_[w].element) {
      if (planes_[w].distance(p_.pos[e]) >= p_.radius[e]) continue;
      const ContactProperties& pr = materials_.pair(planes_[w].material, p_.material[e]);
      touches[p_.body[e]] = 1;
      add(p_.body[e], pr, planes_[w].normal,
          p_.pos[e] - planes_[w].normal * p_.radius[e] - p_.x[p_.body[e]], p_.radius[e]);
    }
  visit_mesh_contacts([&](int m, int, int e, const MeshContactPoint& pt, int) {
    touches[p_.body[e]] = 1;
    add(p_.body[e], materials_.pair(meshes_[m].material, p_.material[e]), pt.normal,
        pt.point - p_.x[p_.body[e]], p_.radius[e]);
  });
  std::vector<double> steps(nb);
  for (int b = 0; b < nb; ++b) {
    if (!touches[b]) {
      // A body touching nothing yet: one contact with its own material, its first touch.
      const int e = p_.first_element[b];
      const ContactProperties& pr = materials_.pair(p_.material[e], p_.material[e]);
      kt[b].array() += std::max(pr.kn, pr.ks);
      kr[b].array() += pr.ks * std::pow((p_.pos[e] - p_.x[b]).norm() + p_.radius[e], 2);
    }
    steps[b] = std::sqrt(p_.mass[b] / kt[b].maxCoeff());
    if (kr[b].maxCoeff() > 0)
      steps[b] = std::min(steps[b], std::sqrt(p_.inertia[b].minCoeff() / kr[b].maxCoeff()));
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
