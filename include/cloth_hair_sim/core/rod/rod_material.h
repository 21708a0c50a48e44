#pragma once
#include <string>

namespace chs::rod {

// The material and cross-section of a strand, in SI. The section is an ellipse with semi-axis
// radius_1 along the material director m1 and radius_2 along m2 (equal for a round fibre).
// Stiffnesses follow from the section of a homogeneous elastic rod:
//   stretching  EA  = E pi a b,
//   bending     B1  = E pi a^3 b / 4 (curvature kappa_1, about m2), B2 = E pi a b^3 / 4,
//   twisting    GJ  = G pi a^3 b^3 / (a^2 + b^2)   (Saint-Venant torsion of an ellipse),
// with a = radius_1, b = radius_2. For a circle B = E pi r^4 / 4 and GJ = G pi r^4 / 2.
struct RodMaterial {
  double youngs_modulus = 0.0;  // E [Pa]
  double shear_modulus = 0.0;   // G [Pa]
  double radius_1 = 0.0;        // a [m]
  double radius_2 = 0.0;        // b [m]; <= 0: round, b = a
  double density = 0.0;         // rho [kg/m^3]

  double semiAxis2() const { return radius_2 > 0.0 ? radius_2 : radius_1; }
  double area() const;                   // pi a b
  double stretchingStiffness() const;    // EA [N]
  double bendingStiffness1() const;      // B1 [N m^2]
  double bendingStiffness2() const;      // B2 [N m^2]
  double twistingStiffness() const;      // GJ [N m^2]
  double linearDensity() const;          // rho A [kg/m]
  double polarInertiaPerLength() const;  // rho (I1 + I2) = rho pi a b (a^2 + b^2) / 4 [kg m]
  // Poisson's ratio E / 2G - 1 of an isotropic material with these moduli.
  double poissonRatio() const { return youngs_modulus / (2.0 * shear_modulus) - 1.0; }
};

// Throws InputError naming the field unless every value is finite and physical: moduli in
// (0, 1e13] Pa (stiffer than diamond is a unit mistake), radii in (0, 0.1] m (a rod, not a
// beam), density in (0, 1e5] kg/m^3, and a section ratio a / b within 1e-3 to 1e3. `who`
// prefixes the message.
void checkRodMaterial(const RodMaterial& material, const std::string& who = "rod material");

// Human scalp hair at about 65 % relative humidity. Young's modulus 3.5 GPa (wet 1.5-2, dry
// 3.5-4.5 GPa: C. R. Robbins, "Chemical and Physical Behavior of Human Hair", 5th ed.,
// Springer 2012, ch. 9 "Tensile properties"); torsional (shear) modulus 0.89 GPa (Bogaty,
// J. Soc. Cosmet. Chem. 18, 575-589, 1967, "Torsional properties of hair in relation to
// permanent waving"); density 1300 kg/m^3 (Robbins ch. 9, 1.30-1.32 g/cm^3); radius 40 um
// (diameters of 50-100 um, Robbins ch. 1). `ellipticity` b / a: 1 round (Asian hair is close
// to that), about 0.6-0.8 for curly African hair (Robbins ch. 1); the area is kept that of a
// circle of 40 um.
RodMaterial humanHair(double ellipticity = 1.0);

}  // namespace chs::rod
