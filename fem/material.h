// Isotropic linear elastic materials of the continuum layers and of the sleeper.
#pragma once

#include <string>

namespace trackbed::fem {

struct Material {
  std::string name;       // used in messages and output, e.g. "subgrade"
  double youngs_modulus;  // E, Pa
  double poisson_ratio;   // nu, -1 < nu < 0.5
  double density;         // rho, kg/m^3

  // Throws InputError naming `where` (e.g. "material 2") unless E > 0, rho > 0, -1 < nu < 0.5.
  void validate(const std::string& where) const;

  // Lame's first parameter lambda = E nu / ((1 + nu)(1 - 2 nu)), Pa.
  double lame_lambda() const;
  // Shear modulus mu = G = E / (2 (1 + nu)), Pa.
  double shear_modulus() const;
  // Constrained (oedometric, P-wave) modulus lambda + 2 mu, Pa.
  double constrained_modulus() const;
  // Body-wave speeds c_p = sqrt((lambda + 2 mu) / rho) and c_s = sqrt(mu / rho), m/s.
  double p_wave_speed() const;
  double s_wave_speed() const;
};

// Typical properties of the track-bed layers (Selig & Waters, "Track Geotechnology and Substructure
// Management", 1994, ch. 8; Powrie & Le Pen, "A Guide to Track Stiffness", 2016). They are
// defaults for cases, not calibrated values.
Material lower_ballast_equivalent();  // E 150 MPa, nu 0.25, 1700 kg/m^3
Material sub_ballast();               // E 120 MPa, nu 0.30, 2000 kg/m^3
Material subgrade_fill();             // E 60 MPa, nu 0.35, 1900 kg/m^3
Material natural_ground();            // E 40 MPa, nu 0.35, 1850 kg/m^3
// Prestressed concrete of a monoblock sleeper (B70): E 35 GPa, nu 0.2, 2450 kg/m^3.
Material sleeper_concrete();

}  // namespace trackbed::fem
