#include "cloth_hair_sim/core/rod/rod_material.h"

#include <cmath>
#include <sstream>

#include "cloth_hair_sim/core/common/input_error.h"

namespace chs::rod {
namespace {

std::string str(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

void checkRange(const std::string& who, const char* name, double v, double hi, const char* unit) {
  if (!(v > 0.0 && v <= hi))
    throw InputError(who + ": " + name + " must lie in (0, " + str(hi) + "] " + unit + ", got " +
                     str(v));
}

}  // namespace

double RodMaterial::area() const {
  return M_PI * radius_1 * semiAxis2();
}

double RodMaterial::stretchingStiffness() const {
  return youngs_modulus * area();
}

double RodMaterial::bendingStiffness1() const {
  return youngs_modulus * M_PI * std::pow(radius_1, 3) * semiAxis2() / 4.0;
}

double RodMaterial::bendingStiffness2() const {
  return youngs_modulus * M_PI * radius_1 * std::pow(semiAxis2(), 3) / 4.0;
}

double RodMaterial::twistingStiffness() const {
  const double a = radius_1, b = semiAxis2();
  return shear_modulus * M_PI * std::pow(a * b, 3) / (a * a + b * b);
}

double RodMaterial::linearDensity() const {
  return density * area();
}

double RodMaterial::polarInertiaPerLength() const {
  const double a = radius_1, b = semiAxis2();
  return density * M_PI * a * b * (a * a + b * b) / 4.0;
}

void checkRodMaterial(const RodMaterial& m, const std::string& who) {
  checkRange(who, "Young's modulus", m.youngs_modulus, 1e13, "Pa");
  checkRange(who, "shear modulus", m.shear_modulus, 1e13, "Pa");
  checkRange(who, "radius", m.radius_1, 0.1, "m");
  if (m.radius_2 != 0.0) {
    checkRange(who, "second semi-axis", m.radius_2, 0.1, "m");
    const double ratio = m.radius_2 / m.radius_1;
    if (!(ratio >= 1e-3 && ratio <= 1e3))
      throw InputError(who + ": section semi-axes " + str(m.radius_1) + " m and " +
                       str(m.radius_2) + " m differ by more than 1000 times");
  }
  checkRange(who, "density", m.density, 1e5, "kg/m^3");
}

RodMaterial humanHair(double ellipticity) {
  if (!(ellipticity > 0.0 && ellipticity <= 1.0))
    throw InputError("human hair: ellipticity b / a must lie in (0, 1], got " + str(ellipticity));
  constexpr double kRadius = 40e-6;
  RodMaterial m;
  m.youngs_modulus = 3.5e9;
  m.shear_modulus = 0.89e9;
  m.density = 1300.0;
  // Same area as the round fibre: a b = r^2.
  m.radius_1 = kRadius / std::sqrt(ellipticity);
  m.radius_2 = kRadius * std::sqrt(ellipticity);
  return m;
}

}  // namespace chs::rod
