#include "dem/clump_conversion.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>

#include "dem/input_error.h"
#include "dem/random_packing.h"

namespace trackbed::dem {

namespace {

constexpr double kPi = 3.14159265358979323846;

double info_number(const Sample& s, const std::string& key) {
  const std::string v = s.info_value(key);
  if (v.empty())
    throw InputError("sample: info line '" + key +
                     "' is missing; valid: a sample written by 'trackbed build-sample'");
  return std::stod(v);
}

SimulationSettings settings_for(const ConversionSettings& c) {
  SimulationSettings s;
  s.critical_fraction = c.critical_fraction;
  s.skin = c.skin;
  s.track_energy = false;
  return s;
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
    mat->local_damping = info_number(sample, k + "local damping");
  }
  return m;
}

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
  if (templates_.empty())
    throw InputError("conversion: no clump templates; valid: a library setting with templates");
  if (base_.meshes.size() != 1 || base_.meshes[0].name != SectionModel::kSleeperName)
    throw InputError(
        "conversion: the base sample has no sleeper mesh; valid: a sample written "
        "by 'trackbed build-sample'");
}

Sample ClumpConversion::run() {
  replace();
  grow();
  settle();
  std::vector<std::string> names;
  for (const auto& t : templates_) names.push_back(t.clump.name);
  Sample out = model_.to_sample(*sim_, shape_of_id_, sieve_size_of_id_, names);
  for (const auto& [k, v] : base_.info)
    if (k.rfind("section/", 0) != 0 && k.rfind("material/", 0) != 0 && k != "zone")
      out.info.push_back({k, v});
  out.info.push_back({"zone", zone_->to_string()});
  out.info.push_back({"conversion/templates", templates_.front().setting});
  out.info.push_back({"conversion/seed", std::to_string(settings_.seed)});
  return out;
}

void ClumpConversion::replace() {
  const Particles& p = base_.particles;
  std::mt19937_64 rng(settings_.seed);
  std::uniform_int_distribution<int> pick(0, static_cast<int>(templates_.size()) - 1);
  particles_ = Particles();
  double scale_sum = 0;
  for (int b = 0; b < p.num_bodies(); ++b) {
    const std::int64_t id = p.id[b];
    shape_of_id_[id] = base_.shape[b];
    sieve_size_of_id_[id] = base_.sieve_size[b];
    const bool convert = !p.is_clump[b] && zone_->contains(p.x[b]);
    if (!convert) {
      std::vector<SphereShape> elements;
      for (int e = p.first_element[b]; e < p.first_element[b + 1]; ++e)
        elements.push_back({p.offset[e], p.radius[e]});
      particles_.add_body_with_elements(p.x[b], p.q[b], p.mass[b], p.inertia[b], p.body_material[b],
                                        p.is_clump[b], id, elements);
      continue;
    }
    // Same volume and mass as the ball: the template scaled by s with V_t s^3 = V_ball.
    const int t = pick(rng);
    const LibraryTemplate& lib = templates_[t];
    const double r = p.radius[p.first_element[b]];
    const double s = std::cbrt(4.0 / 3.0 * kPi * r * r * r / lib.clump.volume);
    const double density = p.mass[b] / (lib.clump.volume * s * s * s);
    std::vector<SphereShape> elements;
    for (const SphereShape& sp : lib.clump.spheres)
      elements.push_back({s * sp.centre, s * sp.radius});
    particles_.add_body_with_elements(p.x[b], random_rotation(rng), p.mass[b],
                                      density * std::pow(s, 5) * lib.clump.principal_moments,
                                      p.body_material[b], true, id, elements);
    // The clump starts shrunk to fit inside the ball it replaces.
    const double start = std::min(1.0, r / (s * lib.clump.bounding_radius));
    start_scale_of_id_[id] = start;
    shape_of_id_[id] = t;
    sieve_size_of_id_[id] = s * lib.sieve_size;
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

void ClumpConversion::grow() {
  const StageMaterials growing{
      settings_.growth_friction_factor, settings_.growth_friction_factor, {}};
  sim_ = std::make_unique<Simulation>(
      model_.make(particles_, {false, true}, growing, base_.meshes.front()));
  // The clumps enter at their start size, so setup sees no overlap the balls did not have.
  Particles& p = sim_->particles();
  std::map<std::int64_t, int> body_of_id;
  for (int b = 0; b < p.num_bodies(); ++b) {
    const auto it = start_scale_of_id_.find(p.id[b]);
    if (it == start_scale_of_id_.end()) continue;
    Growing g{p.first_element[b], {}, it->second};
    for (int e = p.first_element[b]; e < p.first_element[b + 1]; ++e)
      g.full.push_back({p.offset[e], p.radius[e]});
    growing_.push_back(std::move(g));
  }
  set_growth(0);
  sim_->setup();
  // Bodies were sorted at setup: find the growing clumps again by id.
  growing_.clear();
  for (int b = 0; b < p.num_bodies(); ++b) {
    const auto it = start_scale_of_id_.find(p.id[b]);
    if (it == start_scale_of_id_.end()) continue;
    Growing g{p.first_element[b], {}, it->second};
    for (int e = p.first_element[b]; e < p.first_element[b + 1]; ++e)
      g.full.push_back({p.offset[e] / it->second, p.radius[e] / it->second});
    growing_.push_back(std::move(g));
  }
  // Springs of the contacts between bodies that stay balls carry over, with the walls' and the
  // sleeper's (same wall numbering: the base sample's model had the same walls).
  ContactState carried;
  auto unchanged = [&](const ElementKey& k) { return start_scale_of_id_.count(k.body_id) == 0; };
  for (const auto& c : base_.contacts.pairs)
    if (unchanged(c.i) && unchanged(c.j)) carried.pairs.push_back(c);
  for (const auto& c : base_.contacts.walls)
    if (unchanged(c.element)) carried.walls.push_back(c);
  sim_->restore_contact_state(carried);

  const int interval = settings_.growth_interval;
  const long steps = static_cast<long>(std::ceil(settings_.growth_time / sim_->time_step()));
  report_.stages.push_back(
      runner_.run_for(*sim_, "clump growth", settings_.growth_time, [&](long step) {
        if (step % interval != 0) return;
        set_growth(static_cast<double>(step + interval) / steps);
        sim_->particles_changed();
      }));
  set_growth(1);
  sim_->particles_changed();
}

void ClumpConversion::settle() {
  sim_->set_materials(model_.material_table());
  SettleCriterion c;
  c.max_time = settings_.max_stage_time;
  c.ratio = settings_.equilibrium_ratio;
  c.also = [this](const Simulation& sim) { return model_.sleeper_seated(sim); };
  report_.stages.push_back(runner_.settle(*sim_, "equilibrium", c));
}

}  // namespace trackbed::dem
