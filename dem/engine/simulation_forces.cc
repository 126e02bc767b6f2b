// Simulation: the contact force kernels (particle pairs, plane walls, mesh walls) and the
// deterministic reduction of the per-thread loads (docs/theory.md, sections 4 and 5).
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "dem/engine/contact_history.h"
#include "dem/engine/simulation.h"
#include "dem/engine/simulation_internals.h"
#include "dem/engine/work_split.h"

namespace trackbed::dem {

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

// A deformable mesh's velocity at a contact point: its triangle's vertex velocities with the
// point's barycentric weights (the point lies on the triangle), which go to `weights`.
inline Vec3 deformable_velocity(const MeshBody& body, const MeshContactPoint& pt, Vec3& weights) {
  const auto& tri = body.world.triangles[pt.triangle];
  const auto& x = body.world.vertices;
  weights = closest_point_on_triangle(pt.point, x[tri[0]], x[tri[1]], x[tri[2]]).barycentric;
  const auto& u = body.deformation.velocity;
  return weights[0] * u[tri[0]] + weights[1] * u[tri[1]] + weights[2] * u[tri[2]];
}

// The one of an element's `slots` old contacts with a mesh whose normal is closest to n (within
// 60 degrees), or -1: a particle sliding over an edge keeps its spring.
inline int closest_old_contact(const Vec3* normal, const double* fn, const Vec3* shear, int slots,
                               const Vec3& n) {
  int best = -1;
  double best_dot = 0.5;
  for (int o = 0; o < slots; ++o) {
    if (fn[o] <= 0 && shear[o].squaredNorm() == 0) continue;
    const double dot = normal[o].dot(n);
    if (dot > best_dot) best_dot = dot, best = o;
  }
  return best;
}

}  // namespace

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
        const int best =
            closest_old_contact(&h.normal[c * S], &h.fn[c * S], &h.shear[c * S], S, pt.normal);
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
        Vec3 weights = Vec3::Zero();  // the point's barycentric weights (deformable meshes)
        kin.v_rel = point_velocity(p_.v[b], p_.w[b], lever) -
                    (body.deformable ? deformable_velocity(body, pt, weights)
                                     : point_velocity(body.v, body.w, wall_lever));
        kin.w_rel = body.deformable ? p_.w[b] : Vec3(p_.w[b] - body.w);
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
        if (body.deformable)
          for (int k = 0; k < 3; ++k)
            s.vertex_f[m][body.world.triangles[pt.triangle][k]] -= weights[k] * force;
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
  s.vertex_f.resize(meshes_.size());
  for (std::size_t m = 0; m < meshes_.size(); ++m) {
    s.part_f[m].assign(meshes_[m].local.part_names.size(), Vec3::Zero());
    s.part_t[m].assign(meshes_[m].local.part_names.size(), Vec3::Zero());
    if (meshes_[m].deformable) s.vertex_f[m].assign(meshes_[m].world.vertices.size(), Vec3::Zero());
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
    for (auto& v : m.deformation.load) v.setZero();
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
      for (std::size_t k = 0; k < s.vertex_f[m].size(); ++k)
        meshes_[m].deformation.load[k] += s.vertex_f[m][k];
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

}  // namespace trackbed::dem
