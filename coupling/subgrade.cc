#include "coupling/subgrade.h"

namespace trackbed::coupling {

Subgrade::Subgrade(const TrackSection& section, const SubgradeParameters& p, MPI_Comm communicator)
    : body_(std::make_unique<fem::ElasticBody>(p.degree, communicator)) {
  namespace ids = fem::track_section;
  fem::ElasticBody& body = *body_;
  TrackSection whole = section;
  whole.lower_ballast_thickness = p.layers.lower_ballast_thickness;
  whole.sub_ballast_thickness = p.layers.sub_ballast_thickness;
  whole.embankment_height = p.layers.embankment_height;
  whole.embankment_slope = p.layers.embankment_slope;
  whole.ground_depth = p.layers.ground_depth;
  whole.ground_half_width = p.layers.ground_half_width;
  body.make_track_section(whole, p.element_size);
  body.set_material(ids::sub_ballast_id, p.sub_ballast);
  body.set_material(ids::subgrade_id, p.subgrade);
  body.set_material(ids::ground_id, p.ground);
  if (section.lower_ballast_thickness > 0)
    body.set_material(ids::lower_ballast_id, p.lower_ballast);
  body.set_gravity({{0, 0, 0}});
  body.fix(body.boundary_id("bottom"));
  body.fix(body.boundary_id("ends"), {{false, true, false}});
  body.fix(body.boundary_id("sides"), {{true, false, false}});
  body.set_solver(p.solver);
  body.setup();
  interface_ = std::make_unique<fem::BoundaryInterface>(body, "formation");
  wall_ = std::make_unique<InterfaceWall>(*interface_, "formation", communicator);
}

}  // namespace trackbed::coupling
