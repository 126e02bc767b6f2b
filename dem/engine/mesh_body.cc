#include "dem/engine/mesh_body.h"

#include <algorithm>
#include <cmath>

#include "common/input_error.h"

namespace trackbed::dem {

void MeshBody::update_world_mesh() {
  if (deformable) return;  // its world vertices are its state, moved from outside
  const Mat3 R = q.toRotationMatrix();
  for (std::size_t i = 0; i < local.vertices.size(); ++i)
    world.vertices[i] = x + R * local.vertices[i];
}

double MeshBody::reach() const {
  double r = 0;
  for (const auto& p : local.vertices) r = std::max(r, p.norm());
  return r;
}

void MeshBody::integrate(double dt, const Vec3& g) {
  // World-frame diagonal of the inertia tensor for the rotational DOFs (see the header).
  const Mat3 R = q.toRotationMatrix();
  const Vec3 I_world = (R * inertia * R.transpose()).diagonal();
  for (int k = 0; k < 6; ++k) {
    const DofControl& c = dof[k];
    const bool rot = k >= 3;
    const int a = k % 3;
    double& vel = rot ? w[a] : v[a];
    const double load = rot ? contact_moment[a] : contact_force[a];
    const double weight_k = (!rot && weight) ? mass * g[a] : 0.0;
    const double inertia_k = rot ? I_world[a] : mass;
    switch (c.mode) {
      case DofMode::fixed:
        vel = 0;
        break;
      case DofMode::velocity:
        vel = c.value;
        break;
      case DofMode::free:
        vel += (load + weight_k) / inertia_k * dt;
        break;
      case DofMode::force:
        vel += (load + c.value + weight_k) / inertia_k * dt;
        break;
      case DofMode::servo: {
        const double error = load + c.value;
        const double k = rot ? contact_rotational_stiffness[a] : contact_stiffness[a];
        if (c.gain > 0)
          vel = c.gain * error;
        else if (k > 0)
          vel = c.relaxation * error / (k * dt);
        else
          vel = error > 0 ? c.max_speed : (error < 0 ? -c.max_speed : 0.0);
        if (c.max_speed > 0) vel = std::clamp(vel, -c.max_speed, c.max_speed);
        break;
      }
    }
  }
  x += v * dt;
  const double angle = w.norm() * dt;
  if (angle > 0) q = (Quat(Eigen::AngleAxisd(angle, w.normalized())) * q).normalized();
  update_world_mesh();
}

void MeshBody::make_deformable() {
  static const char* kAxes[6] = {"x", "y", "z", "rx", "ry", "rz"};
  for (int k = 0; k < 6; ++k)
    if (dof[k].mode != DofMode::fixed)
      throw InputError("mesh '" + name + "': its dof " + kAxes[k] +
                       " is not fixed; valid: a deformable mesh moves by its vertices, every "
                       "rigid-body degree of freedom fixed");
  deformable = true;
  v = w = Vec3::Zero();
  const std::size_t n = world.vertices.size();
  deformation.velocity.assign(n, Vec3::Zero());
  deformation.load.assign(n, Vec3::Zero());
  deformation.impulse.assign(n, Vec3::Zero());
  deformation.impulse_time = 0;
  deformation.at_build = world.vertices;
  deformation.pending_move.assign(n, Vec3::Zero());
}

std::vector<Vec3> MeshDeformation::take_mean_load() {
  std::vector<Vec3> mean = load;
  if (impulse_time > 0)
    for (std::size_t i = 0; i < mean.size(); ++i) mean[i] = impulse[i] / impulse_time;
  std::fill(impulse.begin(), impulse.end(), Vec3::Zero());
  impulse_time = 0;
  return mean;
}

MeshBody MeshBody::from_world_mesh(std::string name, const TriangleMesh& mesh, int material,
                                   double density, const Vec3& reference) {
  MeshBody b;
  b.name = std::move(name);
  b.material = material;
  b.x = reference;
  if (density > 0) {
    if (!mesh.is_closed())
      throw InputError("mesh '" + b.name +
                       "': a body with density needs a closed mesh (every edge shared by two "
                       "consistently oriented triangles); this one is open");
    const MeshMassProperties mp = closed_mesh_mass_properties(mesh);
    b.x = mp.centroid;
    b.mass = density * mp.volume;
    b.inertia = density * mp.inertia;
  }
  b.local = mesh;
  for (auto& p : b.local.vertices) p -= b.x;
  b.world = mesh;
  return b;
}

}  // namespace trackbed::dem
