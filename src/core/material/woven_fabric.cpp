#include "cloth_hair_sim/core/material/woven_fabric.h"

#include <cmath>

#include "cloth_hair_sim/core/common/input_error.h"

namespace chs {

namespace {
constexpr double kGramForce = 9.80665e-3;  // N

void positive(double v, const char* name, const char* unit) {
  if (!(v > 0.0) || !std::isfinite(v))
    throw InputError(std::string("woven fabric: ") + name + " must be positive (" + unit +
                     "), got " + std::to_string(v));
}
}  // namespace

void WovenFabric::validate() const {
  positive(tensile_warp, "tensile_warp", "N/m");
  positive(tensile_weft, "tensile_weft", "N/m");
  positive(shear, "shear", "N/m");
  positive(bending_warp, "bending_warp", "N m");
  positive(bending_weft, "bending_weft", "N m");
  positive(thickness, "thickness", "m");
  if (!(areal_density >= 0.0) || !std::isfinite(areal_density))
    throw InputError("woven fabric: areal_density must not be negative (kg/m^2)");
  // Positive definite plane-stress law: nu_12 nu_21 = nu_12^2 E2 / E1 < 1.
  if (!(poisson >= 0.0) || !(poisson * poisson * tensile_weft / tensile_warp < 1.0))
    throw InputError("woven fabric: poisson must satisfy 0 <= nu_12 < sqrt(E1 / E2), got " +
                     std::to_string(poisson));
  if (!warp.allFinite() || !(warp.norm() > 0.0))
    throw InputError(
        "woven fabric: the warp direction is missing (an orthotropic fabric needs the direction "
        "of its warp yarns in the flat garment, e.g. warp: [1, 0, 0])");
}

Eigen::Matrix3d WovenFabric::membraneRigidity() const {
  const double nu21 = poisson * tensile_weft / tensile_warp, det = 1.0 - poisson * nu21;
  Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
  C(0, 0) = tensile_warp / det;
  C(1, 1) = tensile_weft / det;
  C(0, 1) = C(1, 0) = poisson * tensile_weft / det;
  C(2, 2) = shear;
  return C;
}

Eigen::Matrix3d WovenFabric::bendingRigidity() const {
  const double mean = std::sqrt(bending_warp * bending_weft);
  Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
  C(0, 0) = bending_warp;
  C(1, 1) = bending_weft;
  C(0, 1) = C(1, 0) = poisson * mean;
  C(2, 2) = 0.5 * (1.0 - poisson) * mean;
  return C;
}

double WovenFabric::transverseShearRigidity() const {
  const double young = 12.0 * std::sqrt(bending_warp * bending_weft) / std::pow(thickness, 3);
  return 5.0 / 6.0 * young * thickness / (2.0 * (1.0 + poisson));
}

double WovenFabric::thicknessRigidity() const {
  return 12.0 * std::sqrt(bending_warp * bending_weft) / (thickness * thickness);
}

std::optional<WovenFabric> wovenFabricPreset(const std::string& name) {
  if (name != "wool_suiting_kes") return std::nullopt;
  WovenFabric f;
  const double bending = kGramForce * 1e-4 / 1e-2;      // 1 gf cm^2/cm in N m
  const double shear = kGramForce / 1e-2 * 180 / M_PI;  // 1 gf/(cm deg) in N/m per rad
  f.bending_warp = 0.10 * bending;
  f.bending_weft = 0.08 * bending;
  f.shear = 0.6 * shear;
  f.tensile_warp = 500.0 * kGramForce / 1e-2 / 0.04;  // 500 gf/cm at EMT = 4 %
  f.tensile_weft = 0.8 * f.tensile_warp;
  f.poisson = 0.3;
  f.thickness = 0.8e-3;
  f.areal_density = 22e-6 / 1e-4;  // mg/cm^2 -> kg/m^2
  return f;
}

std::vector<std::string> wovenFabricPresetNames() {
  return {"wool_suiting_kes"};
}

}  // namespace chs
