#pragma once
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace chs {

// Orthotropic woven fabric, given by its rigidities per unit width as fabric testing measures
// them (Kawabata KES-F: tensile, shear and bending rigidities along warp and weft), in SI.
// Seed 001 (section 3) drapes a wool whose warp is stiffer than its weft in bending: its
// adaptive refinement "is firstly activated along the weft direction due to the smaller bending
// rigidity". The warp direction is part of the material: without it the rigidities mean nothing.
struct WovenFabric {
  double tensile_warp = 0.0;   // E1 h [N/m]
  double tensile_weft = 0.0;   // E2 h [N/m]
  double poisson = 0.0;        // nu_12 (warp strain -> weft contraction); nu_21 = nu_12 E2 / E1
  double shear = 0.0;          // in-plane shear rigidity G12 h [N/m]
  double bending_warp = 0.0;   // B1 [N m]: moment per width bending the warp yarns
  double bending_weft = 0.0;   // B2 [N m]
  double thickness = 0.0;      // h [m]
  double areal_density = 0.0;  // [kg/m^2]
  // Warp direction in the garment's reference (flat) state; it is projected onto each element's
  // plane. Zero = not given.
  Eigen::Vector3d warp = Eigen::Vector3d::Zero();

  // Throws InputError naming the parameter that makes no sense, including a missing or
  // non-finite warp direction.
  void validate() const;

  // Plane-stress rigidities in the (warp, weft) frame, Voigt order (xx, yy, xy with engineering
  // shear strain). Membrane [N/m]: the orthotropic law with nu_21 E1 = nu_12 E2.
  Eigen::Matrix3d membraneRigidity() const;
  // Bending [N m]: diag(B1, B2) coupled by nu_12 sqrt(B1 B2), and twisting (1 - nu_12)
  // sqrt(B1 B2) / 2, which is the isotropic plate's D (1 - nu) / 2 when B1 = B2 = D. KES does
  // not measure twisting; this geometric-mean closure is documented, not measured.
  Eigen::Matrix3d bendingRigidity() const;
  // Transverse shear [N/m] and thickness stretch [N/m] are not measured either: those of a
  // homogeneous plate of the same mean bending rigidity (E_b = 12 sqrt(B1 B2) / h^3) with shear
  // correction 5/6 keep the shell thin (shear deflection < 0.1 % for span / h > 50).
  double transverseShearRigidity() const;
  double thicknessRigidity() const;
};

// Named woven fabrics (the warp direction comes from the scene):
//  wool_suiting_kes: a wool suiting with typical KES-F values, not one cited measurement (no KES
//    table of a specific suiting, nor seed 001's Table 1 after Kang and Yu 1995, could be found):
//    B, G, W and h from the KES-F wool-suiting ranges of the project's reference notes
//    (shared/reference/benchmarks.md, seed 001 section): B1 = 0.10 and B2 = 0.08 gf cm^2/cm
//    (warp stiffer than weft, ratio chosen), G = 0.6 gf/(cm deg), W = 22 mg/cm^2, h = 0.8 mm,
//    nu = 0.3; tensile rigidity as the secant at KES's 500 gf/cm with an assumed EMT of 4 %
//    (1.226e4 N/m warp), weft 0.8 of warp. Conversions: B x 9.80665e-5 -> N m,
//    G x 56.19 -> N/m per rad, W x 0.01 -> kg/m^2.
std::optional<WovenFabric> wovenFabricPreset(const std::string& name);
std::vector<std::string> wovenFabricPresetNames();

}  // namespace chs
