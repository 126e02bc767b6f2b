#include "dem/samples/sample_builder.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <sstream>

#include "common/input_error.h"
#include "common/number_text.h"
#include "dem/samples/deposition.h"
#include "dem/samples/porosity.h"
#include "dem/samples/random_packing.h"

namespace trackbed::dem {

namespace {

constexpr double kPi = 3.14159265358979323846;
// PFC's safety factor on its critical-step estimate once a stage's contacts are counted.
constexpr double kContactStepFraction = 0.8;

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
        number_text(largest_stone_size(s.grading)) +
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

std::string to_string(BuildStage s) {
  static const char* const names[kBuildStages] = {"deposition",
                                                  "settling",
                                                  "friction restored",
                                                  "sleeper seating in the mould",
                                                  "friction restored in the mould",
                                                  "sleeper tamping",
                                                  "sleeper seating"};
  return names[static_cast<int>(s)];
}

SampleBuilder::StageModel SampleBuilder::model_of(BuildStage s) const {
  const double f = report_.deposition_friction_factor, m = settings_.mould_seating_friction;
  switch (s) {
    case BuildStage::deposition:
      return {{true, false}, {f, f, settings_.deposition_damping}};
    case BuildStage::settling:
      return {{true, false}, {f, f, {}}};
    case BuildStage::friction_restored:
      return {{true, false}, {}};
    case BuildStage::mould_seating:
      return {{true, true}, {m, m, {}}};
    case BuildStage::mould_friction_restored:
      return {{true, true}, {}};
    case BuildStage::tamping:
    case BuildStage::seating:
      break;
  }
  return {{false, true}, {}};
}

void SampleBuilder::next_stage(const Particles& particles, const StageModel& m,
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
  sim_ = std::make_unique<Simulation>(model_.make(particles, m.walls, m.materials, sleeper));
  sim_->setup();
  if (dt > 0) {
    // The first stage's step holds for the later ones unless their contacts need a smaller one.
    sim_->set_time_step(std::min(dt, kContactStepFraction * sim_->critical_timestep()));
    sim_->restore_contact_state(carried);
  }
}

bool SampleBuilder::begin(BuildStage s, const std::function<void()>& make) {
  if (resume_ && s < resume_->stage) return false;  // finished before the checkpoint
  stage_ = s;
  if (resume_ && s == resume_->stage)
    restore();
  else
    make();
  return true;
}

void SampleBuilder::restore() {
  const StageModel m = model_of(resume_->stage);
  // The saved bodies stand where the stage left them, in contact with their neighbours: the
  // overlap check of a model's start does not apply to them.
  SimulationSettings s = stage_settings();
  s.initial_overlap_ratio = std::numeric_limits<double>::infinity();
  const SectionModel model(settings_.section, settings_.materials, s,
                           settings_.preparation_damping);
  try {
    // The saved bodies make the model: checked before it is made of them. They are the stones
    // drawn (again) from the seed, by id.
    const Particles& saved = resume_->engine.particles;
    for (const auto id : saved.id)
      if (id < 0 || id >= static_cast<long>(sieve_size_.size()))
        throw InputError("the saved state is damaged: a body has id " + std::to_string(id) +
                         ", none of the " + std::to_string(sieve_size_.size()) +
                         " stones drawn; valid: a checkpoint of this sample file");
    // The sleeper's mesh made as it was, bit for bit, before its pose is restored.
    sleeper_lift_ = resume_->sleeper_lift;
    if (m.walls.sleeper && !std::isfinite(sleeper_lift_))
      throw InputError("the saved state is damaged: the sleeper's lift is not finite");
    std::optional<MeshBody> sleeper;
    if (m.walls.sleeper) sleeper = model_.sleeper_at(sleeper_lift_);
    sim_ = std::make_unique<Simulation>(model.make(saved, m.walls, m.materials, sleeper));
    const std::string defect = sim_->particles().defect(sim_->materials().size());
    if (!defect.empty())
      throw InputError("the saved state is damaged: " + defect + "; the file is damaged");
    sim_->setup();
    sim_->restore_engine_state(std::move(resume_->engine));
  } catch (const InputError& e) {
    throw InputError(resume_->file + ": " + e.what());
  }
}

void SampleBuilder::settle(const std::string& name, const SettleCriterion& c) {
  criterion_ = c;
  StagePoint start;
  if (resume_) {
    try {
      if (criterion_.restore_memory) criterion_.restore_memory(resume_->criterion_memory);
    } catch (const InputError& e) {
      throw InputError(resume_->file + ": " + e.what());
    }
    start = resume_->point;
    resume_ = nullptr;
  }
  in_stage_ = true;
  report_.stages.push_back(runner_.settle(*sim_, name, criterion_, start));
  in_stage_ = false;
}

BuildCheckpoint SampleBuilder::checkpoint(const StagePoint& at) const {
  BuildCheckpoint c;
  c.stage = stage_;
  c.point = at;
  if (criterion_.memory) c.criterion_memory = criterion_.memory();
  c.report = report_;
  c.sleeper_lift = sleeper_lift_;
  c.engine = sim_->engine_state();
  return c;
}

Sample SampleBuilder::run(BuildCheckpoint* from) {
  resume_ = from;
  draw_stones();
  if (from)
    report_ = from->report;  // the calibration's outcome with the stages finished
  else
    calibrate();
  deposit();
  if (seats_in_mould()) seat_in_mould();
  seat_sleeper();
  if (resume_)
    throw InputError("the checkpoint was taken in the stage '" + to_string(resume_->stage) +
                     "', which this build does not have; valid: a checkpoint of the same build");
  std::map<std::int64_t, double> size_of_id;
  for (std::size_t id = 0; id < sieve_size_.size(); ++id) size_of_id[id] = sieve_size_[id];
  Sample sample = model_.to_sample(*sim_, {}, size_of_id, {});
  for (const auto& line : grading_info(settings_.grading)) sample.info.push_back(line);
  sample.info.push_back({"build/seed", std::to_string(settings_.seed)});
  sample.info.push_back({"build/target porosity", number_text(settings_.target_porosity)});
  sample.info.push_back(
      {"build/deposition friction factor", number_text(report_.deposition_friction_factor)});
  sample.info.push_back({"build/porosity after deposition", number_text(report_.porosity)});
  sample.info.push_back(
      {"build/mould seating friction factor", number_text(settings_.mould_seating_friction)});
  if (seats_in_mould())
    sample.info.push_back(
        {"build/mould seating sleeper", settings_.mould_sleeper_free ? "free" : "servo"});
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
  if (begin(BuildStage::deposition, [&] {
        next_stage(
            ball_cloud(sieve_size_, Vec3(-s.half_base_width(), -0.5 * s.length, 0),
                       Vec3(s.half_base_width(), 0.5 * s.length, 0), settings_.cloud_solid_fraction,
                       0, settings_.materials.ballast.density, settings_.seed + 1),
            model_of(BuildStage::deposition));
      }))
    settle("deposition",
           deposition_criterion(settings_.stage_ratio, settings_.max_stage_time, true));
  if (begin(BuildStage::settling, [&] {
        sim_->set_materials(model_.material_table(model_of(BuildStage::settling).materials));
      })) {
    settle("settling",
           deposition_criterion(settings_.stage_ratio, settings_.max_stage_time, false));
    report_.porosity = core_porosity(sim_->particles());
  }
  if (!seats_in_mould()) restore_friction(BuildStage::friction_restored, f);
}

void SampleBuilder::restore_friction(BuildStage s, double factor) {
  if (factor == 1) return;
  if (!begin(s, [&] { sim_->set_materials(model_.material_table(model_of(s).materials)); })) return;
  SettleCriterion c;
  c.max_time = settings_.max_stage_time;
  c.ratio = settings_.stage_ratio;
  settle("friction restored", c);
}

void SampleBuilder::seat_in_mould() {
  // Levelled at the crest and cleared of the sleeper's box, the bed stays in its mould at a
  // reduced friction while the sleeper seats itself, so that the stones under it can slide into
  // place under its weight; the mould keeps the bed from flowing out meanwhile.
  if (begin(BuildStage::mould_seating, [&] {
        const Particles& p = sim_->particles();
        const Particles kept = p.subset(bodies_in_section(p, settings_.section, {false, true}));
        next_stage(kept, model_of(BuildStage::mould_seating), placed_sleeper(kept));
      })) {
    SettleCriterion c;
    c.max_time = settings_.mould_seating_time;
    c.ratio = settings_.stage_ratio;
    model_.require_seated_sleeper(c);
    if (settings_.mould_sleeper_free) model_.release_sleeper_when_carried(c);
    settle(to_string(BuildStage::mould_seating), c);
  }
  restore_friction(BuildStage::mould_friction_restored, settings_.mould_seating_friction);
}

MeshBody SampleBuilder::placed_sleeper(const Particles& p) {
  sleeper_lift_ = sleeper_lift(p, settings_.section);
  return model_.sleeper_at(sleeper_lift_);
}

void SampleBuilder::trimmed_model() {
  // The stones inside the design profile (the slopes cut, the crest levelled, the sleeper's box
  // cleared), the mould removed. A sleeper already seated in the mould stays where it is: no
  // stone is inside its box.
  const int k = sim_->mesh_index(SectionModel::kSleeperName);
  const Particles& p = sim_->particles();
  const Particles kept = p.subset(bodies_in_section(p, settings_.section, {true, k < 0}));
  next_stage(kept, model_of(BuildStage::seating),
             k >= 0 ? sim_->meshes()[k] : placed_sleeper(kept));
}

void SampleBuilder::seat_sleeper() {
  // One criterion for both stages: the seating goes on judging the sleeper's load from where the
  // tamping left it.
  SettleCriterion c;
  c.max_time = settings_.max_stage_time;
  model_.require_seated_sleeper(c);
  const double weight = model_.sleeper_weight();
  auto load = [this]() -> double& { return sim_->meshes().front().dof[2].value; };
  const bool tamped = settings_.tamping_load_factor > 1;
  if (tamped && begin(BuildStage::tamping, [&] {
        trimmed_model();
        // Pressed into the bed, as tamping and traffic seat a real sleeper, then released.
        load() = settings_.tamping_load_factor * weight;
      })) {
    c.ratio = settings_.stage_ratio;
    settle(to_string(BuildStage::tamping), c);
  }
  if (begin(BuildStage::seating, [&] {
        if (!tamped) trimmed_model();
        load() = weight;
      })) {
    c.ratio = settings_.equilibrium_ratio;
    settle(to_string(BuildStage::seating), c);
  }
}

}  // namespace trackbed::dem
