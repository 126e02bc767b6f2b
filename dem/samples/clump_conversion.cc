#include "dem/samples/clump_conversion.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "common/input_error.h"
#include "common/number_text.h"
#include "dem/engine/mass_properties.h"
#include "dem/samples/ballast_stone.h"
#include "dem/samples/clump_fitting.h"
#include "dem/samples/random_packing.h"

namespace trackbed::dem {

std::string to_string(ConversionStage s) {
  static const char* const names[kConversionStages] = {"clump growth", "densification",
                                                       "equilibrium"};
  return names[static_cast<int>(s)];
}

namespace {

constexpr double kPi = 3.14159265358979323846;
// A clump squeezed below this start scale by its neighbours starts at it anyway: the few such
// overlaps are pushed apart by the contacts as the growth begins.
constexpr double kMinimumStartScale = 0.3;

SimulationSettings settings_for(const ConversionSettings& c) {
  SimulationSettings s;
  s.time_step = 0;  // the critical fraction of the converted model's own estimate
  s.critical_fraction = c.critical_fraction;
  s.skin = c.skin;
  s.track_energy = false;
  return s;
}

}  // namespace

ClumpConversion::ClumpConversion(const Sample& base, ZonePtr zone,
                                 std::vector<LibraryTemplate> templates,
                                 ConversionSettings settings)
    : base_(base),
      zone_(std::move(zone)),
      templates_(std::move(templates)),
      settings_(settings),
      model_(section_of(base), materials_of(base), settings_for(settings),
             settings.preparation_damping) {
  check_range("conversion: growth time", settings_.growth_time, 1e-4, 10);
  check_range("conversion: growth interval", settings_.growth_interval, 1, 1e6);
  check_range("conversion: growth friction factor", settings_.growth_friction_factor, 0, 1);
  check_range("conversion: equilibrium ratio", settings_.equilibrium_ratio, 1e-8, 0.5);
  check_range("conversion: growth step factor", settings_.growth_step_factor, 1, 100);
  check_range("conversion: settling step factor", settings_.settling_step_factor, 1, 100);
  if (settings_.growth_step_factor > 1 && settings_.growth_step == GrowthStep::probe)
    throw InputError(
        "conversion: a growth step factor above 1 with the probe's growth step; "
        "valid: 1, or the renewed growth step");
  if (templates_.empty())
    throw InputError("conversion: no clump templates; valid: a library setting with templates");
  for (const LibraryTemplate& t : templates_) {
    pebble_volume_.push_back(sphere_union_mass_properties(t.clump.spheres).volume);
    pebble_sieve_size_.push_back(clump_sieve_size(t.clump));
  }
  const Particles& p = base_.particles;
  for (int b = 0; b < p.num_bodies(); ++b)
    converts_.push_back(!p.is_clump[b] && zone_->contains(p.x[b]));
  if (base_.meshes.size() != 1 || base_.meshes[0].name != SectionModel::kSleeperName)
    throw InputError(
        "conversion: the base sample has no sleeper mesh; valid: a sample written "
        "by 'trackbed build-sample'");
}

Sample ClumpConversion::run(ConversionCheckpoint* from) {
  replace();
  grow(from);
  settle(from && from->stage != ConversionStage::growth ? from : nullptr);
  std::vector<std::string> names;
  for (const auto& t : templates_) names.push_back(t.clump.name);
  Sample out = model_.to_sample(*sim_, shape_of_id_, sieve_size_of_id_, names);
  // The sample's clumps are ballast again, as its balls: a case gives them the material it runs
  // them with ('particles/clump material'), as it does to clumps of any sample.
  // Clump material to the ballast (the table's first material), the ones after it one down.
  const int clump = model_.clump_material();
  const auto as_ballast = [clump](int& m) {
    if (m == clump)
      m = 0;
    else if (m > clump)
      --m;
  };
  Particles& q = out.particles;
  for (int& m : q.body_material) as_ballast(m);
  for (int& m : q.material) as_ballast(m);
  out.materials.erase(out.materials.begin() + clump);
  for (const auto& [k, v] : base_.info)
    if (k.rfind("section/", 0) != 0 && k.rfind("material/", 0) != 0 && k != "zone")
      out.info.push_back({k, v});
  out.info.push_back({"zone", zone_->to_string()});
  out.info.push_back({"conversion/templates", templates_.front().setting});
  out.info.push_back({"conversion/seed", std::to_string(settings_.seed)});
  // The rolling friction the clumps settled with: the ballast's after a densification, else none.
  out.info.push_back(
      {"conversion/clump rolling friction",
       exact_number_text(sim_->materials()[model_.clump_material()].rolling_friction)});
  out.info.push_back(
      {"conversion/densification ratio", exact_number_text(settings_.densification_ratio)});
  out.info.push_back(
      {"conversion/growth step", settings_.growth_step == GrowthStep::probe ? "probe" : "renewed"});
  out.info.push_back(
      {"conversion/growth step factor", exact_number_text(settings_.growth_step_factor)});
  out.info.push_back(
      {"conversion/settling step factor", std::to_string(settings_.settling_step_factor)});
  return out;
}

void ClumpConversion::replace() {
  const Particles& p = base_.particles;
  std::mt19937_64 rng(settings_.seed);
  std::uniform_int_distribution<int> pick(0, static_cast<int>(templates_.size()) - 1);
  // The sleeper as it sits in the base sample: its design shape raised to its seated level.
  double bottom = std::numeric_limits<double>::infinity();
  for (const Vec3& v : base_.meshes.front().world.vertices) bottom = std::min(bottom, v.z());
  ClumpFitter fitter(p, model_.section(), bottom - model_.section().depth_under_sleeper);
  particles_ = Particles();
  double scale_sum = 0;
  const int clump_material = model_.clump_material();
  for (int b = 0; b < p.num_bodies(); ++b) {
    const std::int64_t id = p.id[b];
    shape_of_id_[id] = base_.shape[b];
    sieve_size_of_id_[id] = base_.sieve_size[b];
    if (!converts_[b]) {
      std::vector<SphereShape> elements;
      for (int e = p.first_element[b]; e < p.first_element[b + 1]; ++e)
        elements.push_back({p.offset[e], p.radius[e]});
      particles_.add_body_with_elements(p.x[b], p.q[b], p.mass[b], p.inertia[b], p.body_material[b],
                                        p.is_clump[b], id, elements);
      continue;
    }
    // Same solid volume and mass as the ball: the template scaled by s so that its pebbles fill
    // the ball's volume, V_pebbles s^3 = V_ball; the inertia has the template's radii of
    // gyration (from the chosen mass source), scaled by s, for the ball's mass.
    const int t = pick(rng);
    const LibraryTemplate& lib = templates_[t];
    const double r = p.radius[p.first_element[b]];
    const double s = std::cbrt(4.0 / 3.0 * kPi * r * r * r / pebble_volume_[t]);
    std::vector<SphereShape> elements;
    for (const SphereShape& sp : lib.clump.spheres)
      elements.push_back({s * sp.centre, s * sp.radius});
    // The orientation that lets the clump start largest among its neighbours as they stand.
    fitter.remove_body(b);
    Quat best_q = Quat::Identity();
    double start = -1;
    std::vector<SphereShape> rotated(elements.size());
    for (int trial = 0; trial < settings_.orientation_trials; ++trial) {
      const Quat q = random_rotation(rng);
      const Mat3 R = q.toRotationMatrix();
      for (std::size_t k = 0; k < elements.size(); ++k)
        rotated[k] = {R * elements[k].centre, elements[k].radius};
      const double g = fitter.fit(p.x[b], rotated);
      if (g > start) start = g, best_q = q;
    }
    start = std::max(start, kMinimumStartScale);
    const Mat3 R = best_q.toRotationMatrix();
    std::vector<SphereShape> placed;
    for (const SphereShape& e : elements)
      placed.push_back({p.x[b] + start * (R * e.centre), start * e.radius});
    fitter.add(placed);
    particles_.add_body_with_elements(
        p.x[b], best_q, p.mass[b],
        p.mass[b] * s * s / lib.clump.volume * lib.clump.principal_moments, clump_material, true,
        id, elements);
    start_scale_of_id_[id] = start;
    shape_of_id_[id] = t;
    sieve_size_of_id_[id] = s * pebble_sieve_size_[t];
    report_.start_scale_min = std::min(report_.start_scale_min, start);
    scale_sum += start;
    ++report_.converted;
  }
  report_.start_scale_mean = report_.converted > 0 ? scale_sum / report_.converted : 1;
}

void ClumpConversion::set_growth(double fraction) {
  Particles& p = sim_->particles();
  for (const Growing& g : growing_) {
    const double f = g.start_scale + (1 - g.start_scale) * std::min(1.0, fraction);
    for (std::size_t k = 0; k < g.full.size(); ++k) {
      p.offset[g.first_element + k] = f * g.full[k].centre;
      p.radius[g.first_element + k] = f * g.full[k].radius;
    }
  }
}

int ClumpConversion::balls_in_zone() const {
  return static_cast<int>(std::count(converts_.begin(), converts_.end(), true));
}

ConversionCheckpoint ClumpConversion::checkpoint(const StagePoint& at) const {
  ConversionCheckpoint c;
  c.stage = stage_;
  c.point = at;
  if (stage_ == ConversionStage::equilibrium && settled_.memory)
    c.criterion_memory = settled_.memory();
  c.done = report_.stages;
  c.engine = sim_->engine_state();
  return c;
}

void ClumpConversion::restore(ConversionCheckpoint& from) {
  try {
    sim_->restore_engine_state(std::move(from.engine));
    if (from.stage == ConversionStage::equilibrium) settled_.restore_memory(from.criterion_memory);
  } catch (const InputError& e) {
    throw InputError(from.file + ": " + e.what());
  }
}

void ClumpConversion::grow(ConversionCheckpoint* from) {
  const StageMaterials growing{
      settings_.growth_friction_factor, settings_.growth_friction_factor, {}, true};
  const bool renewed = settings_.growth_step == GrowthStep::renewed;
  double dt = std::numeric_limits<double>::infinity();
  if (!renewed) {
    // The step must suit the grown clumps: the critical step of the full-size model, whose
    // overlaps a probe model tolerates (it is never stepped).
    SimulationSettings probe_settings = settings_for(settings_);
    probe_settings.initial_overlap_ratio = 1e9;
    SectionModel probe_model(model_.section(), model_.materials(), probe_settings);
    Simulation probe = probe_model.make(particles_, {false, true}, growing, base_.meshes.front());
    probe.setup();
    dt = settings_.critical_fraction * probe.critical_timestep();
  }

  sim_ = std::make_unique<Simulation>(
      model_.make(particles_, {false, true}, growing, base_.meshes.front()));
  // The clumps enter at their start size, so setup sees no overlap the balls did not have.
  Particles& p = sim_->particles();
  auto collect = [&](bool divide_by_start) {
    growing_.clear();
    for (int b = 0; b < p.num_bodies(); ++b) {
      const auto it = start_scale_of_id_.find(p.id[b]);
      if (it == start_scale_of_id_.end()) continue;
      Growing g{p.first_element[b], {}, it->second};
      const double f = divide_by_start ? 1 / it->second : 1;
      for (int e = p.first_element[b]; e < p.first_element[b + 1]; ++e)
        g.full.push_back({f * p.offset[e], f * p.radius[e]});
      growing_.push_back(std::move(g));
    }
  };
  collect(false);
  set_growth(0);
  sim_->setup();
  sim_->set_time_step(std::min(sim_->time_step(), dt));
  collect(true);  // bodies were sorted at setup: find the growing clumps again
  // Springs of the contacts between bodies that stay balls carry over, with the walls' and the
  // sleeper's (same wall numbering: the base sample's model had the same walls).
  ContactState carried;
  auto unchanged = [&](const ElementKey& k) { return start_scale_of_id_.count(k.body_id) == 0; };
  for (const auto& c : base_.contacts.pairs)
    if (unchanged(c.i) && unchanged(c.j)) carried.pairs.push_back(c);
  for (const auto& c : base_.contacts.walls)
    if (unchanged(c.element)) carried.walls.push_back(c);
  sim_->restore_contact_state(carried);
  // Interrupted in the settling, the clumps are grown: settle() restores the state.
  if (from && from->stage != ConversionStage::growth) {
    report_.stages = from->done;
    return;
  }
  StagePoint start;
  StepRenewal renewal;
  renewal.began = sim_->time();
  if (from) {
    restore(*from);
    start = from->point;
  }
  if (renewed)
    // The critical step of the model as it stands, renewed at every check (500 steps, in which
    // the clumps grow by well under a thousandth of their size): the clumps touch their
    // neighbours as they grow, not as the probe's full-size clumps in the balls' places. A
    // multiple of it with the bodies that need it density scaled, their factors renewed with it:
    // for every pair of their neighbour list, as the growing clumps touch new neighbours between
    // two checks (scaled for their contacts alone, a loose bed's stones that touched few blew
    // the bed apart once they met more: docs/samples.md, "Time step").
    renewal.renew = [fraction = settings_.critical_fraction,
                     factor = settings_.growth_step_factor](Simulation& sim) {
      sim.end_density_scaling();  // the unscaled bed's critical step
      const double dt = factor * fraction * sim.critical_timestep();
      if (factor > 1)
        sim.scale_density_for_step(dt, fraction, true);
      else
        sim.set_time_step(dt);
    };

  stage_ = ConversionStage::growth;
  const int interval = settings_.growth_interval;
  const double duration = settings_.growth_time;
  const long steps = static_cast<long>(std::ceil(duration / sim_->time_step()));
  // Linear in time: by the steps of the fixed step, by the clock of a renewed one.
  auto fraction_after = [&](long step) {
    return renewed ? (sim_->time() - renewal.began + interval * sim_->time_step()) / duration
                   : static_cast<double>(step + interval) / steps;
  };
  report_.stages.push_back(runner_.run_for(
      *sim_, to_string(stage_), duration,
      [&](long step) {
        if (step % interval != 0) return;
        set_growth(fraction_after(step));
        sim_->particles_changed();
      },
      start, 500, renewal));
  set_growth(1);
  sim_->particles_changed();
  sim_->end_density_scaling();  // the settling takes its own step from the unscaled bed
}

void ClumpConversion::settle(ConversionCheckpoint* from) {
  const bool split = settings_.densification_ratio > 0;
  const bool densify = split && (!from || from->stage == ConversionStage::densification);
  auto materials = [&](bool clump_rolling) {
    return model_.material_table(StageMaterials{1, 1, {}, true, clump_rolling});
  };
  // The materials of the stage it begins in: the clumps roll freely but in a split settling's
  // equilibrium stage.
  sim_->set_materials(materials(split && !densify));
  settled_ = SettleCriterion{};
  settled_.max_time = settings_.max_stage_time;
  settled_.ratio = settings_.equilibrium_ratio;
  model_.require_seated_sleeper(settled_);
  model_.release_sleeper_when_carried(settled_);
  StagePoint start;
  // The grown bed's own estimate, as a case takes at its setup: about twice the probe's growth
  // step (every clump at full size where its ball was, deep in its neighbours, touches several
  // times the stiffness it touches in the grown bed; docs/samples.md, "Time step"). Density
  // scaling allows a multiple of it.
  double dt =
      settings_.settling_step_factor * settings_.critical_fraction * sim_->critical_timestep();
  if (from) {
    restore(*from);
    dt = sim_->time_step();  // the step it was taking
    start = from->point;
  }
  if (densify) {
    // Judged by the ratio alone: the sleeper's seating is the equilibrium stage's to judge.
    SettleCriterion dense;
    dense.max_time = settings_.max_stage_time;
    dense.ratio = settings_.densification_ratio;
    model_.release_sleeper_when_carried(dense);
    stage_ = ConversionStage::densification;
    take_settling_step(dense, dt, start.steps);
    report_.stages.push_back(runner_.settle(*sim_, to_string(stage_), dense, start));
    sim_->set_materials(materials(true));
    // The rolling springs stiffen the clumps' rotation: density scaled anew below, or, unscaled, a
    // step the model can take with them.
    if (settings_.settling_step_factor <= 1)
      dt = std::min(dt, settings_.critical_fraction * sim_->critical_timestep());
    start = StagePoint{};
  }
  stage_ = ConversionStage::equilibrium;
  take_settling_step(settled_, dt, start.steps);
  report_.stages.push_back(runner_.settle(*sim_, to_string(stage_), settled_, start));
  sim_->end_density_scaling();
}

void ClumpConversion::take_settling_step(SettleCriterion& c, double dt, long steps_done) {
  if (settings_.settling_step_factor <= 1) {
    sim_->set_time_step(dt);
    return;
  }
  // Renewed at the checks, where a checkpoint is taken: a resumed stage scales from the same
  // state as the uninterrupted one, bit for bit.
  const double fraction = settings_.critical_fraction;
  sim_->scale_density_for_step(dt, fraction);
  auto steps = std::make_shared<long>(steps_done);
  c.each_step = [record = std::move(c.each_step), steps, fraction,
                 interval = c.check_interval](Simulation& sim) {
    if (record) record(sim);
    if (++*steps % interval == 0) sim.scale_density_for_step(sim.time_step(), fraction);
  };
}

}  // namespace trackbed::dem
