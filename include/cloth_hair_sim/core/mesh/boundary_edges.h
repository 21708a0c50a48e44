#pragma once
#include <array>
#include <vector>

#include "cloth_hair_sim/core/mesh/quad_mesh.h"

namespace chs {

// The edges of a quad mesh used by exactly one quad, each directed as its quad runs it
// ({a, b} for a quad corner a followed by b), in increasing order of (min, max) vertex index.
std::vector<std::array<int, 2>> boundaryEdges(const QuadMesh& mesh);

}  // namespace chs
