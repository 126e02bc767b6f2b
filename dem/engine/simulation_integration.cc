// Simulation: the time step -- forces, then the bodies and walls moved (docs/theory.md,
// section 7).
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "dem/engine/rigid_rotation.h"
#include "dem/engine/simulation.h"
#include "dem/engine/simulation_internals.h"
#include "dem/engine/work_split.h"

namespace trackbed::dem {

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
  std::vector<int> moved_by(nthreads, 0), blown_up(nthreads, 0);
  // One region for the bodies' motion, their elements' positions and the Verlet check of those
  // elements (body by body: each touches only its own elements).
#pragma omp parallel if (parallel_)
  {
    const int t = omp_get_thread_num();
    double my_local = 0, my_gravity_work = 0;
    int my_moved = 0, my_blown_up = 0;
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
      // A NaN or an infinity anywhere in the step ends in the velocities (inf - inf is NaN).
      if (!std::isfinite(p_.v[b].sum() + p_.w[b].sum())) my_blown_up = 1;
      my_local -= Fd.dot(dx) + Md.dot(p_.w[b]) * dt;
      p_.update_body_elements(b);
      for (int e = p_.first_element[b]; e < p_.first_element[b + 1]; ++e)
        if (moved_farther_than(e, limit)) my_moved = 1;
    }
    local[t] = my_local;
    gravity_work[t] = my_gravity_work;
    moved_by[t] = my_moved;
    blown_up[t] = my_blown_up;
  }
  bool moved = half <= 0;
  for (int t = 0; t < nthreads; ++t) {
    tally_.local_damping += local[t];
    tally_.gravity_work += gravity_work[t];
    moved = moved || moved_by[t];
    if (blown_up[t]) check_finite();
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
    if (m.deformable) {
      move_deformable_mesh(m, dt);
      continue;
    }
    const Vec3 x0 = m.x;
    m.integrate(dt, settings_.gravity);
    tally(planes_.size() + k, m.contact_force, m.contact_moment, m.x - x0, m.w * dt);
  }
}

void Simulation::move_deformable_mesh(MeshBody& m, double dt) {
  MeshDeformation& d = m.deformation;
  for (std::size_t v = 0; v < m.world.vertices.size(); ++v) {
    d.pending_move[v] = d.velocity[v] * dt;
    tally_.wall_work -= 0.5 * d.load[v].dot(d.pending_move[v]);
    m.world.vertices[v] += d.pending_move[v];
  }
}

void Simulation::set_mesh_vertices(int mesh, const std::vector<Vec3>& positions,
                                   const std::vector<Vec3>& velocities) {
  if (mesh < 0 || mesh >= static_cast<int>(meshes_.size()) || !meshes_[mesh].deformable)
    throw std::invalid_argument("set_mesh_vertices: mesh " + std::to_string(mesh) +
                                " is not a deformable mesh of this model");
  MeshBody& m = meshes_[mesh];
  MeshDeformation& d = m.deformation;
  const std::size_t n = m.world.vertices.size();
  if (positions.size() != n || velocities.size() != n)
    throw std::invalid_argument("set_mesh_vertices: mesh '" + m.name + "' has " +
                                std::to_string(n) + " vertices, given " +
                                std::to_string(positions.size()) + " positions and " +
                                std::to_string(velocities.size()) + " velocities");
  for (std::size_t v = 0; v < n; ++v)
    if (!positions[v].allFinite() || !velocities[v].allFinite())
      throw std::runtime_error("mesh '" + m.name + "': vertex " + std::to_string(v) +
                               " was given a non-finite position or velocity");
  // A jump between steps is a wall motion like a step's: its work by the trapezoidal rule, half
  // with the loads now and half with the next force pass's (closing_wall_work).
  for (std::size_t v = 0; v < n; ++v) {
    const Vec3 jump = positions[v] - m.world.vertices[v];
    tally_.wall_work -= 0.5 * d.load[v].dot(jump);
    d.pending_move[v] += jump;
  }
  m.world.vertices = positions;
  d.velocity = velocities;
}

void Simulation::step() {
  if (!ready_) setup();
  compute_forces();
  for (MeshBody& m : meshes_)
    if (m.deformable) {
      MeshDeformation& d = m.deformation;
      for (std::size_t v = 0; v < d.load.size(); ++v)
        d.impulse[v] += d.load[v] * settings_.time_step;
      d.impulse_time += settings_.time_step;
    }
  const bool elements_moved = integrate_bodies();
  move_walls();
  time_ += settings_.time_step;
  ++steps_;
  if (elements_moved || walls_moved(rebuild_distance())) rebuild();
}

}  // namespace trackbed::dem
