#pragma once
#include <string>

#include "cloth_hair_sim/core/rod/groom.h"

namespace chs {

// Strands from a PLY file of vertices and edges (what the simulate tool writes for hair, and
// Blender or MeshLab export for curves): ascii or binary_little_endian; `vertex` with x, y, z
// (float or double, other properties skipped), `edge` with vertex1, vertex2 (any integer type).
// Each strand is a chain of edges, read from its lower-numbered end (the simulate tool writes
// roots first). Throws InputError naming the file and the problem: a header that is not PLY,
// big-endian data, faces (a mesh, not strands), an edge out of range, a vertex on more than two
// edges (a branch), a closed loop, or data shorter than the header says. Private to the core
// (io/strand_file.cpp reads .ply through it).
rod::Polylines readStrandPly(const std::string& path, const std::string& bytes);

}  // namespace chs
