#pragma once
#include <string>
#include <vector>

#include <Eigen/Core>

#include "cloth_hair_sim/core/mesh/quad_mesh.h"

namespace chs {

// Write the quads of mesh at the given positions (a deformed state; same count as
// mesh.vertices), keeping the quads as quads. Throws InputError if the file cannot be written.
void writeObj(const std::string& path, const QuadMesh& mesh,
              const std::vector<Eigen::Vector3d>& positions);
void writePly(const std::string& path, const QuadMesh& mesh,
              const std::vector<Eigen::Vector3d>& positions);

// The mesh in its own (reference) configuration.
inline void writeObj(const std::string& path, const QuadMesh& mesh) {
  writeObj(path, mesh, mesh.vertices);
}
inline void writePly(const std::string& path, const QuadMesh& mesh) {
  writePly(path, mesh, mesh.vertices);
}

}  // namespace chs
