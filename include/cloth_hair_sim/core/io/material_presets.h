#pragma once
#include <optional>
#include <string>
#include <vector>

#include "cloth_hair_sim/core/material/shell_material.h"

namespace chs {

// Named fabrics for scene files, in SI (Pa, m, kg/m^2):
//  cotton_eischen: the tablecloth cotton of seed 000 section 4.4: E = 118.1176 gf/mm^2,
//    weight 0.2384e-3 gf/mm^2, h = 0.54229 mm, nu = 0.3, with 1 gf = 9.80665e-3 N (so the
//    areal density is 0.2384 kg/m^2 and the weight is exact under g = 9.80665 m/s^2).
//  wool_suiting: a documented stand-in for seed 001's wool fabric, whose Table 1 is lost
//    (benchmarks.md): typical KES-F wool suiting values B = 0.1 gf cm^2/cm (9.80665e-6 N m),
//    W = 22 mg/cm^2 (0.22 kg/m^2), h = 0.8 mm, nu = 0.3, and E from B = E h^3 / (12 (1 - nu^2)),
//    i.e. E = 2.09e5 Pa.
std::optional<ShellMaterial> materialPreset(const std::string& name);
std::vector<std::string> materialPresetNames();

}  // namespace chs
