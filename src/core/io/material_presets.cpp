#include "cloth_hair_sim/core/io/material_presets.h"

namespace chs {

namespace {
constexpr double kGramForce = 9.80665e-3;  // N
}  // namespace

std::optional<ShellMaterial> materialPreset(const std::string& name) {
  ShellMaterial m;
  if (name == "cotton_eischen") {
    m.young = 118.1176 * kGramForce / 1e-6;     // gf/mm^2 -> Pa
    m.areal_density = 0.2384e-3 * 1e-3 / 1e-6;  // weight in gf/mm^2 is mass in g/mm^2
    m.thickness = 0.54229e-3;
    m.poisson = 0.3;
    return m;
  }
  if (name == "wool_suiting") {
    const double bending = 0.1 * kGramForce * 1e-4 / 1e-2;  // gf cm^2/cm -> N m
    m.poisson = 0.3;
    m.thickness = 0.8e-3;
    m.areal_density = 22e-6 / 1e-4;  // mg/cm^2 -> kg/m^2
    m.young =
        12.0 * (1.0 - m.poisson * m.poisson) * bending / (m.thickness * m.thickness * m.thickness);
    return m;
  }
  return std::nullopt;
}

std::vector<std::string> materialPresetNames() {
  return {"cotton_eischen", "wool_suiting"};
}

}  // namespace chs
