#pragma once
#include "cloth_hair_sim/core/mesh/quad_mesh.h"

namespace chs {

// Rejects a mesh no solver can use, throwing InputError that names the first offending vertex or
// element: empty mesh, NaN/Inf coordinates, corner indices out of range or repeated, degenerate
// (zero-area) or inverted quads (orientation inconsistent with the neighbours), and non-manifold
// edges (shared by more than two quads).
void checkMesh(const QuadMesh& mesh);

}  // namespace chs
