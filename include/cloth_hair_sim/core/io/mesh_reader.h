#pragma once
#include <string>

#include "cloth_hair_sim/core/mesh/quad_mesh.h"

namespace chs {

// Reads a quad mesh through assimp (OBJ, PLY, glTF, DAE, STL, ...): all meshes of the file, node
// transforms applied, positions multiplied by scale, vertices welded by position (formats store
// them per face corner) and unused ones dropped. Quads are kept as they are, never
// triangulated; triangles and larger polygons are refused since the FEM shell is quad-based.
// Throws InputError naming the file and the problem (missing, unreadable, no quads, bad mesh).
QuadMesh readQuadMesh(const std::string& path, double scale = 1.0);

}  // namespace chs
