#include "dem/samples/section_model.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <sstream>
#include <stdexcept>

#include "common/input_error.h"
#include "common/number_text.h"
#include "dem/engine/triangle_mesh.h"
#include "dem/samples/zone.h"

namespace trackbed::dem {

SectionMaterials::SectionMaterials() {
  // Jia, Markine and Guo (2023), Table 2: ballast-ballast contacts 2e7 N/m (entity 4e7 in series,
  // docs/theory.md section 3), friction 0.5, local damping 0.7; the sleeper 5e9 N/m.
  ballast.name = "ballast";
  ballast.density = 2800;
  ballast.normal_stiffness = ballast.shear_stiffness = 4e7;
  ballast.friction = 0.5;
  ballast.rolling_friction = 0.3;
  ballast.local_damping = 0.7;
  sleeper.name = "sleeper";
  sleeper.density = 2500;
  sleeper.normal_stiffness = sleeper.shear_stiffness = 5e9;
  sleeper.friction = 0.5;
  wall.name = "wall";
  wall.normal_stiffness = wall.shear_stiffness = 4e7;
  wall.friction = 0;
}

SectionModel::SectionModel(TrackSection section, SectionMaterials materials,
                           SimulationSettings settings, double preparation_damping)
    : section_(section),
      materials_(std::move(materials)),
      settings_(settings),
      preparation_damping_(preparation_damping) {
  check_range("build: preparation damping ratio", preparation_damping, 0, 1);
}

MaterialTable SectionModel::material_table(const StageMaterials& stage) const {
  Material ballast = materials_.ballast;
  ballast.friction *= stage.friction_factor;
  ballast.rolling_friction *= stage.rolling_factor;
  if (stage.local_damping) ballast.local_damping = *stage.local_damping;
  ballast.normal_damping_ratio = preparation_damping_;
  MaterialTable t;
  t.add(ballast);
  t.add(materials_.sleeper);
  t.add(materials_.wall);
  if (stage.clump_material) {
    Material clump = ballast;
    clump.name = kClumpMaterialName;
    if (!stage.clump_rolling) clump.rolling_friction = 0;
    t.add(clump);
  }
  return t;
}

int SectionModel::clump_material() const {
  StageMaterials stage;
  stage.clump_material = true;
  return material_table(stage).index_of(kClumpMaterialName);
}

namespace {

PlaneWall plane(const std::string& name, const Vec3& point, const Vec3& normal, int material) {
  PlaneWall w;
  w.name = name;
  w.point = point;
  w.normal = normal;
  w.material = material;
  return w;
}

}  // namespace

Simulation SectionModel::make(Particles particles, const StageWalls& walls,
                              const StageMaterials& stage,
                              const std::optional<MeshBody>& sleeper_body) const {
  Simulation sim(material_table(stage), std::move(particles), settings_);
  const TrackSection& s = section_;
  sim.add_plane(plane("base", Vec3::Zero(), Vec3::UnitZ(), 0));
  if (!s.periodic) {
    sim.add_plane(plane("crib_front", Vec3(0, -0.5 * s.length, 0), Vec3::UnitY(), 2));
    sim.add_plane(plane("crib_back", Vec3(0, 0.5 * s.length, 0), -Vec3::UnitY(), 2));
  }
  // A box's side walls stand at every stage; a section's mould walls (at the foot of the slopes)
  // only while the bed is deposited.
  if (s.side_walls) {
    sim.add_plane(plane("side_left", Vec3(-s.half_base_width(), 0, 0), Vec3::UnitX(), 2));
    sim.add_plane(plane("side_right", Vec3(s.half_base_width(), 0, 0), -Vec3::UnitX(), 2));
  } else if (walls.mould) {
    sim.add_plane(plane("mould_left", Vec3(-s.half_base_width(), 0, 0), Vec3::UnitX(), 2));
    sim.add_plane(plane("mould_right", Vec3(s.half_base_width(), 0, 0), -Vec3::UnitX(), 2));
  }
  if (walls.sleeper) {
    MeshBody body;
    body = sleeper_body ? *sleeper_body : sleeper_at(sleeper_lift(sim.particles(), s));
    body.material = 1;
    body.weight = true;
    for (auto& d : body.dof) d = DofControl{};
    DofControl& z = body.dof[2];
    z.mode = DofMode::servo;
    z.value = body.mass * settings_.gravity.z();  // the weight, downward
    // A slow servo: its automatic gain assumes the contacts respond within a step, but the
    // stones under a sleeper respond over several, and a relaxation of 0.5 locks the servo into a
    // two-step oscillation at its speed limit that keeps the bed shaking. With 0.01 the force
    // error decays over about a hundred steps, smoothly.
    z.relaxation = 0.01;
    z.max_speed = 0.02;
    sim.add_mesh_body(std::move(body));
  }
  return sim;
}

MeshBody SectionModel::sleeper_at(double lift) const {
  const TrackSection& s = section_;
  const Vec3 up(0, 0, lift);
  const TriangleMesh box = make_box_mesh(
      Vec3(s.sleeper_lower().x(), -0.5 * s.sleeper_width, s.depth_under_sleeper) + up,
      Vec3(s.sleeper_upper().x(), 0.5 * s.sleeper_width, s.crest_z()) + up, true, s.bottom_width());
  MeshBody body = MeshBody::from_world_mesh(kSleeperName, box, 1, 1.0, Vec3::Zero());
  // The box's own inertia distribution, scaled to the sleeper's mass.
  body.inertia *= s.sleeper_mass / body.mass;
  body.mass = s.sleeper_mass;
  return body;
}

int SectionModel::permanent_walls() const {
  return 1 + (section_.periodic ? 0 : 2) + (section_.side_walls ? 2 : 0);
}

namespace {

template <class Sim>
auto sleeper_of(Sim& sim) -> decltype(&sim.meshes().front()) {
  const int k = sim.mesh_index(SectionModel::kSleeperName);
  return k < 0 ? nullptr : &sim.meshes()[k];
}

// The sleeper's load and position since the last judgement.
struct SeatingInterval {
  double load_sum = 0;
  long steps = 0;
  Vec3 start = Vec3::Constant(NAN);
  double start_time = NAN;
};

}  // namespace

void SectionModel::require_seated_sleeper(SettleCriterion& c, double max_speed) const {
  auto interval = std::make_shared<SeatingInterval>();
  c.each_step = [interval](const Simulation& sim) {
    const MeshBody* m = sleeper_of(sim);
    if (!m) return;
    if (std::isnan(interval->start_time)) {
      interval->start = m->x;
      interval->start_time = sim.time();
    }
    interval->load_sum += m->contact_force.z();
    ++interval->steps;
  };
  c.also = [interval, max_speed](const Simulation& sim) {
    const MeshBody* m = sleeper_of(sim);
    if (!m) return true;
    const SeatingInterval i = *interval;
    *interval = SeatingInterval{};
    if (i.steps < 2) return false;
    const double held = -m->dof[2].value;  // what the servo holds: the weight, or a tamping load
    const double mean_load = i.load_sum / i.steps;
    const double mean_speed = (m->x - i.start).norm() / (sim.time() - i.start_time);
    return std::abs(mean_load - held) <= 0.01 * std::abs(held) && mean_speed < max_speed;
  };
  c.memory = [interval] {
    const SeatingInterval& i = *interval;
    return std::vector<double>{i.load_sum,  double(i.steps), i.start.x(),
                               i.start.y(), i.start.z(),     i.start_time};
  };
  c.restore_memory = [interval](const std::vector<double>& v) {
    if (v.size() != 6)
      throw InputError("the saved seating interval has " + std::to_string(v.size()) +
                       " numbers; valid: 6 (a checkpoint written by this version)");
    // An interval not begun: no steps, no load, its start NaN; one begun: every number finite,
    // its steps a count.
    const bool begun = !std::isnan(v[5]);
    const bool finite = std::all_of(v.begin(), v.end(), [](double a) { return std::isfinite(a); });
    const bool ok =
        begun ? finite && v[1] >= 0 && v[1] <= 1e15 && v[1] == std::floor(v[1])
              : v[0] == 0 && v[1] == 0 && std::isnan(v[2]) && std::isnan(v[3]) && std::isnan(v[4]);
    if (!ok) throw InputError("the saved seating interval holds a value out of range");
    *interval = {v[0], std::lround(v[1]), Vec3(v[2], v[3], v[4]), v[5]};
  };
}

void SectionModel::release_sleeper_when_carried(SettleCriterion& c) const {
  c.each_step = [record = std::move(c.each_step)](Simulation& sim) {
    if (MeshBody* m = sleeper_of(sim)) {
      DofControl& z = m->dof[2];
      // value: the held load, downward (negative); the contact load carries it when the sum is 0.
      if (z.mode == DofMode::servo && m->contact_force.z() + z.value <= 0) z.mode = DofMode::free;
    }
    if (record) record(sim);
  };
}

Sample SectionModel::to_sample(const Simulation& sim,
                               const std::map<std::int64_t, int>& shape_of_id,
                               const std::map<std::int64_t, double>& sieve_size_of_id,
                               const std::vector<std::string>& shapes) const {
  Sample out;
  out.particles = sim.particles();
  for (int i = 0; i < sim.materials().size(); ++i) out.materials.push_back(sim.materials()[i].name);
  for (const auto id : out.particles.id) {
    const auto size = sieve_size_of_id.find(id);
    if (size == sieve_size_of_id.end())
      throw std::logic_error("SectionModel::to_sample: no sieve size for body " +
                             std::to_string(id));
    const auto shape = shape_of_id.find(id);
    out.shape.push_back(shape == shape_of_id.end() ? -1 : shape->second);
    out.sieve_size.push_back(size->second);
  }
  out.shapes = shapes;
  out.planes = sim.planes();
  out.meshes = sim.meshes();
  out.contacts = sim.contact_state();
  out.info = info();
  return out;
}

std::vector<std::pair<std::string, std::string>> SectionModel::info() const {
  auto num = [](double v) {
    std::ostringstream s;
    s.precision(10);
    s << v;
    return s.str();
  };
  const TrackSection& s = section_;
  std::vector<std::pair<std::string, std::string>> out = {
      {"section/sleeper length", num(s.sleeper_length)},
      {"section/sleeper width", num(s.sleeper_width)},
      {"section/sleeper height", num(s.sleeper_height)},
      {"section/sleeper mass", num(s.sleeper_mass)},
      {"section/depth under sleeper", num(s.depth_under_sleeper)},
      {"section/shoulder width", num(s.shoulder_width)},
      {"section/slope", num(s.slope)},
      {"section/length", num(s.length)},
      {"section/boundary", s.periodic ? "periodic" : "walls"},
      {"section/sides", s.side_walls ? "walls" : "slopes"},
      {"section/sleeper bottom width", num(s.bottom_width())},
  };
  for (const Material* m : {&materials_.ballast, &materials_.sleeper, &materials_.wall}) {
    const std::string k = "material/" + m->name + "/";
    out.push_back({k + "density", num(m->density)});
    out.push_back({k + "normal stiffness", num(m->normal_stiffness)});
    out.push_back({k + "shear stiffness", num(m->shear_stiffness)});
    out.push_back({k + "friction", num(m->friction)});
    out.push_back({k + "rolling friction", num(m->rolling_friction)});
    out.push_back({k + "normal damping ratio", num(m->normal_damping_ratio)});
    out.push_back({k + "shear damping ratio", num(m->shear_damping_ratio)});
    out.push_back({k + "normal damping rate", num(m->normal_damping_rate)});
    out.push_back({k + "local damping", num(m->local_damping)});
  }
  return out;
}

namespace {

// A finite number of an info line; InputError naming the line when it is not one.
double info_text_number(const std::string& key, const std::string& text) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !std::isfinite(v))
    throw InputError("sample: info line '" + key + "' holds '" + excerpt(text) +
                     "'; valid: a number, as 'trackbed build-sample' writes it");
  return v;
}

double info_number(const Sample& s, const std::string& key) {
  const std::string v = s.info_value(key);
  if (v.empty())
    throw InputError("sample: info line '" + key +
                     "' is missing; valid: a sample written by 'trackbed build-sample'");
  return info_text_number(key, v);
}

std::string number_list(const std::vector<double>& v) {
  std::string out;
  for (double x : v) out += (out.empty() ? "" : ", ") + exact_number_text(x);
  return out;
}

std::vector<double> info_numbers(const Sample& s, const std::string& key) {
  std::vector<double> out;
  std::string text = s.info_value(key) + ",";
  for (std::size_t start = 0, comma; (comma = text.find(',', start)) != std::string::npos;
       start = comma + 1)
    if (comma > start) out.push_back(info_text_number(key, text.substr(start, comma - start)));
  return out;
}

}  // namespace

TrackSection section_of(const Sample& sample) {
  TrackSection s;
  s.sleeper_length = info_number(sample, "section/sleeper length");
  s.sleeper_width = info_number(sample, "section/sleeper width");
  s.sleeper_height = info_number(sample, "section/sleeper height");
  s.sleeper_mass = info_number(sample, "section/sleeper mass");
  s.depth_under_sleeper = info_number(sample, "section/depth under sleeper");
  s.shoulder_width = info_number(sample, "section/shoulder width");
  s.slope = info_number(sample, "section/slope");
  s.length = info_number(sample, "section/length");
  s.periodic = sample.info_value("section/boundary") == "periodic";
  // Optional: samples written before boxes and wedges were a box-shaped sleeper on slopes.
  s.side_walls = sample.info_value("section/sides") == "walls";
  if (!sample.info_value("section/sleeper bottom width").empty())
    s.sleeper_bottom_width = info_number(sample, "section/sleeper bottom width");
  return s;
}

SectionMaterials materials_of(const Sample& sample) {
  SectionMaterials m;
  for (Material* mat : {&m.ballast, &m.sleeper, &m.wall}) {
    const std::string k = "material/" + mat->name + "/";
    mat->density = info_number(sample, k + "density");
    mat->normal_stiffness = info_number(sample, k + "normal stiffness");
    mat->shear_stiffness = info_number(sample, k + "shear stiffness");
    mat->friction = info_number(sample, k + "friction");
    mat->rolling_friction = info_number(sample, k + "rolling friction");
    // Optional: 0 when absent (samples written before the dashpots were recorded).
    auto optional = [&](const std::string& key) {
      return sample.info_value(key).empty() ? 0.0 : info_number(sample, key);
    };
    mat->normal_damping_ratio = optional(k + "normal damping ratio");
    mat->shear_damping_ratio = optional(k + "shear damping ratio");
    mat->normal_damping_rate = optional(k + "normal damping rate");
    mat->local_damping = info_number(sample, k + "local damping");
  }
  return m;
}

SieveTable grading_of(const Sample& sample) {
  SieveTable t;
  t.source = sample.info_value("grading");
  t.size = info_numbers(sample, "grading/sizes");
  t.passing = info_numbers(sample, "grading/passing");
  validate_sieve_table(t);
  return t;
}

std::vector<std::pair<std::string, std::string>> grading_info(const SieveTable& grading) {
  return {{"grading", grading.source},
          {"grading/sizes", number_list(grading.size)},
          {"grading/passing", number_list(grading.passing)}};
}

double sleeper_lift(const Particles& p, const TrackSection& section) {
  // The bodies centred below the sleeper's bottom that reach into it hold it up: the least lift
  // that clears them. The others do not count: a wedge wider at its bottom, raised, meets the crib
  // stones beside its slanted faces, which bodies_in_section removes instead.
  const double half_length = 0.5 * section.sleeper_length,
               half_bottom = 0.5 * section.bottom_width();
  const bool narrower_below = section.bottom_width() < section.sleeper_width;
  double lift = 0;
  for (int b = 0; b < p.num_bodies(); ++b) {
    if (p.x[b].z() >= section.depth_under_sleeper) continue;
    for (int e = p.first_element[b]; e < p.first_element[b + 1]; ++e) {
      const Vec3& x = p.pos[e];
      const double r = p.radius[e];
      if (section.distance_to_sleeper(x, lift) >= r) continue;
      // The sphere's top over the bottom face's footprint, which the bottom must clear.
      const double dx = std::max(std::abs(x.x()) - half_length, 0.0);
      const double dy = std::max(std::abs(x.y()) - half_bottom, 0.0);
      const double top = x.z() + std::sqrt(std::max(r * r - dx * dx - dy * dy, 0.0));
      lift = std::max(lift, top - section.depth_under_sleeper);
      if (!narrower_below || section.distance_to_sleeper(x, lift) >= r) continue;
      // A wedge narrower at its bottom may still cut the sphere with a slanted face: bisection,
      // the clearance of a sphere below the bottom only growing with the lift.
      double lo = lift, hi = lift + 2 * r;
      for (int k = 0; k < 50; ++k) {
        const double mid = 0.5 * (lo + hi);
        (section.distance_to_sleeper(x, mid) >= r ? hi : lo) = mid;
      }
      lift = hi;
    }
  }
  return lift;
}

std::vector<char> bodies_in_section(const Particles& p, const TrackSection& section,
                                    TrimRule rule) {
  const double lift = rule.sleeper ? sleeper_lift(p, section) : 0.0;
  std::vector<char> keep(p.num_bodies(), 0);
  for (int b = 0; b < p.num_bodies(); ++b) {
    const Vec3& c = p.x[b];
    const bool in_prism =
        c.z() >= 0 && c.z() <= section.crest_z() && std::abs(c.y()) <= 0.5 * section.length &&
        (!rule.slopes || std::abs(c.x()) <= section.half_base_width() - section.slope * c.z());
    // Clear of the sleeper at its design position and where it is placed, raised by the lift.
    bool clear = true;
    for (int e = p.first_element[b]; e < p.first_element[b + 1] && clear && rule.sleeper; ++e)
      clear = section.distance_to_sleeper(p.pos[e]) >= p.radius[e] &&
              section.distance_to_sleeper(p.pos[e], lift) >= p.radius[e];
    keep[b] = in_prism && (c.z() < section.depth_under_sleeper || clear);
  }
  return keep;
}

}  // namespace trackbed::dem
