// The elastic box of the coupling tests: [0, a]^2 x [-H, 0], a = H = 0.2 m, E 100 MPa, nu 0.3,
// trilinear cells, rollers on its four sides, fixed at its base, no gravity (its displacements
// are those the interface loads cause: the geostatic state, measured from, is the origin of the
// coupling's displacements). Its top, boundary "zmax", is the interface.
#pragma once

#include <array>
#include <memory>

#include "fem/elastic_body.h"
#include "fem/material.h"

namespace trackbed::coupling::testing {

constexpr double kSide = 0.2, kHeight = 0.2;  // m
inline const fem::Material kSoil{"soil", 1e8, 0.3, 1900};

// `cells` coarse cells per direction, refined `refinements` times; set up with `solver`. Another
// `height` and `material` make a slab of the same plan and boundary conditions.
inline std::unique_ptr<fem::ElasticBody> elastic_box(MPI_Comm communicator,
                                                     const std::array<unsigned int, 3>& cells,
                                                     unsigned int refinements,
                                                     const fem::SolverParameters& solver,
                                                     double height = kHeight,
                                                     const fem::Material& material = kSoil) {
  auto body = std::make_unique<fem::ElasticBody>(1, communicator);
  body->make_box({{{0, 0, -height}}, {{kSide, kSide, 0}}, cells, {}});
  if (refinements > 0) body->refine_globally(refinements);
  body->set_material(0, material);
  body->set_gravity({{0, 0, 0}});
  body->fix(body->boundary_id("zmin"));
  for (const char* side : {"xmin", "xmax"})
    body->fix(body->boundary_id(side), {{true, false, false}});
  for (const char* side : {"ymin", "ymax"})
    body->fix(body->boundary_id(side), {{false, true, false}});
  body->set_solver(solver);
  body->setup();
  return body;
}

}  // namespace trackbed::coupling::testing
