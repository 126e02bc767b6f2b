// The elastic subgrade of a coupled run: the continuum tier of a track section (its layers below
// the formation, fem::ElasticBody::make_track_section) with the boundary conditions of a
// single-sleeper section, and its formation as the DEM's interface wall (docs/coupling.md,
// "The subgrade of a coupled run").
//
//   formation (z = 0)     the interface: loaded by the ballast, moves the DEM wall
//   ends (y = +-L/2)      rollers (u_y = 0): symmetry planes, like the crib walls above them
//   sides (x = +-W)       rollers (u_x = 0): the far field across the track
//   bottom                fixed
//   slopes, ground        free
// The body has no gravity: its displacements are measured from its state under its own weight
// (the geostatic state), which does not move the interface.
#pragma once

#include <mpi.h>

#include <memory>

#include "common/track_section.h"
#include "coupling/interface_wall.h"
#include "coupling/parameters.h"
#include "fem/boundary_interface.h"
#include "fem/elastic_body.h"

namespace trackbed::coupling {

class Subgrade {
 public:
  // Builds the mesh of the continuum layers of parameters.layers under the ballast bed of
  // `section` (a sample's), sets it up and gathers its formation into the interface wall.
  // Collective over `communicator`. Throws InputError for a non-physical section, material or
  // element size.
  Subgrade(const TrackSection& section, const SubgradeParameters& parameters,
           MPI_Comm communicator);

  fem::ElasticBody& body() { return *body_; }
  InterfaceWall& wall() { return *wall_; }
  const InterfaceWall& wall() const { return *wall_; }

 private:
  std::unique_ptr<fem::ElasticBody> body_;
  std::unique_ptr<fem::BoundaryInterface> interface_;
  std::unique_ptr<InterfaceWall> wall_;
};

}  // namespace trackbed::coupling
