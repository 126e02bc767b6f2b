// The parameters of a coupled run, as plain data (the case file's `coupling` and `fem`
// subsections set them; docs/user-guide.md lists them with their defaults).
#pragma once

#include "common/track_section.h"
#include "fem/elastic_body.h"
#include "fem/material.h"

namespace trackbed::coupling {

// The quasi-static staggered scheme (quasi_static_scheme.h).
struct QuasiStaticParameters {
  int interval_steps = 1000;  // DEM steps per exchange, >= 1
  double relaxation = 0.5;    // the first (or, without Aitken, every) relaxation factor, (0, 1]
  bool aitken = true;         // Aitken's dynamic relaxation after the ramp
  double tolerance = 1e-2;    // converged at |F . r| <= tolerance |F . u~| (the load's work)
  int ramp_exchanges = 5;     // the load reaches its full value at this exchange, >= 1
  // Throws InputError naming the parameter for a value outside its range.
  void validate() const;
};

// The dynamic staggered scheme (dynamic_scheme.h).
struct DynamicParameters {
  int interval_steps = 10;        // DEM steps per FE (Newmark) step, >= 1
  int ramp_exchanges = 1;         // the load reaches its full value at this exchange, >= 1
  double rayleigh_mass = 0;       // alpha of the FE body's damping C = alpha M + beta K, 1/s
  double rayleigh_stiffness = 0;  // beta, s
  // Throws InputError naming the parameter for a value outside its range.
  void validate() const;
};

// The elastic subgrade under the ballast (subgrade.h).
struct SubgradeParameters {
  // The continuum layers: only the continuum fields of this section are used (lower ballast and
  // sub-ballast thickness, embankment height and slope, ground depth and half-width); the ballast
  // bed's fields come from the DEM sample.
  TrackSection layers;
  unsigned int degree = 1;    // FE_Q degree, 1 or 2
  double element_size = 0.2;  // m, in the embankment (twice that in the ground beside it)
  fem::Material sub_ballast = fem::sub_ballast();
  fem::Material subgrade = fem::subgrade_fill();
  fem::Material ground = fem::natural_ground();
  fem::Material lower_ballast = fem::lower_ballast_equivalent();  // where the section has one
  // One sparse LU factorisation, then a back-substitution per exchange: far cheaper than an
  // iterative solve each time for the subgrade's few thousand cells.
  fem::SolverParameters solver{fem::SolverParameters::Method::direct, 1e-10, 2000};
};

}  // namespace trackbed::coupling
