#pragma once
#include <string>

#include "cloth_hair_sim/GarmentMesh.h"
#include "cloth_hair_sim/core/dynamics/cloth_dynamics.h"

namespace chs_node {

// A garment's state for ~garments/<name>/mesh: its drawn surface and its simulated vertices
// with their velocities (header left for the caller).
cloth_hair_sim::GarmentMesh garmentMeshMessage(const std::string& name,
                                               const chs::ClothDynamics& dynamics,
                                               const chs::DisplaySurface& surface);

}  // namespace chs_node
