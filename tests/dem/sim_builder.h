// Small builders shared by the DEM tests: a one-material model and helpers to run it.
#pragma once

#include <utility>

#include "dem/engine/simulation.h"

namespace trackbed::dem::testing {

inline Material test_material(double k = 1e6, double mu = 0.5, double mu_roll = 0,
                              double damping_ratio = 0, double density = 2800) {
  Material m;
  m.name = "test";
  m.density = density;
  // Entity stiffnesses combine in series: twice the value gives k for a pair of equals.
  m.normal_stiffness = 2 * k;
  m.shear_stiffness = 2 * k;
  m.friction = mu;
  m.rolling_friction = mu_roll;
  m.normal_damping_ratio = damping_ratio;
  return m;
}

// A table with one material whose every pair (particle-particle and particle-wall) has exactly
// the given properties.
inline MaterialTable table_with_pair(const Material& m, double k) {
  MaterialTable t;
  t.add(m);
  ContactProperties p;
  p.kn = p.ks = k;
  p.mu = m.friction;
  p.mu_roll = m.rolling_friction;
  p.normal_damping_ratio = m.normal_damping_ratio;
  p.shear_damping_ratio = m.shear_damping_ratio;
  t.set_pair(0, 0, p);
  return t;
}

inline PlaneWall floor_at(double z, int material = 0) {
  PlaneWall w;
  w.name = "floor";
  w.point = Vec3(0, 0, z);
  w.normal = Vec3::UnitZ();
  w.material = material;
  return w;
}

// A floor at z = 0 and four side walls bounding [0, size]^2 (planes 1..4: x = 0, y = 0,
// x = size, y = size); the x = size wall moves at `far_x_velocity`.
inline void add_open_box(Simulation& sim, double size, const Vec3& far_x_velocity = Vec3::Zero()) {
  sim.add_plane(floor_at(0));
  for (auto [at, n] : {std::pair{0.0, 1.0}, {size, -1.0}}) {
    PlaneWall w;
    w.name = "x";
    w.point = Vec3(at, 0, 0);
    w.normal = Vec3(n, 0, 0);
    if (at > 0) w.velocity = far_x_velocity;
    sim.add_plane(w);
    w.name = "y";
    w.point = Vec3(0, at, 0);
    w.normal = Vec3(0, n, 0);
    w.velocity = Vec3::Zero();
    sim.add_plane(w);
  }
}

inline void run_for(Simulation& sim, double t) {
  const long n = static_cast<long>(std::llround(t / sim.time_step()));
  for (long i = 0; i < n; ++i) sim.step();
}

}  // namespace trackbed::dem::testing
