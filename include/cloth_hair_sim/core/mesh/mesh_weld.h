#pragma once
#include "cloth_hair_sim/core/mesh/polygon_mesh.h"
#include "cloth_hair_sim/core/mesh/quad_mesh.h"

namespace chs {

// Merges vertices closer than tolerance (absolute, in mesh units) and drops vertices no quad
// uses. File formats and block-structured generators duplicate vertices along seams; the
// solvers need one vertex per material point so that neighbouring quads are connected.
// Quad corners are renumbered; their order (orientation) is kept.
void weldVertices(QuadMesh& mesh, double tolerance);
void weldVertices(PolygonMesh& mesh, double tolerance);

}  // namespace chs
