#pragma once
#include "cloth_hair_sim/core/drape/drape_problem.h"

namespace chs {

// The isotropic test cloth of the hybrid shell tests: E = 0.2 MPa, nu = 0.3, 0.5 mm thick,
// 0.2 kg/m^2 unless told otherwise.
inline ShellMaterial testCloth(double young = 2e5, double thickness = 5e-4,
                               double areal_density = 0.2) {
  ShellMaterial m;
  m.young = young;
  m.poisson = 0.3;
  m.thickness = thickness;
  m.areal_density = areal_density;
  return m;
}

}  // namespace chs
