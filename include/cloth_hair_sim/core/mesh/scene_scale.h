#pragma once
#include "cloth_hair_sim/core/mesh/quad_mesh.h"

namespace chs {

// What a robot scene can hold [m]. Farther out than kMaxSceneCoordinate from the world origin
// (a garment 1e9 m wide, a mesh in mm read as m, a stray pose) doubles lose the micrometres the
// cloth's dynamics resolve, and a sparse grid of such cells is meaningless; quads whose edges are
// shorter than kMinCellEdge (a mesh in m read as mm) would force a step of nanoseconds.
constexpr double kMaxSceneCoordinate = 1000.0;
constexpr double kMinCellEdge = 1e-4;

// Throws InputError naming the vertex (and its coordinate) or the edge (and its length) outside
// these bounds.
void checkSceneScale(const QuadMesh& mesh);

}  // namespace chs
