#include "cloth_hair_sim/core/material/shell_material.h"

#include <cmath>
#include <sstream>

#include "cloth_hair_sim/core/common/input_error.h"

namespace chs {

namespace {
double polynomial(const std::array<double, 5>& a, double k) {
  return k * (a[0] + k * (a[1] + k * (a[2] + k * (a[3] + k * a[4]))));
}
double polynomialSlope(const std::array<double, 5>& a, double k) {
  return a[0] + k * (2 * a[1] + k * (3 * a[2] + k * (4 * a[3] + k * 5 * a[4])));
}
}  // namespace

double KawabataBending::moment(double k) const {
  const double kf = std::abs(k) * curvature_to_fit;
  const double m = kf <= k_max ? polynomial(a, kf)
                               : polynomial(a, k_max) + polynomialSlope(a, k_max) * (kf - k_max);
  return std::copysign(m * fit_to_moment, k);  // odd symmetry M(-K) = -M(K)
}

double KawabataBending::stiffness(double k) const {
  const double kf = std::min(std::abs(k) * curvature_to_fit, k_max);
  return polynomialSlope(a, kf) * fit_to_moment * curvature_to_fit;
}

void ShellMaterial::validate() const {
  std::ostringstream err;
  if (!std::isfinite(young) || young <= 0.0)
    err << "Young's modulus E = " << young << " must be positive";
  else if (!std::isfinite(poisson) || poisson < 0.0 || poisson >= 0.5)
    err << "Poisson's ratio nu = " << poisson << " must lie in [0, 0.5)";
  else if (!std::isfinite(thickness) || thickness <= 0.0)
    err << "thickness h = " << thickness << " must be positive";
  else if (!std::isfinite(areal_density) || areal_density < 0.0)
    err << "areal density = " << areal_density << " must not be negative";
  else if (!std::isfinite(shear_correction) || shear_correction <= 0.0)
    err << "shear correction factor = " << shear_correction << " must be positive";
  else if (kawabata) {
    for (double k = 0.0; k <= kawabata->k_max; k += kawabata->k_max / 200.0)
      if (polynomialSlope(kawabata->a, k) <= 0.0) {
        err << "Kawabata bending fit is not increasing at K = " << k << " (fit units)";
        break;
      }
  }
  if (!err.str().empty()) throw InputError("material: " + err.str());
}

}  // namespace chs
