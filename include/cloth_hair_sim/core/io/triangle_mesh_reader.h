#pragma once
#include <string>
#include <vector>

#include <Eigen/Core>

#include "cloth_hair_sim/core/mesh/triangle_mesh.h"

namespace chs {

// Reads a collider's surface through assimp (STL, OBJ, PLY, DAE, glTF, ...): all meshes of the
// file, node transforms applied, polygons triangulated, positions multiplied component-wise by
// scale (0.001 for a file in mm; URDF allows a scale per axis), and vertices with identical
// coordinates merged, so that a surface stored per face corner (STL) or split into several
// meshes by material becomes one connected surface. Unlike readQuadMesh this keeps triangles,
// which is all a rigid collider needs. Throws InputError naming the file and the problem
// (missing, unreadable, no triangles, non-positive or non-finite scale, a part not in the file).
// parts, when not empty, keeps only the nodes (with their subtrees) and meshes of those names:
// a file may hold open pieces next to a closed body (MakeHuman's eyes beside its skin).
TriangleMesh readTriangleMesh(const std::string& path,
                              const Eigen::Vector3d& scale = Eigen::Vector3d::Ones(),
                              const std::vector<std::string>& parts = {});

}  // namespace chs
