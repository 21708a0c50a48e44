#pragma once
#include <optional>

#include "cloth_hair_sim/node/garment.h"
#include "cloth_hair_sim/node/sim_params.h"

namespace chs_node {

// A live change of a garment's material (dynamic_reconfigure): the fields that are set change.
struct MaterialChange {
  std::optional<double> young, poisson, thickness, areal_density, self_friction;
};

// Applies the change to a loaded garment in its current state. Neither backend can change its
// material in place (masses, stiffnesses, quadrature and stability bounds all derive from it),
// so the dynamics are re-created from the garment's reference with the new material and given
// the current positions and velocities; world pins keep their targets, frame pins are
// re-pinned where their frames are (colliders and grasps are the caller's). Lost: the hybrid
// shell's contact fibres restart unstressed and its plastic strain (~mpm/yield_stress) is reset.
// The reference keeps the new material, so ~reset and ~drape_solve use it too. Throws
// chs::InputError naming the bad value (the garment is then unchanged).
void changeMaterial(Garment& garment, const MaterialChange& change, const SimParams& params);

}  // namespace chs_node
