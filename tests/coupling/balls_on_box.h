// The bed of the coupling tests: the 4 x 4 x 4 elastic box of elastic_box.h, solved directly,
// its top a deformable DEM wall carrying a 5 x 5 layer of frictionless balls, 40 mm apart (they
// do not touch each other), each set down with the overlap of its weight. No ball sits on an
// edge of the wall's triangles: where the wall sags there, the edge turns concave and the ball
// would touch both faces (dem/engine/mesh_contact.h: one contact per face at a concave edge),
// its contact doubling at once.
#pragma once

#include <cmath>
#include <memory>
#include <vector>

#include "coupling/interface_wall.h"
#include "dem/engine/mesh_body.h"
#include "dem/engine/simulation.h"
#include "elastic_box.h"
#include "fem/boundary_interface.h"
#include "fem/elastic_body.h"

namespace trackbed::coupling::testing {

// The 4 x 4 x 4 box, solved directly.
inline std::unique_ptr<fem::ElasticBody> box() {
  fem::SolverParameters solver;
  solver.method = fem::SolverParameters::Method::direct;
  return testing::elastic_box(MPI_COMM_WORLD, {{4, 4, 4}}, 0, solver);
}

// The area mean of u_z over the top: the three edge-midpoint rule on each interface triangle,
// exact for the bilinear field a trilinear element has on a flat face.
inline double mean_top_settlement(const fem::BoundaryInterface& top) {
  double integral = 0, area = 0;
  const auto& triangles = top.triangles();
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const std::vector<fem::TrianglePoint> midpoints = {
        {t, {{0.5, 0.5, 0}}}, {t, {{0, 0.5, 0.5}}}, {t, {{0.5, 0, 0.5}}}};
    for (const auto& m : top.motion(midpoints)) integral += m[0][2] * triangles[t].area / 3;
    area += triangles[t].area;
  }
  return -integral / area;
}

// A 5 x 5 layer of frictionless balls, 40 mm apart (they do not touch each other), each set
// down with the overlap of its weight, on the box's top made a deformable DEM wall.
struct BallsOnBox {
  std::unique_ptr<fem::ElasticBody> body = box();
  fem::BoundaryInterface top{*body, "zmax"};
  InterfaceWall wall{top, "zmax", MPI_COMM_WORLD};
  std::unique_ptr<dem::Simulation> sim;
  int mesh = -1;
  double weight = 0;

  explicit BallsOnBox(double damping_ratio = 0.9) {
    dem::Material stone;
    stone.name = "stone";
    stone.density = 2650;
    stone.normal_stiffness = stone.shear_stiffness = 2e6;  // 1e6 N/m per contact in series
    stone.friction = 0;
    stone.normal_damping_ratio = damping_ratio;
    dem::MaterialTable materials;
    materials.add(stone);
    const double r = 0.019, mass = 4.0 / 3.0 * M_PI * r * r * r * stone.density;
    dem::Particles balls;
    for (int i = 0; i < 5; ++i)
      for (int j = 0; j < 5; ++j)
        balls.add_ball(dem::Vec3(0.022 + 0.04 * i, 0.019 + 0.04 * j, r - mass * 9.81 / 1e6), r, 0,
                       stone.density, 5 * i + j);
    weight = 25 * mass * 9.81;
    dem::SimulationSettings settings;
    settings.time_step = 1e-5;  // 0.04 of sqrt(m / k)
    sim = std::make_unique<dem::Simulation>(materials, std::move(balls), settings);
    dem::MeshBody floor =
        dem::MeshBody::from_world_mesh("zmax", wall.mesh(), 0, 0, dem::Vec3::Zero());
    floor.make_deformable();
    mesh = sim->add_mesh_body(std::move(floor));
    sim->setup();
  }
  // F H / (M A): the area-mean settlement of the top under the total vertical load F.
  static double settlement_of(double load) {
    return load * kHeight / (kSoil.constrained_modulus() * kSide * kSide);
  }
};

}  // namespace trackbed::coupling::testing
