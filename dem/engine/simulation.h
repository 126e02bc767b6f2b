// The DEM engine: one class that owns particles, walls and contacts and advances them in time.
//
//   run():  repeat step():
//             compute_forces()     contacts (pairs, planes, meshes)
//             integrate_bodies()   gravity, local damping, leapfrog for bodies, element positions
//             move_walls()         wall and mesh motion
//             rebuild if some element or wall moved more than skin/2
//
// The time integration is the central-difference (leapfrog) scheme of PFC: velocities live at
// half steps, positions at full steps. See docs/theory.md.
#pragma once

#include <omp.h>

#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "dem/engine/contact_law.h"
#include "dem/engine/contact_state.h"
#include "dem/engine/material.h"
#include "dem/engine/mesh_body.h"
#include "dem/engine/mesh_contact.h"
#include "dem/engine/neighbor_list.h"
#include "dem/engine/particles.h"
#include "dem/engine/plane_wall.h"

namespace trackbed::dem {

struct EngineState;

struct SimulationSettings {
  double time_step = 1e-5;  // s; 0: critical_fraction * the critical timestep at setup
  double critical_fraction = 0.2;
  Vec3 gravity = Vec3(0, 0, -9.81);
  double skin = 0.004;             // Verlet skin, m
  bool track_energy = true;        // tally dissipation every step (costs ~10 % of a step)
  double max_overlap_ratio = 0.5;  // runaway: overlap above this fraction of the smaller radius
  double max_energy_error = 0.1;   // blow-up: energy balance error above this (check_energy)
  double initial_overlap_ratio = 0.05;  // setup: tolerated overlap as a fraction of the radius
  bool allow_supercritical_step = false;
  bool spatial_sort = true;  // reorder bodies along a Morton curve at setup (cache locality)
  // Models with fewer sphere elements run on one thread: their steps are too short to pay for
  // a step's two parallel regions, and on a loaded machine each barrier can cost a whole
  // scheduler time slice. Two threads broke even near 500 balls and were 1.4 times as fast at
  // 1,700-2,800 (docs/benchmarks.md, "Threads on a small model").
  int parallel_threshold = 1000;
};

// Energy bookkeeping (J). With no numerical error
//   kinetic + strain + dissipated() - gravity_work - wall_work = initial kinetic + initial strain.
struct EnergyBudget {
  double kinetic = 0, strain = 0;
  double friction = 0, rolling = 0, dashpot = 0, local_damping = 0;
  double gravity_work = 0, wall_work = 0;
  double dissipated() const { return friction + rolling + dashpot + local_damping; }
  double total() const { return kinetic + strain + dissipated() - gravity_work - wall_work; }
  // The change of total() since `initial` over the largest term, max(|E_k| + E_s, D, |W_g|,
  // |W_w|, initial E_k + E_s): a relative error that a model at rest does not divide by ~0.
  double balance_error(const EnergyBudget& initial) const;
};

// One active contact, for output (force chains) and statistics.
struct ContactRecord {
  int element_i;  // -1 for a wall
  int element_j;
  int wall = -1;  // plane index, or planes + mesh index; -1 for particle-particle
  Vec3 point;
  Vec3 force;     // on j
  int part = -1;  // a mesh contact: the mesh part (part_names) of the triangle it touches
};

class Simulation {
 public:
  Simulation(MaterialTable materials, Particles particles, SimulationSettings settings);
  ~Simulation();
  Simulation(Simulation&&) noexcept;
  Simulation& operator=(Simulation&&) noexcept;

  int add_plane(const PlaneWall& wall);
  int add_mesh_body(MeshBody body);

  // Builds contacts and checks the start: overlaps, timestep against the critical one.
  void setup();
  bool is_set_up() const { return ready_; }
  void step();
  // After the caller edited the particles' geometry or mass between steps (element offsets and
  // radii, masses, inertia, bodies moved): recomputes the element positions and rebuilds the
  // contact lists if the motion plus the growth of radii since the last build exceed half the
  // skin, keeping the springs of the pairs that stay in the lists.
  void particles_changed();
  // Replaces the material table (same number of materials, e.g. another friction for a stage of
  // a sample build); the contact springs are kept.
  void set_materials(MaterialTable materials);
  // The springs of the live contacts, keyed by body id (see contact_state.h), and their
  // restoration into a model set up from the same bodies in any order (after setup()).
  // Restoring returns the number of contacts that found their pair in the current lists.
  ContactState contact_state() const;
  int restore_contact_state(const ContactState& state);

  double time() const { return time_; }
  long step_count() const { return steps_; }
  double time_step() const { return settings_.time_step; }
  // Changes gravity between steps (e.g. off while clumps grow in a bed).
  void set_gravity(const Vec3& g) { settings_.gravity = g; }
  // Changes the step between steps (a stage of a build with other contacts). Throws InputError
  // above the critical step, unless the settings allow it, like setup().
  void set_time_step(double dt);
  const SimulationSettings& settings() const { return settings_; }
  const MaterialTable& materials() const { return materials_; }
  const Particles& particles() const { return p_; }
  Particles& particles() { return p_; }
  const std::vector<PlaneWall>& planes() const { return planes_; }
  std::vector<PlaneWall>& planes() { return planes_; }
  const std::vector<MeshBody>& meshes() const { return meshes_; }
  std::vector<MeshBody>& meshes() { return meshes_; }
  // The index of the mesh body of that name in meshes(), or -1.
  int mesh_index(const std::string& name) const;
  // Between steps: new world positions and velocities of every vertex of deformable mesh `mesh`
  // (MeshBody::make_deformable). The vertices then move by these velocities each step until set
  // again; a change of position here is a wall motion whose work enters the energy ledger.
  // Throws std::invalid_argument for a mesh that is not deformable or sizes that differ from its
  // vertex count, std::runtime_error for a non-finite value.
  void set_mesh_vertices(int mesh, const std::vector<Vec3>& positions,
                         const std::vector<Vec3>& velocities);

  // PFC's estimate: min over bodies and degrees of freedom of sqrt(m/k) and sqrt(I/k_rot) with
  // the stiffness summed over the body's current contacts (a body with none: one contact), each
  // shortened by the factor sqrt(1 + zeta^2) - zeta of the dashpots summed alike (half the
  // damped limit, as sqrt(m/k) is half the undamped one; docs/theory.md, "Dashpots"), with the
  // scaled mass and inertia while density scaling is on.
  double critical_timestep() const;
  // Density scaling (PFC's, for quasi-static runs; docs/theory.md, "Density scaling"): the mass
  // and inertia with which every body accelerates become s_b times its own, with s_b the smallest
  // factor >= 1 that makes `dt` at most `fraction` of the body's critical step with its current
  // contacts (`within_skin`: with every element pair of the neighbour list as if touching, the
  // contacts it may make before the list is built again); then the step is set to `dt`. Gravity
  // and the unbalanced force ratio keep the true masses, so a static equilibrium is that of the
  // unscaled model; the motion towards it is not physical, nor is the energy budget. Call again
  // as contacts change; end_density_scaling() returns to the true inertia. Returns the largest
  // factor.
  double scale_density_for_step(double dt, double fraction, bool within_skin = false);
  void end_density_scaling() { inertia_scale_.clear(); }
  bool density_scaled() const { return !inertia_scale_.empty(); }
  EnergyBudget energy() const;
  int num_contacts() const;  // touching pairs and wall contacts of the last step
  int num_neighbor_builds() const { return builds_; }
  // Threads this model runs on (1 below settings().parallel_threshold elements).
  int team_size() const { return parallel_ ? omp_get_max_threads() : 1; }
  void for_each_contact(const std::function<void(const ContactRecord&)>& f) const;
  // Largest contact force magnitude sqrt(F_n^2 + |F_s|^2) of the last step between particles
  // and against walls/meshes, N.
  double max_particle_contact_force() const;
  double max_wall_contact_force() const;
  // PFC's mean unbalanced force ratio over the particles, after a step: the mean over bodies of
  // |sum of contact forces + weight| over the mean of (sum of the contact force magnitudes +
  // |weight|). 0 for a model in exact static equilibrium; of order 1 in free flight. Bodies with
  // no contact and no weight count as balanced.
  double unbalanced_force_ratio() const;
  // Checks the state for NaN; throws a std::runtime_error naming the first bad body. Every step
  // calls it when a body's velocity has become non-finite.
  void check_finite() const;
  // Stops a model that has blown up: throws std::runtime_error, one line naming the step and the
  // fastest body, when the energy balance since `initial` (EnergyBudget::balance_error) has risen
  // above settings().max_energy_error: energy that no work put in. Only a rise counts: the
  // balance falls where dissipation is not tallied (without energy tracking) and, by the
  // leapfrog's half-step velocities, in free fall (-1/(n+1) after n steps from rest)
  // (docs/theory.md, "Runaway detection"). Costs one pass over the contacts (energy()).
  void check_energy(const EnergyBudget& initial) const { check_energy(initial, energy()); }
  // The same with `now`, energy() of the present state, computed already.
  void check_energy(const EnergyBudget& initial, const EnergyBudget& now) const;

  // Sets the clock (a snapshot being read back; contact springs are not part of a snapshot).
  void set_time(double t, long steps) { time_ = t, steps_ = steps; }

  // The complete state of the set-up model (a checkpoint, engine_state.h), and its restoration
  // into a model built from the same input, in place of setup(): the same walls and meshes by
  // name, the same bodies by id. The model then steps on bit for bit as the saved one (same number
  // of threads). Throws InputError naming what does not match.
  EngineState engine_state() const;
  void restore_engine_state(EngineState state);

 private:
  struct PairHistory;
  struct WallHistory;
  struct ThreadScratch;

  // The force pass (compute_forces): called by every thread of its parallel region, each
  // running its share of the loops into its own scratch.
  template <bool Rolling, bool Energy>
  void contact_forces(ThreadScratch& s);
  template <bool Rolling, bool Energy>
  void pair_forces(ThreadScratch& s);
  template <bool Rolling, bool Energy>
  void plane_forces(ThreadScratch& s);
  template <bool Rolling, bool Energy>
  void mesh_forces(ThreadScratch& s);
  // Where this thread adds body forces and moments (see ThreadScratch).
  std::pair<Vec3*, Vec3*> body_load_arrays(ThreadScratch& s);
  void clear_thread_loads(ThreadScratch& s);
  // Inside the region: the other threads' body loads added to the bodies', body by body.
  void add_thread_body_loads();
  // After it: the walls' loads, the dissipation and the runaway check, in thread order.
  void reduce_thread_wall_loads();
  void compute_forces();
  // Moves the bodies and their elements one step; returns whether an element moved farther than
  // rebuild_distance() since the last neighbour build.
  bool integrate_bodies();
  // Each thread's bodies in integrate_bodies: `parts` contiguous shares of about equal work
  // (a clump's rotation and its elements weigh more than a ball).
  std::vector<int> body_work_ranges(int parts) const;
  void move_walls();
  // A deformable mesh's step: each vertex moved by its velocity, the motion's first-half work.
  void move_deformable_mesh(MeshBody& m, double dt);
  // The second half of the work of the walls' last motion with their current loads, -(F . d +
  // M . theta) / 2 summed over the walls (move_walls, trapezoidal rule).
  double closing_wall_work() const;
  // How far an element or wall may move before the neighbour lists must be rebuilt: half the
  // skin, less the growth of the radii since the last build.
  double rebuild_distance() const;
  bool needs_rebuild() const;
  // Whether element e has moved more than sqrt(squared_distance) since the last build.
  bool moved_farther_than(int e, double squared_distance) const {
    return (p_.pos[e] - pos_at_build_[e]).squaredNorm() > squared_distance;
  }
  bool walls_moved(double distance) const;
  void rebuild();
  // Whether a contact these particles can make (element-element, element-wall) has rolling
  // resistance: only then are rolling springs kept and the rolling kernels run.
  bool rolling_in_use(const Particles& p) const;
  void check_initial_overlaps() const;
  // The contact points of candidate `c` of mesh `m`'s history with that mesh at the current
  // positions, in the order mesh_forces stores them.
  void mesh_points_now(std::size_t m, std::size_t c, std::vector<MeshContactPoint>& points) const;
  // Calls visit(mesh, candidate, element, point, slot) for every particle-mesh contact at the
  // current positions, in the order mesh_forces stores them (slot = index among the element's
  // contacts with that mesh, the history slot).
  template <class Visitor>
  void visit_mesh_contacts(Visitor&& visit) const;
  // Per body, the smallest of sqrt(m/k) and sqrt(I/k_rot) over its degrees of freedom, shortened
  // by its dashpots, with its true mass and inertia (critical_timestep()).
  std::vector<double> body_critical_steps(bool within_skin = false) const;
  double inertia_scale(int b) const { return inertia_scale_.empty() ? 1.0 : inertia_scale_[b]; }
  [[noreturn]] void runaway(int ei, int ej, double ratio, const std::string& other) const;
  bool consistent_lists(const EngineState& s, std::size_t nwalls) const;

  MaterialTable materials_;
  Particles p_;
  SimulationSettings settings_;
  std::vector<PlaneWall> planes_;
  std::vector<MeshBody> meshes_;

  NeighborList list_;
  // Each thread's rows of the list in the force pass (NeighborList::balanced_ranges); emptied
  // when the list changes (rebuild, restore) and made again by the next force pass.
  std::vector<int> pair_ranges_;
  std::vector<int> body_ranges_;  // each thread's bodies in integrate_bodies (body_work_ranges)
  std::unique_ptr<PairHistory> pair_history_;
  std::vector<WallHistory> plane_history_;
  std::vector<Vec3> pos_at_build_;
  std::vector<double> radius_at_build_;
  std::vector<double> inertia_scale_;  // per body, density scaling; empty: none
  double growth_since_build_ = 0;  // largest radius growth since the last build (particles_changed)
  std::vector<Vec3> plane_point_at_build_;  // planes, then mesh reference points
  std::vector<Quat> mesh_q_at_build_;
  std::unique_ptr<std::vector<ThreadScratch>> scratch_;

  double time_ = 0;
  long steps_ = 0;
  int builds_ = 0;
  bool ready_ = false;
  bool parallel_ = true;  // OpenMP team for this model (see parallel_threshold)
  bool rolling_ = false;  // rolling springs kept (rolling_in_use at the last list build)
  EnergyBudget tally_;    // dissipation and work terms accumulated so far
  // Each wall's (planes, then meshes) displacement and rotation of the last step, whose work
  // move_walls completes with the next step's forces.
  std::vector<std::pair<Vec3, Vec3>> last_wall_motion_;
};

}  // namespace trackbed::dem
