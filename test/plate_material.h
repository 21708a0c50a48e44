#pragma once
#include "cloth_hair_sim/core/material/shell_material.h"

namespace chs::fixtures {

// An isotropic plate of Young's modulus E, Poisson's ratio nu and thickness h (unit areal
// density): the material of the solid-shell element tests.
inline ShellMaterial plate(double E, double nu, double h) {
  ShellMaterial m;
  m.young = E;
  m.poisson = nu;
  m.thickness = h;
  m.areal_density = 1.0;
  return m;
}

}  // namespace chs::fixtures
