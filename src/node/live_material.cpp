#include "cloth_hair_sim/node/live_material.h"

#include <cmath>
#include <utility>

#include "cloth_hair_sim/core/common/input_error.h"

namespace chs_node {

void changeMaterial(Garment& g, const MaterialChange& change, const SimParams& params) {
  Garment next;
  next.name = g.name;
  next.reference = g.reference;
  next.self_friction = g.self_friction;
  chs::ShellMaterial& m = next.reference.material;
  if (change.young) m.young = *change.young;
  if (change.poisson) m.poisson = *change.poisson;
  if (change.thickness) m.thickness = *change.thickness;
  if (change.areal_density) m.areal_density = *change.areal_density;
  m.validate();  // its messages name the field
  if (change.self_friction) {
    if (params.dynamics_backend != "mpm")
      throw chs::InputError("self_friction: the particle backend has no contact between layers");
    if (!(*change.self_friction >= 0.0) || !std::isfinite(*change.self_friction))
      throw chs::InputError("self_friction must be >= 0 and finite");
    next.self_friction = change.self_friction;
  }
  resetDynamics(next, params);
  const chs::ClothDynamics& old = *g.dynamics;
  next.dynamics->setPositions(old.positions());
  next.dynamics->setVelocities(old.velocities());
  for (const auto& a : g.frame_pins) a.pinAt(*next.dynamics, 1.0);

  g.reference = std::move(next.reference);
  g.self_friction = next.self_friction;
  g.dynamics = std::move(next.dynamics);
  g.body = std::move(next.body);  // the caller puts it in the world in place of the old one
  if (g.material_name.find("(reconfigured)") == std::string::npos)
    g.material_name += " (reconfigured)";
}

}  // namespace chs_node
