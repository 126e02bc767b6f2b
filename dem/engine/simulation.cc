#include "dem/engine/simulation.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "common/input_error.h"
#include "dem/engine/contact_history.h"
#include "dem/engine/simulation_internals.h"
#include "dem/engine/triangle_grid.h"
#include "dem/engine/work_split.h"

namespace trackbed::dem {

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
  check_range("simulation: energy error limit", settings_.max_energy_error, 1e-6, 1.0);
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
  for (auto& m : meshes_)
    if (m.deformable) m.deformation.at_build = m.world.vertices;
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
    if (b.deformable) {
      for (std::size_t v = 0; v < b.world.vertices.size(); ++v)
        if ((b.world.vertices[v] - b.deformation.at_build[v]).squaredNorm() > half * half)
          return true;
      continue;
    }
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

}  // namespace trackbed::dem
