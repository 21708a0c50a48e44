#pragma once
#include <array>
#include <optional>

namespace chs {

// Kawabata moment-curvature fit, seed 000 eq. (15): M = a1 K + ... + a5 K^5, with M the
// moment per unit width and K the curvature, both in the units of the fit. The scales convert
// the model's curvature to the fit's units and the fit's moment back to model units.
// The fit is used on |K| <= k_max (fit units) and continued linearly beyond, odd in K
// (benchmarks.md: the K^5 term dominates past ~2.2 1/cm).
struct KawabataBending {
  std::array<double, 5> a{};
  double curvature_to_fit = 1.0;  // fit K per model curvature unit
  double fit_to_moment = 1.0;     // model moment-per-width per fit moment unit
  double k_max = 2.5;             // fit units

  // Moment per unit width and its derivative for a model curvature k.
  double moment(double k) const;
  double stiffness(double k) const;
};

// Isotropic shell material: seed 000 eqs. (8)-(14). Units are the caller's, consistent
// (SI in scenes: Pa, m, kg/m^2).
struct ShellMaterial {
  double young = 0.0;          // E
  double poisson = 0.0;        // nu, in [0, 0.5)
  double thickness = 0.0;      // h
  double areal_density = 0.0;  // mass per unit mid-surface area (weight = areal_density * g)
  double shear_correction = 5.0 / 6.0;
  std::optional<KawabataBending> kawabata;  // replaces the linear bending law (9) if set

  // Throws InputError naming the parameter that makes no sense.
  void validate() const;

  double membraneStiffness() const { return young * thickness / (1.0 - poisson * poisson); }
  double bendingStiffness() const {  // D = E h^3 / (12 (1 - nu^2))
    return young * thickness * thickness * thickness / (12.0 * (1.0 - poisson * poisson));
  }
  double shearModulus() const { return young / (2.0 * (1.0 + poisson)); }  // (14)
};

}  // namespace chs
