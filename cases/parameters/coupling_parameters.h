// The case file's `coupling` and `fem` subsections (mode = coupled): declared and read like the
// other subsections of case_parameters.cc, into CaseParameters::coupling and ::subgrade. Includes
// deal.II's ParameterHandler: only for the .cc files that read parameters.
#pragma once

#include <deal.II/base/parameter_handler.h>

#include "cases/parameters/case_parameters.h"
#include "cases/parameters/prm_support.h"

namespace trackbed::cases {

// coupling: the staggered scheme that joins the DEM bed and the FE subgrade.
void declare_coupling(dealii::ParameterHandler& prm);
void parse_coupling(dealii::ParameterHandler& prm, const ParameterSource& in, CaseParameters& c);
// fem: the subgrade's layers, their materials, its elements and solver.
void declare_fem(dealii::ParameterHandler& prm);
void parse_fem(dealii::ParameterHandler& prm, const ParameterSource& in, CaseParameters& c);

}  // namespace trackbed::cases
