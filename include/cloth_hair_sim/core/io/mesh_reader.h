#pragma once
#include <string>

#include "cloth_hair_sim/core/mesh/quad_mesh.h"

namespace chs {

// Reads a quad mesh through assimp (OBJ, PLY, glTF, DAE, STL, ...): all meshes of the file, node
// transforms applied, positions multiplied by scale, vertices welded by position (formats store
// them per face corner) and unused ones dropped. An all-quad mesh is kept as it is (never
// triangulated); a mesh with triangles or larger polygons takes one Catmull-Clark step, which
// makes it all-quad with the same limit surface (toQuadControlMesh), since the shells are
// quad-based. Throws InputError naming the file and the problem (missing, unreadable, no faces,
// bad mesh).
QuadMesh readQuadMesh(const std::string& path, double scale = 1.0);

}  // namespace chs
