// A rigid body bounded by a triangle mesh (a sleeper, a box, a moving plate): each of its six
// degrees of freedom (translation along and rotation about the world axes, through its reference
// point) is fixed, free, velocity-controlled, force-loaded or servo-controlled.
//
//   fixed     v_k = 0
//   velocity  v_k = value
//   free      m a_k = F_k (+ m g_k)
//   force     m a_k = F_k + value (+ m g_k)
//   servo     v_k = clamp(G (F_k + value), -max_speed, max_speed): the body moves until the
//             contact force balances the applied load `value` (PFC's servo mechanism). With
//             gain 0 the gain is automatic, G = relaxation / (k_k dt) with k_k the contact
//             stiffness summed along DOF k (as PFC does), which converges without overshoot for
//             relaxation < 1; with no contact the body moves at max_speed toward the load.
// F_k is the contact force (or moment about the reference point) the particles exert on the body.
// Free rotations use the world-frame diagonal of the inertia tensor (products of inertia of a
// partly constrained body are neglected; see docs/theory.md).
#pragma once

#include <array>
#include <string>
#include <vector>

#include "dem/engine/triangle_mesh.h"
#include "dem/engine/types.h"

namespace trackbed::dem {

enum class DofMode { fixed, free, velocity, force, servo };

struct DofControl {
  DofMode mode = DofMode::fixed;
  double value = 0;         // velocity (m/s, rad/s) or applied load (N, N m)
  double gain = 0;          // servo gain, (m/s)/N or (rad/s)/(N m); 0: automatic
  double max_speed = 0;     // servo speed limit, m/s or rad/s (0: none; needed for automatic gain)
  double relaxation = 0.5;  // automatic gain: fraction of the force error removed per step
};

// The state of a deformable mesh: one whose vertices are moved from outside (an FE boundary
// under the ballast, coupling/) instead of by a rigid-body motion. Its world vertices move each
// step by their velocities (set with Simulation::set_mesh_vertices, which may also set new
// positions between steps); a contact's wall velocity is interpolated from its triangle's vertex
// velocities with the contact point's barycentric weights, and its force is split to the three
// vertices with the same weights (docs/theory.md, "Deformable mesh walls").
struct MeshDeformation {
  std::vector<Vec3> velocity;  // per vertex, world frame, m/s
  // Per vertex: the particles' contact forces on the mesh in the last force pass, N, split to
  // the vertices by barycentric weights; their sum is the body's contact_force.
  std::vector<Vec3> load;
  // Per vertex: the impulse of `load` summed over the force passes since the last
  // take_mean_load(), N s, and the time it covers, s.
  std::vector<Vec3> impulse;
  double impulse_time = 0;
  std::vector<Vec3> at_build;      // vertex positions at the last neighbour-list build
  std::vector<Vec3> pending_move;  // displacement since the last force pass (wall work)

  // The mean vertex loads over the interval since the last call (the impulses over their time;
  // the last pass's loads if no time has passed), and a new interval begun.
  std::vector<Vec3> take_mean_load();
};

struct MeshBody {
  std::string name;
  TriangleMesh local;  // vertices relative to the reference point, body frame; topology final
  TriangleMesh world;  // same topology, current world vertices (updated every step)
  int material = 0;

  Vec3 x = Vec3::Zero();  // reference point (the centroid for a body made from a closed mesh)
  Quat q = Quat::Identity();
  Vec3 v = Vec3::Zero();
  Vec3 w = Vec3::Zero();
  double mass = 0;                  // kg; needed for free and force DOFs
  Mat3 inertia = Mat3::Identity();  // about x, body frame, kg m^2
  bool weight = false;              // gravity acts on free and force DOFs
  std::array<DofControl, 6> dof{};  // x, y, z, rx, ry, rz

  // Results of the last step: load the particles exert on the body (moment about x), in total
  // and per named part of the mesh.
  Vec3 contact_force = Vec3::Zero(), contact_moment = Vec3::Zero();
  // Contact normal stiffness summed along each translational / rotational DOF (servo gain).
  Vec3 contact_stiffness = Vec3::Zero(), contact_rotational_stiffness = Vec3::Zero();
  std::vector<Vec3> part_force, part_moment;

  // Deformable (make_deformable): the world vertices are the mesh's state; x, q stay fixed and
  // every DOF must be fixed.
  bool deformable = false;
  MeshDeformation deformation;
  // Makes the body deformable, its world vertices as they are now, at rest. Throws InputError
  // naming the body if a DOF is not fixed.
  void make_deformable();

  // Sets world vertices from (x, q).
  void update_world_mesh();
  // Advances the body by one step under its controls; gravity g.
  void integrate(double dt, const Vec3& g);
  // Largest distance of a vertex from the reference point.
  double reach() const;
  // Builds a body from a mesh given in world coordinates. With `density` > 0 the mass, centroid
  // (reference point) and inertia come from the closed mesh; otherwise the reference point is
  // `reference` and mass/inertia must be set by the caller if any DOF needs them.
  static MeshBody from_world_mesh(std::string name, const TriangleMesh& mesh, int material,
                                  double density, const Vec3& reference);
};

}  // namespace trackbed::dem
