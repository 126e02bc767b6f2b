#include "dem/sample_builder.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>

#include "dem/deposition.h"
#include "dem/input_error.h"
#include "dem/porosity.h"
#include "dem/random_packing.h"

namespace trackbed::dem {

namespace {

constexpr double kPi = 3.14159265358979323846;
// PFC's safety factor on its critical-step estimate once a stage's contacts are counted.
constexpr double kContactStepFraction = 0.8;

std::string number(double v) {
  std::ostringstream s;
  s.precision(6);
  s << v;
  return s.str();
}

}  // namespace

void porosity_box(const TrackSection& section, double largest_stone, Vec3& lower, Vec3& upper) {
  lower = Vec3(-0.5 * section.sleeper_length, -0.5 * section.length + largest_stone, largest_stone);
  upper = Vec3(0.5 * section.sleeper_length, 0.5 * section.length - largest_stone,
               section.depth_under_sleeper);
}

SampleBuilder::SampleBuilder(SampleBuildSettings settings)
    : settings_(std::move(settings)),
      model_(settings_.section, settings_.materials, stage_settings(),
             settings_.preparation_damping) {
  const SampleBuildSettings& s = settings_;
  s.section.validate("");
  if (s.section.periodic)
    throw InputError("section: boundary = periodic is not available in this build; valid: walls");
  validate_sieve_table(s.grading);
  check_range("build: target porosity", s.target_porosity, 0.2, 0.7);
  check_range("build: overfill", s.overfill, 0, 1);
  check_range("build: cloud solid fraction", s.cloud_solid_fraction, 0.01, 0.35);
  check_range("build: deposition damping", s.deposition_damping, 0, 0.999);
  check_range("build: stage ratio", s.stage_ratio, 1e-8, 0.5);
  check_range("build: equilibrium ratio", s.equilibrium_ratio, 1e-8, 0.5);
  check_range("build: maximum stage time", s.max_stage_time, 1e-3, 1e3);
  check_range("build: critical timestep fraction", s.critical_fraction, 1e-3, 1);
  if (s.deposition_friction >= 0)
    check_range("build: deposition friction factor", s.deposition_friction, 0, 1);
  Vec3 lo, hi;
  porosity_box(s.section, largest_stone_size(s.grading), lo, hi);
  if (!((hi - lo).minCoeff() > 0))
    throw InputError(
        "section: the porosity box under the sleeper is empty (the depth under the sleeper and "
        "the section length must exceed the largest stone, " +
        number(largest_stone_size(s.grading)) +
        " m, and twice it); valid: a larger section or smaller stones");
}

SimulationSettings SampleBuilder::stage_settings() const {
  SimulationSettings s;
  s.time_step = settings_.time_step;
  s.critical_fraction = settings_.critical_fraction;
  s.skin = settings_.skin;
  s.track_energy = false;
  return s;
}

double SampleBuilder::core_porosity(const Particles& p) const {
  Vec3 lo, hi;
  porosity_box(settings_.section, largest_stone_size(settings_.grading), lo, hi);
  // A tenth of the smallest stone: the midpoint rule's error is then far below 1 % (porosity.h).
  return porosity_in_box(p, lo, hi, 0.1 * settings_.grading.size.front()).porosity;
}

void SampleBuilder::next_stage(const Particles& particles, const StageWalls& walls,
                               const StageMaterials& materials,
                               const std::optional<MeshBody>& sleeper) {
  ContactState carried;
  double dt = 0;
  if (sim_) {
    carried = sim_->contact_state();
    dt = sim_->time_step();
    // Walls are numbered base, crib walls, side or mould walls, then meshes: only contacts with
    // the walls that every stage has carry over.
    const int common = model_.permanent_walls();
    carried.walls.erase(std::remove_if(carried.walls.begin(), carried.walls.end(),
                                       [&](const SavedWallContact& c) { return c.wall >= common; }),
                        carried.walls.end());
  }
  sim_ = std::make_unique<Simulation>(model_.make(particles, walls, materials, sleeper));
  sim_->setup();
  if (dt > 0) {
    // The first stage's step holds for the later ones unless their contacts need a smaller one.
    sim_->set_time_step(std::min(dt, kContactStepFraction * sim_->critical_timestep()));
    sim_->restore_contact_state(carried);
  }
}

Sample SampleBuilder::run() {
  draw_stones();
  calibrate();
  deposit();
  if (settings_.mould_seating_friction > 0) seat_in_mould();
  trim();
  seat_sleeper();
  std::map<std::int64_t, double> size_of_id;
  for (std::size_t id = 0; id < sieve_size_.size(); ++id) size_of_id[id] = sieve_size_[id];
  Sample sample = model_.to_sample(*sim_, {}, size_of_id, {});
  for (const auto& line : grading_info(settings_.grading)) sample.info.push_back(line);
  sample.info.push_back({"build/seed", std::to_string(settings_.seed)});
  sample.info.push_back({"build/target porosity", number(settings_.target_porosity)});
  sample.info.push_back(
      {"build/deposition friction factor", number(report_.deposition_friction_factor)});
  sample.info.push_back({"build/porosity after deposition", number(report_.porosity)});
  sample.info.push_back(
      {"build/mould seating friction factor", number(settings_.mould_seating_friction)});
  sample.info.push_back({"zone", "none"});
  return sample;
}

void SampleBuilder::draw_stones() {
  const TrackSection& s = settings_.section;
  const double box = 2 * s.half_base_width() * s.length * s.crest_z();
  const double solid = box * (1 + settings_.overfill) * (1 - settings_.target_porosity);
  std::mt19937_64 rng(settings_.seed);
  sieve_size_.clear();
  for (const GradedStone& g : sample_grading(settings_.grading, solid, kPi / 6, rng))
    sieve_size_.push_back(g.size);
  report_.stones_drawn = static_cast<int>(sieve_size_.size());
}

void SampleBuilder::calibrate() {
  if (settings_.deposition_friction >= 0) {
    report_.deposition_friction_factor = settings_.deposition_friction;
    return;
  }
  CalibrationSettings c = settings_.calibration;
  c.bed_height = settings_.section.crest_z();
  c.plan_size = std::max(c.plan_size, 8 * largest_stone_size(settings_.grading));
  c.stage_ratio = settings_.stage_ratio;
  c.max_stage_time = settings_.max_stage_time;
  c.deposition_damping = settings_.deposition_damping;
  c.preparation_damping = settings_.preparation_damping;
  c.critical_fraction = settings_.critical_fraction;
  c.skin = settings_.skin;
  c.seed = settings_.seed + 2;
  const CalibrationResult r = calibrate_deposition_friction(settings_.grading, settings_.materials,
                                                            settings_.target_porosity, c, runner_);
  for (const auto& p : r.points) report_.stages.push_back(p.stage);
  report_.calibration = r.points;
  report_.deposition_friction_factor = r.friction_factor;
}

void SampleBuilder::deposit() {
  const TrackSection& s = settings_.section;
  const double f = report_.deposition_friction_factor;
  const Particles cloud =
      ball_cloud(sieve_size_, Vec3(-s.half_base_width(), -0.5 * s.length, 0),
                 Vec3(s.half_base_width(), 0.5 * s.length, 0), settings_.cloud_solid_fraction, 0,
                 settings_.materials.ballast.density, settings_.seed + 1);
  const StageMaterials fall{f, f, settings_.deposition_damping};
  next_stage(cloud, {true, false}, fall);
  dem::deposit(*sim_,
               {model_.material_table(fall), model_.material_table({f, f, {}}),
                settings_.stage_ratio, settings_.max_stage_time},
               runner_, report_.stages);
  report_.porosity = core_porosity(sim_->particles());
  if (settings_.mould_seating_friction == 0) restore_friction(f);
}

void SampleBuilder::restore_friction(double factor) {
  if (factor == 1) return;
  sim_->set_materials(model_.material_table());
  SettleCriterion c;
  c.max_time = settings_.max_stage_time;
  c.ratio = settings_.stage_ratio;
  report_.stages.push_back(runner_.settle(*sim_, "friction restored", c));
}

void SampleBuilder::seat_in_mould() {
  // Levelled at the crest and cleared of the sleeper's box, the bed stays in its mould at a
  // reduced friction while the sleeper seats itself, so that the stones under it can slide into
  // place under its weight; the mould keeps the bed from flowing out meanwhile.
  const double f = settings_.mould_seating_friction;
  const Particles& p = sim_->particles();
  next_stage(p.subset(bodies_in_section(p, settings_.section, {false, true})), {true, true},
             {f, f, {}});
  SettleCriterion c;
  c.max_time = settings_.mould_seating_time;
  c.ratio = settings_.stage_ratio;
  model_.require_seated_sleeper(c);
  report_.stages.push_back(runner_.settle(*sim_, "sleeper seating in the mould", c));
  restore_friction(f);
}

void SampleBuilder::trim() {
  // A sleeper already seated (in the mould) stays where it is: no stone is inside its box.
  const bool seated = sim_->mesh_index(SectionModel::kSleeperName) >= 0;
  particles_ = sim_->particles().subset(
      bodies_in_section(sim_->particles(), settings_.section, {true, !seated}));
}

void SampleBuilder::seat_sleeper() {
  std::optional<MeshBody> seated;
  if (const int k = sim_->mesh_index(SectionModel::kSleeperName); k >= 0)
    seated = sim_->meshes()[k];
  next_stage(particles_, {false, true}, {}, seated);
  SettleCriterion c;
  c.max_time = settings_.max_stage_time;
  model_.require_seated_sleeper(c);
  double& load = sim_->meshes().front().dof[2].value;
  const double weight = load;
  if (settings_.tamping_load_factor > 1) {
    // Pressed into the bed, as tamping and traffic seat a real sleeper, then released.
    load = settings_.tamping_load_factor * weight;
    c.ratio = settings_.stage_ratio;
    report_.stages.push_back(runner_.settle(*sim_, "sleeper tamping", c));
    load = weight;
  }
  c.ratio = settings_.equilibrium_ratio;
  report_.stages.push_back(runner_.settle(*sim_, "sleeper seating", c));
}

}  // namespace trackbed::dem
