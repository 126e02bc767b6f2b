// Capturing and restoring the complete state of a Simulation (Simulation::engine_state and
// Simulation::restore_engine_state; the history arrays are in contact_history.h), and its HDF5
// form.
#include "dem/io/engine_state.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>

#include "common/input_error.h"
#include "dem/engine/contact_history.h"
#include "dem/engine/value_checks.h"
#include "dem/io/hdf5_io.h"

namespace trackbed::dem {

EngineState Simulation::engine_state() const {
  EngineState s;
  s.particles = p_;
  s.time = time_;
  s.time_step = settings_.time_step;
  s.steps = steps_;
  s.builds = builds_;
  s.gravity = settings_.gravity;
  s.tally = tally_;
  for (const PlaneWall& w : planes_)
    s.planes.push_back({w.name, w.point, w.velocity, w.force, w.moment});
  for (const MeshBody& m : meshes_)
    s.meshes.push_back({m.name, m.x, m.v, m.w, m.q, m.dof, m.contact_force, m.contact_moment,
                        m.contact_stiffness, m.contact_rotational_stiffness, m.part_force,
                        m.part_moment, m.deformable ? m.world.vertices : std::vector<Vec3>{},
                        m.deformation});
  for (const auto& [move, turn] : last_wall_motion_) {
    s.wall_move.push_back(move);
    s.wall_turn.push_back(turn);
  }
  s.list_offsets = list_.offsets;
  s.list_partners = list_.partners;
  s.pair_shear = pair_history_->shear;
  s.pair_roll = pair_history_->roll;
  s.pair_fn = pair_history_->fn;
  for (const WallHistory& h : plane_history_)
    s.walls.push_back(
        {h.element, h.triangle_offsets, h.triangles, h.shear, h.roll, h.normal, h.fn});
  s.pos_at_build = pos_at_build_;
  s.radius_at_build = radius_at_build_;
  s.growth_since_build = growth_since_build_;
  s.wall_point_at_build = plane_point_at_build_;
  s.mesh_q_at_build = mesh_q_at_build_;
  return s;
}

namespace {

[[noreturn]] void mismatch(const std::string& what, const std::string& saved,
                           const std::string& here) {
  throw InputError("the saved state does not fit this model: " + what + " " + saved +
                   " in the saved state, " + here +
                   " in the model; valid: a state saved from a "
                   "model built from the same input");
}

std::string text(std::size_t n) {
  return std::to_string(n);
}

// Indices [0, n) all.
bool indices_below(const std::vector<int>& v, std::size_t n) {
  return std::all_of(v.begin(), v.end(), [n](int i) { return i >= 0 && std::size_t(i) < n; });
}

// Offsets of a CSR list of `rows` rows into `entries` entries.
bool csr(const std::vector<int>& offsets, std::size_t rows, std::size_t entries) {
  return offsets.size() == rows + 1 && offsets.front() == 0 &&
         std::size_t(offsets.back()) == entries && std::is_sorted(offsets.begin(), offsets.end());
}

// The clock, walls and contact springs of a saved state: finite numbers, a positive step, unit
// quaternions (the bodies are Particles::defect's).
bool finite_state(const EngineState& s) {
  const EnergyBudget& e = s.tally;
  if (!std::isfinite(s.time) || !(s.time_step > 0 && s.time_step < 1) || s.steps < 0 ||
      s.builds < 0 || !s.gravity.allFinite() ||
      !all_finite({e.friction, e.rolling, e.dashpot, e.local_damping, e.gravity_work, e.wall_work}))
    return false;
  for (const EngineState::Plane& p : s.planes)
    if (!all_finite({p.point, p.velocity, p.force, p.moment})) return false;
  for (const EngineState::Mesh& m : s.meshes) {
    const MeshDeformation& d = m.deformation;  // a deformable mesh's vertex state
    if (!all_finite(d.velocity) || !all_finite(d.load) || !all_finite(d.impulse) ||
        !std::isfinite(d.impulse_time) || !all_finite(d.at_build) || !all_finite(d.pending_move))
      return false;
    if (!all_finite({m.x, m.v, m.w, m.contact_force, m.contact_moment, m.contact_stiffness,
                     m.contact_rotational_stiffness}) ||
        !unit_norm(m.q) || !all_finite(m.part_force) || !all_finite(m.part_moment) ||
        !all_finite(m.vertices))
      return false;
  }
  for (const EngineState::WallContacts& w : s.walls)
    if (!all_finite(w.shear) || !all_finite(w.roll) || !all_finite(w.normal) || !all_finite(w.fn))
      return false;
  return all_finite(s.pair_shear) && all_finite(s.pair_roll) && all_finite(s.pair_fn) &&
         all_finite(s.wall_move) && all_finite(s.wall_turn) && all_finite(s.pos_at_build) &&
         all_finite(s.radius_at_build) && std::isfinite(s.growth_since_build) &&
         all_finite(s.wall_point_at_build) &&
         std::all_of(s.mesh_q_at_build.begin(), s.mesh_q_at_build.end(),
                     [](const Quat& q) { return unit_norm(q); });
}

}  // namespace

// Whether the saved lists fit the saved bodies and `nwalls` walls (planes first, one slot per
// candidate; then meshes, kSlots per candidate): a damaged file must not index out of bounds.
bool Simulation::consistent_lists(const EngineState& s, std::size_t nwalls) const {
  const auto ne = static_cast<std::size_t>(s.particles.num_elements());
  const std::size_t npairs = s.list_partners.size();
  if (!indices_below(s.particles.body, static_cast<std::size_t>(s.particles.num_bodies())) ||
      !csr(s.list_offsets, ne, npairs) || !indices_below(s.list_partners, ne) ||
      s.pair_shear.size() != npairs || s.pair_fn.size() != npairs ||
      (!s.pair_roll.empty() && s.pair_roll.size() != npairs))
    return false;
  if (s.walls.size() != nwalls || s.wall_move.size() != s.wall_turn.size() ||
      (!s.wall_move.empty() && s.wall_move.size() != nwalls) || s.pos_at_build.size() != ne ||
      s.radius_at_build.size() != ne || s.wall_point_at_build.size() != nwalls ||
      s.mesh_q_at_build.size() != meshes_.size())
    return false;
  for (std::size_t w = 0; w < nwalls; ++w) {
    const EngineState::WallContacts& c = s.walls[w];
    const bool mesh = w >= planes_.size();
    const std::size_t slots = (mesh ? WallHistory::kSlots : 1) * c.element.size();
    if (!indices_below(c.element, ne) || c.shear.size() != slots || c.roll.size() != slots ||
        c.fn.size() != slots || (mesh && c.normal.size() != slots))
      return false;
    if (mesh && (!csr(c.triangle_offsets, c.element.size(), c.triangles.size()) ||
                 !indices_below(c.triangles, meshes_[w - planes_.size()].world.triangles.size())))
      return false;
  }
  return true;
}

void Simulation::restore_engine_state(EngineState s) {
  // The input fixes the walls, meshes and bodies; the state must be of the same model.
  if (s.planes.size() != planes_.size())
    mismatch("plane walls:", text(s.planes.size()), text(planes_.size()));
  for (std::size_t w = 0; w < planes_.size(); ++w)
    if (s.planes[w].name != planes_[w].name)
      mismatch("plane wall " + text(w) + ":", "'" + s.planes[w].name + "'",
               "'" + planes_[w].name + "'");
  if (s.meshes.size() != meshes_.size())
    mismatch("meshes:", text(s.meshes.size()), text(meshes_.size()));
  for (std::size_t m = 0; m < meshes_.size(); ++m) {
    if (s.meshes[m].name != meshes_[m].name ||
        s.meshes[m].part_force.size() != meshes_[m].local.part_names.size())
      mismatch("mesh " + text(m) + ":", "'" + s.meshes[m].name + "'", "'" + meshes_[m].name + "'");
    const std::size_t vertices = meshes_[m].deformable ? meshes_[m].world.vertices.size() : 0;
    if (s.meshes[m].vertices.size() != vertices)
      mismatch("mesh '" + meshes_[m].name + "' deformable vertices:",
               text(s.meshes[m].vertices.size()), text(vertices));
  }
  const Particles& q = s.particles;
  if (q.num_bodies() != p_.num_bodies())
    mismatch("bodies:", text(q.num_bodies()), text(p_.num_bodies()));
  if (q.num_elements() != p_.num_elements())
    mismatch("sphere elements:", text(q.num_elements()), text(p_.num_elements()));
  std::vector<std::int64_t> saved_ids = q.id, ids = p_.id;
  std::sort(saved_ids.begin(), saved_ids.end());
  std::sort(ids.begin(), ids.end());
  const auto differ = std::mismatch(saved_ids.begin(), saved_ids.end(), ids.begin());
  if (differ.first != saved_ids.end())
    mismatch("body ids: the first that differs is", std::to_string(*differ.first),
             std::to_string(*differ.second));
  const std::string defect = q.defect(static_cast<int>(materials_.size()));
  if (!defect.empty())
    throw InputError("the saved state is damaged: " + defect +
                     "; valid: a state saved from a model built from the same input");
  const std::size_t nwalls = planes_.size() + meshes_.size();
  if (!finite_state(s))
    throw InputError(
        "the saved state is damaged: its clock, walls or contact springs hold a value that is "
        "not finite (or a time step, step or build count out of range); valid: a state written "
        "by trackbed");
  if (!consistent_lists(s, nwalls))
    throw InputError(
        "the saved state is inconsistent (its contact lists do not fit its bodies and walls); "
        "valid: a state written by trackbed");
  // Rolling springs exist where a contact the elements can make has rolling resistance. A state
  // saved with springs this model does not need (a build before rolling_in_use, or other
  // materials) drops them: they hold no moment. One without springs that are needed cannot go on.
  const bool rolling = rolling_in_use(s.particles);
  if (!rolling) {
    s.pair_roll.clear();
  } else if (s.pair_roll.size() != s.list_partners.size()) {
    throw InputError(
        "the saved state has no rolling springs and contacts of this model have rolling "
        "resistance; valid: the materials of the saved model");
  }

  p_ = std::move(s.particles);
  time_ = s.time;
  steps_ = s.steps;
  builds_ = s.builds;
  settings_.time_step = s.time_step;
  settings_.gravity = s.gravity;
  tally_ = s.tally;
  for (std::size_t w = 0; w < planes_.size(); ++w) {
    const EngineState::Plane& from = s.planes[w];
    PlaneWall& to = planes_[w];
    to.point = from.point, to.velocity = from.velocity;
    to.force = from.force, to.moment = from.moment;
  }
  for (std::size_t m = 0; m < meshes_.size(); ++m) {
    EngineState::Mesh& from = s.meshes[m];
    MeshBody& to = meshes_[m];
    to.x = from.x, to.v = from.v, to.w = from.w, to.q = from.q, to.dof = from.dof;
    to.contact_force = from.contact_force, to.contact_moment = from.contact_moment;
    to.contact_stiffness = from.contact_stiffness;
    to.contact_rotational_stiffness = from.contact_rotational_stiffness;
    to.part_force = std::move(from.part_force);
    to.part_moment = std::move(from.part_moment);
    if (to.deformable) {
      to.world.vertices = std::move(from.vertices);
      to.deformation = std::move(from.deformation);
    }
    to.update_world_mesh();
  }
  last_wall_motion_.clear();
  for (std::size_t k = 0; k < s.wall_move.size(); ++k)
    last_wall_motion_.emplace_back(s.wall_move[k], s.wall_turn[k]);
  list_.offsets = std::move(s.list_offsets);
  list_.partners = std::move(s.list_partners);
  pair_ranges_.clear();  // made again for the restored list
  pair_history_->shear = std::move(s.pair_shear);
  pair_history_->roll = std::move(s.pair_roll);
  rolling_ = rolling;
  pair_history_->fn = std::move(s.pair_fn);
  plane_history_.assign(nwalls, WallHistory{});
  for (std::size_t w = 0; w < nwalls; ++w) {
    EngineState::WallContacts& from = s.walls[w];
    WallHistory& to = plane_history_[w];
    to.element = std::move(from.element);
    to.triangle_offsets = std::move(from.triangle_offsets);
    to.triangles = std::move(from.triangles);
    to.shear = std::move(from.shear);
    to.roll = std::move(from.roll);
    to.normal = std::move(from.normal);
    to.fn = std::move(from.fn);
  }
  pos_at_build_ = std::move(s.pos_at_build);
  radius_at_build_ = std::move(s.radius_at_build);
  growth_since_build_ = s.growth_since_build;
  plane_point_at_build_ = std::move(s.wall_point_at_build);
  mesh_q_at_build_ = std::move(s.mesh_q_at_build);
  parallel_ = p_.num_elements() >= settings_.parallel_threshold;
  ready_ = true;
}

// ---------------------------------------------------------------------------------------------
// HDF5

namespace {

using hdf5::Handle;

template <class T>
void write_ints(hid_t g, const char* name, const std::vector<T>& v) {
  hdf5::write_integers(g, name, std::vector<std::int64_t>(v.begin(), v.end()));
}

template <class T>
std::vector<T> read_ints(hid_t g, const std::string& file, const char* name, long expected = -1) {
  const auto v = hdf5::read_integers(g, file, name, expected);
  for (std::int64_t i : v)
    if (i < std::numeric_limits<T>::min() || i > std::numeric_limits<T>::max())
      throw InputError(file + ": dataset '" + name + "' holds " + std::to_string(i) +
                       ", beyond its type's range; the file is damaged");
  return std::vector<T>(v.begin(), v.end());
}

// A group per item of a list, named by its index.
std::string item(std::size_t k) {
  return std::to_string(k);
}

void write_particles(hid_t g, const Particles& p) {
  hdf5::write_vectors(g, "x", p.x);
  hdf5::write_vectors(g, "v", p.v);
  hdf5::write_quaternions(g, "q_wxyz", p.q);
  hdf5::write_vectors(g, "w", p.w);
  hdf5::write_vectors(g, "L", p.L);
  hdf5::write_vectors(g, "f", p.f);
  hdf5::write_vectors(g, "t", p.t);
  hdf5::write_doubles(g, "mass", p.mass);
  hdf5::write_vectors(g, "inertia", p.inertia);
  write_ints(g, "body_material", p.body_material);
  write_ints(g, "first_element", p.first_element);
  write_ints(g, "id", p.id);
  write_ints(g, "is_clump", p.is_clump);
  hdf5::write_vectors(g, "pos", p.pos);
  hdf5::write_vectors(g, "offset", p.offset);
  hdf5::write_doubles(g, "radius", p.radius);
  write_ints(g, "body", p.body);
  write_ints(g, "material", p.material);
}

Particles read_particles(hid_t g, const std::string& file) {
  Particles p;
  p.x = hdf5::read_vectors(g, file, "x");
  const long nb = static_cast<long>(p.x.size());
  p.v = hdf5::read_vectors(g, file, "v", nb);
  p.q = hdf5::read_quaternions(g, file, "q_wxyz", nb);
  p.w = hdf5::read_vectors(g, file, "w", nb);
  p.L = hdf5::read_vectors(g, file, "L", nb);
  p.f = hdf5::read_vectors(g, file, "f", nb);
  p.t = hdf5::read_vectors(g, file, "t", nb);
  p.mass = hdf5::read_doubles(g, file, "mass", nb);
  p.inertia = hdf5::read_vectors(g, file, "inertia", nb);
  p.body_material = read_ints<int>(g, file, "body_material", nb);
  p.first_element = read_ints<int>(g, file, "first_element", nb + 1);
  p.id = read_ints<std::int64_t>(g, file, "id", nb);
  p.is_clump = read_ints<std::uint8_t>(g, file, "is_clump", nb);
  p.pos = hdf5::read_vectors(g, file, "pos");
  const long ne = static_cast<long>(p.pos.size());
  p.offset = hdf5::read_vectors(g, file, "offset", ne);
  p.radius = hdf5::read_doubles(g, file, "radius", ne);
  p.body = read_ints<int>(g, file, "body", ne);
  p.material = read_ints<int>(g, file, "material", ne);
  if (p.first_element.front() != 0 || p.first_element.back() != ne ||
      !std::is_sorted(p.first_element.begin(), p.first_element.end()))
    throw InputError(file + ": particles/first_element does not split the " + std::to_string(ne) +
                     " elements among the bodies; the file is damaged");
  return p;
}

// A DOF control as 5 numbers: mode, value, gain, max_speed, relaxation.
std::vector<double> dof_numbers(const std::array<DofControl, 6>& dof) {
  std::vector<double> out;
  for (const DofControl& c : dof)
    out.insert(out.end(),
               {double(static_cast<int>(c.mode)), c.value, c.gain, c.max_speed, c.relaxation});
  return out;
}

std::array<DofControl, 6> dof_controls(const std::vector<double>& v, const std::string& file) {
  std::array<DofControl, 6> dof;
  for (int k = 0; k < 6; ++k) {
    const double mode = v[5 * k];
    if (!(mode >= 0 && mode <= static_cast<int>(DofMode::servo)) || mode != int(mode))
      throw InputError(file + ": a mesh's dof mode is " + std::to_string(mode) +
                       "; the file is damaged");
    dof[k] = {static_cast<DofMode>(int(mode)), v[5 * k + 1], v[5 * k + 2], v[5 * k + 3],
              v[5 * k + 4]};
    if (!std::all_of(v.begin() + 5 * k + 1, v.begin() + 5 * k + 5,
                     [](double a) { return std::isfinite(a) && a > -1e300; }) ||
        dof[k].gain < 0 || dof[k].max_speed < 0 || dof[k].relaxation < 0)
      throw InputError(file +
                       ": a mesh's dof control holds a value out of range (not finite, "
                       "or a negative gain, speed limit or relaxation); the file is damaged");
  }
  return dof;
}

}  // namespace

void write_engine_state(hid_t group, const EngineState& s) {
  hdf5::write_doubles(group, "clock", {s.time, double(s.steps), s.time_step, double(s.builds)});
  hdf5::write_vectors(group, "gravity", {s.gravity});
  const EnergyBudget& e = s.tally;
  hdf5::write_doubles(
      group, "tally",
      {e.friction, e.rolling, e.dashpot, e.local_damping, e.gravity_work, e.wall_work});
  {
    Handle g(hdf5::create_group(group, "particles"), H5Gclose, "group particles");
    write_particles(g, s.particles);
  }
  {
    Handle g(hdf5::create_group(group, "planes"), H5Gclose, "group planes");
    std::vector<std::string> names;
    std::vector<Vec3> point, velocity, force, moment;
    for (const auto& w : s.planes) {
      names.push_back(w.name), point.push_back(w.point), velocity.push_back(w.velocity);
      force.push_back(w.force), moment.push_back(w.moment);
    }
    hdf5::write_strings(g, "names", names);
    hdf5::write_vectors(g, "point", point);
    hdf5::write_vectors(g, "velocity", velocity);
    hdf5::write_vectors(g, "force", force);
    hdf5::write_vectors(g, "moment", moment);
  }
  {
    Handle g(hdf5::create_group(group, "meshes"), H5Gclose, "group meshes");
    hdf5::write_string_attribute(g, "count", std::to_string(s.meshes.size()));
    for (std::size_t k = 0; k < s.meshes.size(); ++k) {
      const EngineState::Mesh& m = s.meshes[k];
      Handle mg(hdf5::create_group(g, item(k).c_str()), H5Gclose, "group mesh");
      hdf5::write_string_attribute(mg, "name", m.name);
      hdf5::write_vectors(mg, "x_v_w", {m.x, m.v, m.w});
      hdf5::write_quaternions(mg, "q_wxyz", {m.q});
      hdf5::write_doubles(mg, "dof", dof_numbers(m.dof));
      hdf5::write_vectors(
          mg, "loads",
          {m.contact_force, m.contact_moment, m.contact_stiffness, m.contact_rotational_stiffness});
      hdf5::write_vectors(mg, "part_force", m.part_force);
      hdf5::write_vectors(mg, "part_moment", m.part_moment);
      if (!m.vertices.empty()) {
        const MeshDeformation& d = m.deformation;
        hdf5::write_vectors(mg, "vertices", m.vertices);
        hdf5::write_vectors(mg, "vertex_velocity", d.velocity);
        hdf5::write_vectors(mg, "vertex_load", d.load);
        hdf5::write_vectors(mg, "vertex_impulse", d.impulse);
        hdf5::write_doubles(mg, "impulse_time", std::vector<double>{d.impulse_time});
        hdf5::write_vectors(mg, "vertex_at_build", d.at_build);
        hdf5::write_vectors(mg, "vertex_pending_move", d.pending_move);
      }
    }
  }
  hdf5::write_vectors(group, "wall_move", s.wall_move);
  hdf5::write_vectors(group, "wall_turn", s.wall_turn);
  {
    Handle g(hdf5::create_group(group, "pairs"), H5Gclose, "group pairs");
    write_ints(g, "offsets", s.list_offsets);
    write_ints(g, "partners", s.list_partners);
    hdf5::write_vectors(g, "shear", s.pair_shear);
    hdf5::write_vectors(g, "roll", s.pair_roll);
    hdf5::write_doubles(g, "fn", s.pair_fn);
  }
  {
    Handle g(hdf5::create_group(group, "walls"), H5Gclose, "group walls");
    hdf5::write_string_attribute(g, "count", std::to_string(s.walls.size()));
    for (std::size_t k = 0; k < s.walls.size(); ++k) {
      const EngineState::WallContacts& w = s.walls[k];
      Handle wg(hdf5::create_group(g, item(k).c_str()), H5Gclose, "group wall");
      write_ints(wg, "element", w.element);
      write_ints(wg, "triangle_offsets", w.triangle_offsets);
      write_ints(wg, "triangles", w.triangles);
      hdf5::write_vectors(wg, "shear", w.shear);
      hdf5::write_vectors(wg, "roll", w.roll);
      hdf5::write_vectors(wg, "normal", w.normal);
      hdf5::write_doubles(wg, "fn", w.fn);
    }
  }
  {
    Handle g(hdf5::create_group(group, "at_build"), H5Gclose, "group at_build");
    hdf5::write_vectors(g, "pos", s.pos_at_build);
    hdf5::write_doubles(g, "radius", s.radius_at_build);
    hdf5::write_doubles(g, "growth", {s.growth_since_build});
    hdf5::write_vectors(g, "wall_point", s.wall_point_at_build);
    hdf5::write_quaternions(g, "mesh_q_wxyz", s.mesh_q_at_build);
  }
}

namespace {

// A count written as an attribute (the number of item groups).
std::size_t count_of(hid_t g, const std::string& file) {
  return static_cast<std::size_t>(hdf5::read_integer_attribute(g, file, "count", 0, 1 << 20));
}

}  // namespace

EngineState read_engine_state(hid_t group, const std::string& file) {
  EngineState s;
  const auto clock = hdf5::read_doubles(group, file, "clock", 4);
  s.time = clock[0], s.steps = static_cast<long>(clock[1]), s.time_step = clock[2];
  s.builds = static_cast<int>(clock[3]);
  s.gravity = hdf5::read_vectors(group, file, "gravity", 1).front();
  const auto t = hdf5::read_doubles(group, file, "tally", 6);
  s.tally.friction = t[0], s.tally.rolling = t[1], s.tally.dashpot = t[2];
  s.tally.local_damping = t[3], s.tally.gravity_work = t[4], s.tally.wall_work = t[5];
  {
    Handle g(hdf5::open_group(group, file, "particles"), H5Gclose, "group particles");
    s.particles = read_particles(g, file);
  }
  {
    Handle g(hdf5::open_group(group, file, "planes"), H5Gclose, "group planes");
    const auto names = hdf5::read_strings(g, file, "names");
    const long n = static_cast<long>(names.size());
    const auto point = hdf5::read_vectors(g, file, "point", n);
    const auto velocity = hdf5::read_vectors(g, file, "velocity", n);
    const auto force = hdf5::read_vectors(g, file, "force", n);
    const auto moment = hdf5::read_vectors(g, file, "moment", n);
    for (long k = 0; k < n; ++k)
      s.planes.push_back({names[k], point[k], velocity[k], force[k], moment[k]});
  }
  {
    Handle g(hdf5::open_group(group, file, "meshes"), H5Gclose, "group meshes");
    const std::size_t n = count_of(g, file);
    for (std::size_t k = 0; k < n; ++k) {
      Handle mg(hdf5::open_group(g, file, item(k).c_str()), H5Gclose, "group mesh");
      EngineState::Mesh m;
      m.name = hdf5::read_string_attribute(mg, file, "name");
      const auto xvw = hdf5::read_vectors(mg, file, "x_v_w", 3);
      m.x = xvw[0], m.v = xvw[1], m.w = xvw[2];
      m.q = hdf5::read_quaternions(mg, file, "q_wxyz", 1).front();
      m.dof = dof_controls(hdf5::read_doubles(mg, file, "dof", 30), file);
      const auto loads = hdf5::read_vectors(mg, file, "loads", 4);
      m.contact_force = loads[0], m.contact_moment = loads[1];
      m.contact_stiffness = loads[2], m.contact_rotational_stiffness = loads[3];
      m.part_force = hdf5::read_vectors(mg, file, "part_force");
      m.part_moment =
          hdf5::read_vectors(mg, file, "part_moment", static_cast<long>(m.part_force.size()));
      if (hdf5::exists(mg, "vertices")) {
        m.vertices = hdf5::read_vectors(mg, file, "vertices");
        const long n = static_cast<long>(m.vertices.size());
        MeshDeformation& d = m.deformation;
        d.velocity = hdf5::read_vectors(mg, file, "vertex_velocity", n);
        d.load = hdf5::read_vectors(mg, file, "vertex_load", n);
        d.impulse = hdf5::read_vectors(mg, file, "vertex_impulse", n);
        d.impulse_time = hdf5::read_doubles(mg, file, "impulse_time", 1).front();
        d.at_build = hdf5::read_vectors(mg, file, "vertex_at_build", n);
        d.pending_move = hdf5::read_vectors(mg, file, "vertex_pending_move", n);
      }
      s.meshes.push_back(std::move(m));
    }
  }
  s.wall_move = hdf5::read_vectors(group, file, "wall_move");
  s.wall_turn = hdf5::read_vectors(group, file, "wall_turn", long(s.wall_move.size()));
  {
    Handle g(hdf5::open_group(group, file, "pairs"), H5Gclose, "group pairs");
    s.list_offsets = read_ints<int>(g, file, "offsets");
    s.list_partners = read_ints<int>(g, file, "partners");
    s.pair_shear = hdf5::read_vectors(g, file, "shear");
    s.pair_roll = hdf5::read_vectors(g, file, "roll");
    s.pair_fn = hdf5::read_doubles(g, file, "fn");
  }
  {
    Handle g(hdf5::open_group(group, file, "walls"), H5Gclose, "group walls");
    const std::size_t n = count_of(g, file);
    for (std::size_t k = 0; k < n; ++k) {
      Handle wg(hdf5::open_group(g, file, item(k).c_str()), H5Gclose, "group wall");
      EngineState::WallContacts w;
      w.element = read_ints<int>(wg, file, "element");
      w.triangle_offsets = read_ints<int>(wg, file, "triangle_offsets");
      w.triangles = read_ints<int>(wg, file, "triangles");
      w.shear = hdf5::read_vectors(wg, file, "shear");
      w.roll = hdf5::read_vectors(wg, file, "roll", long(w.shear.size()));
      w.normal = hdf5::read_vectors(wg, file, "normal");
      w.fn = hdf5::read_doubles(wg, file, "fn", long(w.shear.size()));
      s.walls.push_back(std::move(w));
    }
  }
  {
    Handle g(hdf5::open_group(group, file, "at_build"), H5Gclose, "group at_build");
    s.pos_at_build = hdf5::read_vectors(g, file, "pos");
    s.radius_at_build = hdf5::read_doubles(g, file, "radius");
    s.growth_since_build = hdf5::read_doubles(g, file, "growth", 1).front();
    s.wall_point_at_build = hdf5::read_vectors(g, file, "wall_point");
    s.mesh_q_at_build = hdf5::read_quaternions(g, file, "mesh_q_wxyz");
  }
  return s;
}

}  // namespace trackbed::dem
