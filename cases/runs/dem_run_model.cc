// The model of a DemRun (dem_run.h): materials, bodies, walls and meshes from the case file and
// its sample, and a coupled run's subgrade in place of the sample's base.
#include <algorithm>
#include <iostream>
#include <map>
#include <optional>

#include "cases/runs/dem_run.h"
#include "common/input_error.h"
#include "common/number_text.h"
#include "dem/engine/clump_template.h"
#include "dem/engine/triangle_mesh.h"
#include "dem/io/clump_template_file.h"
#include "dem/io/particle_file.h"
#include "dem/io/stl_file.h"
#include "dem/samples/random_packing.h"
#include "dem/samples/section_model.h"

namespace trackbed::cases {

using dem::Vec3;

namespace {

int material_index(const dem::MaterialTable& table, const std::string& name,
                   const std::string& where) {
  if (name.empty()) return 0;
  try {
    return table.index_of(name);
  } catch (const InputError& e) {
    throw InputError(where + ": " + e.what());
  }
}
}  // namespace

void DemRun::build_model() {
  std::optional<dem::Sample> sample;
  if (!prm_.sample_file.empty()) sample = dem::read_sample(prm_.sample_file);
  if (prm_.mode == "coupled") {
    if (!sample)
      throw InputError(prm_.file +
                       ": mode = coupled needs particles/sample file, a track-section sample (its "
                       "section gives the subgrade's formation); valid: a sample built by "
                       "'trackbed build-sample'");
    make_subgrade(*sample);
  }
  const dem::Sample* from = sample ? &*sample : nullptr;
  dem::MaterialTable materials = make_materials();
  dem::Particles particles = make_particles(from, materials);

  dem::SimulationSettings settings;
  settings.time_step = prm_.time_step;
  settings.critical_fraction = prm_.critical_fraction;
  settings.allow_supercritical_step = prm_.allow_supercritical;
  settings.gravity = prm_.gravity;
  settings.skin = prm_.skin;
  settings.track_energy = prm_.track_energy;
  settings.max_energy_error = prm_.energy_error_limit;
  sim_ = std::make_unique<dem::Simulation>(std::move(materials), std::move(particles), settings);

  add_planes(from);
  for (const auto& m : prm_.meshes) add_mesh(m, from);
  if (subgrade_) {
    // The formation carries the material of the base plane it replaces.
    const auto base = std::find_if(sample->planes.begin(), sample->planes.end(),
                                   [](const dem::PlaneWall& w) { return w.name == "base"; });
    const int material = base == sample->planes.end() ? 0 : sample_material_[base->material];
    formation_mesh_ = sim_->add_mesh_body(subgrade_->formation_body(material));
  }
}

dem::MaterialTable DemRun::make_materials() const {
  dem::MaterialTable materials;
  for (const auto& m : prm_.materials) materials.add(m);
  for (const auto& p : prm_.pairs) {
    const std::string where = prm_.file + ": contact pairs";
    materials.set_pair(material_index(materials, p.material_a, where),
                       material_index(materials, p.material_b, where), p.properties);
  }
  return materials;
}

dem::Particles DemRun::make_particles(const dem::Sample* sample,
                                      const dem::MaterialTable& materials) {
  std::map<std::string, dem::ClumpTemplate> templates;
  for (const auto& [name, file] : prm_.templates)
    templates.emplace(name, dem::read_clump_template_csv(file, name));

  dem::Particles particles;
  if (sample) {
    sample_material_.clear();
    for (const auto& name : sample->materials)
      sample_material_.push_back(material_index(
          materials, name, prm_.file + ": particles/sample file " + prm_.sample_file));
    particles = sample_particles(*sample, materials);
  }
  if (!prm_.particle_file.empty())
    dem::read_particle_file(prm_.particle_file, materials, templates, particles);
  if (prm_.generator.count > 0) {
    const auto& g = prm_.generator;
    dem::RandomPackingSpec spec;
    spec.lower = Vec3(g.region[0], g.region[1], g.region[2]);
    spec.upper = Vec3(g.region[3], g.region[4], g.region[5]);
    spec.count = g.count;
    spec.radius_min = g.radius_min;
    spec.radius_max = g.radius_max;
    spec.clump_fraction = g.clump_fraction;
    if (!g.clump_template.empty()) {
      const auto it = templates.find(g.clump_template);
      if (it == templates.end())
        throw InputError(prm_.file + ": particles/generator/clump template '" + g.clump_template +
                         "' is not among particles/templates");
      spec.clump_template = &it->second;
    }
    spec.material = material_index(materials, g.material, prm_.file + ": particles/generator");
    spec.seed = prm_.seed;
    dem::add_random_packing(spec, materials, particles);
  }
  return particles;
}

void DemRun::add_planes(const dem::Sample* sample) {
  if (sample)
    for (const int k : kept_sample_planes(*sample)) {
      dem::PlaneWall w = sample->planes[k];
      w.material = sample_material_[w.material];
      sim_->add_plane(w);
    }
  for (const auto& w : prm_.planes) {
    dem::PlaneWall wall;
    wall.name = w.name;
    wall.point = w.point;
    wall.normal = w.normal;
    wall.velocity = w.velocity;
    wall.material =
        material_index(sim_->materials(), w.material, prm_.file + ": plane walls/" + w.name);
    sim_->add_plane(wall);
  }
}

void DemRun::add_mesh(const MeshParameters& m, const dem::Sample* sample) {
  const std::string where = prm_.file + ": meshes/" + m.name;
  if (m.from_sample) {
    const auto it = std::find_if(sample->meshes.begin(), sample->meshes.end(),
                                 [&](const dem::MeshBody& b) { return b.name == m.name; });
    if (it == sample->meshes.end())
      throw InputError(
          where + ": the sample " + prm_.sample_file + " has no mesh of this name; valid: " +
          (sample->meshes.empty() ? std::string("(none)") : sample->meshes.front().name));
    dem::MeshBody body = *it;
    body.material = m.material.empty() ? sample_material_[it->material]
                                       : material_index(sim_->materials(), m.material, where);
    body.weight = m.weight;
    body.dof = m.dof;
    sim_->add_mesh_body(std::move(body));
    return;
  }
  dem::TriangleMesh mesh =
      m.file.empty() ? dem::make_box_mesh(Vec3(m.box[0], m.box[1], m.box[2]),
                                          Vec3(m.box[3], m.box[4], m.box[5]), m.named_box_parts)
                     : dem::read_stl(m.file);
  // A model spans metres to kilometres: a vertex beyond 1e6 m is a wrong scale or translation
  // (an STL in millimetres needs scale 0.001), and its products would overflow.
  constexpr double kMaxCoordinate = 1e6;
  for (auto& v : mesh.vertices) {
    v = v * m.scale + m.translation;
    if (!(v.cwiseAbs().maxCoeff() <= kMaxCoordinate))
      throw InputError(where + ": a vertex lies at (" + number_text(v.x()) + ", " +
                       number_text(v.y()) + ", " + number_text(v.z()) +
                       ") m after scale and translation; valid: coordinates within 1e6 m");
  }
  const int mat = material_index(sim_->materials(), m.material, where);
  const double density = m.density > 0 ? m.density : (m.mass > 0 ? 1.0 : 0.0);
  dem::MeshBody body = dem::MeshBody::from_world_mesh(m.name, mesh, mat, density, Vec3::Zero());
  if (m.mass > 0) {
    // Keep the mesh's inertia distribution, scaled to the given mass.
    body.inertia *= m.mass / body.mass;
    body.mass = m.mass;
  }
  body.weight = m.weight;
  body.dof = m.dof;
  for (int d = 0; d < 6; ++d) {
    const auto mode = m.dof[d].mode;
    if ((mode == dem::DofMode::free || mode == dem::DofMode::force) && !(body.mass > 0))
      throw InputError(where +
                       ": a free or force-loaded degree of freedom needs a mass; "
                       "valid: set 'density' (closed mesh) or 'mass' > 0");
  }
  sim_->add_mesh_body(std::move(body));
}

void DemRun::make_subgrade(const dem::Sample& sample) {
  const TrackSection section = dem::section_of(sample);
  try {
    subgrade_ = std::make_unique<SubgradeCoupling>(prm_, section);
  } catch (const InputError& e) {
    // The FE mesh's checks see the section (the sample's, with the case's layers), not where
    // its figures came from.
    throw InputError(prm_.file + ": fem/layers with the sample's section: " + e.what());
  }
  std::cout << "trackbed: coupled: " << subgrade_->description() << std::endl;
}

std::vector<int> DemRun::kept_sample_planes(const dem::Sample& sample) const {
  std::vector<int> kept;
  if (!prm_.sample_walls) return kept;
  for (int k = 0; k < static_cast<int>(sample.planes.size()); ++k)
    if (!(subgrade_ && sample.planes[k].name == "base")) kept.push_back(k);
  return kept;
}

int DemRun::sleeper_mesh() const {
  const auto& meshes = sim_->meshes();
  for (int k = 0; k < static_cast<int>(meshes.size()); ++k)
    if (meshes[k].name == (prm_.push.mesh.empty() ? "sleeper" : prm_.push.mesh)) return k;
  return -1;
}

dem::Particles DemRun::sample_particles(const dem::Sample& sample,
                                        const dem::MaterialTable& materials) {
  dem::Particles p = sample.particles;
  for (int& m : p.body_material) m = sample_material_[m];
  for (int& m : p.material) m = sample_material_[m];
  if (!prm_.clump_material.empty()) {
    const int clump =
        material_index(materials, prm_.clump_material, prm_.file + ": particles/clump material");
    for (int b = 0; b < p.num_bodies(); ++b) {
      if (!p.is_clump[b]) continue;
      p.body_material[b] = clump;
      for (int e = p.first_element[b]; e < p.first_element[b + 1]; ++e) p.material[e] = clump;
    }
  }
  // The sample walls the run keeps come first, in their order; its meshes are matched by name
  // to the case's meshes taken from the sample; contacts with anything else are dropped (but
  // those with a base a subgrade's formation replaces).
  const int sample_planes = static_cast<int>(sample.planes.size());
  std::vector<int> plane_number(sample_planes, -1);
  const std::vector<int> kept = kept_sample_planes(sample);
  for (int k = 0; k < static_cast<int>(kept.size()); ++k) plane_number[kept[k]] = k;
  const int case_planes = static_cast<int>(kept.size() + prm_.planes.size());
  sample_contacts_ = dem::ContactState();
  sample_contacts_.pairs = sample.contacts.pairs;
  for (dem::SavedWallContact c : sample.contacts.walls) {
    if (c.wall < sample_planes && subgrade_ && sample.planes[c.wall].name == "base") {
      // A spring on the base carries over to the formation that replaces it (added after the
      // case's meshes): the element's only contact with it, facing the same way.
      c.normal = sample.planes[c.wall].normal;
      c.wall = case_planes + static_cast<int>(prm_.meshes.size());
      c.slot = 0;
    } else if (c.wall < sample_planes) {
      if (plane_number[c.wall] < 0) continue;
      c.wall = plane_number[c.wall];
    } else {
      const std::string& name = sample.meshes[c.wall - sample_planes].name;
      int k = 0;
      while (k < static_cast<int>(prm_.meshes.size()) &&
             !(prm_.meshes[k].from_sample && prm_.meshes[k].name == name))
        ++k;
      if (k == static_cast<int>(prm_.meshes.size())) continue;
      c.wall = case_planes + k;
    }
    sample_contacts_.walls.push_back(c);
  }
  return p;
}

}  // namespace trackbed::cases
