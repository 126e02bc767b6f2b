#include "fem/material.h"

#include <cmath>
#include <sstream>

#include "fem/errors.h"

namespace trackbed::fem {

void Material::validate(const std::string& where) const {
  const std::string label = where + (name.empty() ? "" : " ('" + name + "')");
  std::ostringstream message;
  if (!(youngs_modulus > 0.0 && std::isfinite(youngs_modulus)))
    message << label << ": Young's modulus = " << youngs_modulus
            << " Pa is invalid; it must be a finite value > 0";
  else if (!(poisson_ratio > -1.0 && poisson_ratio < 0.5))
    message << label << ": Poisson ratio = " << poisson_ratio
            << " is invalid; valid range is -1 < nu < 0.5 (0.5 is incompressible)";
  else if (!(density > 0.0 && std::isfinite(density)))
    message << label << ": density = " << density
            << " kg/m^3 is invalid; it must be a finite value > 0";
  else
    return;
  throw InputError(message.str());
}

double Material::lame_lambda() const {
  return youngs_modulus * poisson_ratio / ((1.0 + poisson_ratio) * (1.0 - 2.0 * poisson_ratio));
}

double Material::shear_modulus() const {
  return youngs_modulus / (2.0 * (1.0 + poisson_ratio));
}

double Material::constrained_modulus() const {
  return lame_lambda() + 2.0 * shear_modulus();
}

double Material::p_wave_speed() const {
  return std::sqrt(constrained_modulus() / density);
}

double Material::s_wave_speed() const {
  return std::sqrt(shear_modulus() / density);
}

Material lower_ballast_equivalent() {
  return {"lower ballast", 150e6, 0.25, 1700.0};
}
Material sub_ballast() {
  return {"sub-ballast", 120e6, 0.30, 2000.0};
}
Material subgrade_fill() {
  return {"subgrade", 60e6, 0.35, 1900.0};
}
Material natural_ground() {
  return {"ground", 40e6, 0.35, 1850.0};
}
Material sleeper_concrete() {
  return {"sleeper concrete", 35e9, 0.20, 2450.0};
}

}  // namespace trackbed::fem
