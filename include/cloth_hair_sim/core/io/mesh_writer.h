#pragma once
#include <array>
#include <string>
#include <vector>
#include "cloth_hair_sim/core/rod/groom.h"

#include <Eigen/Core>

#include "cloth_hair_sim/core/dynamics/cloth_dynamics.h"
#include "cloth_hair_sim/core/mesh/quad_mesh.h"

namespace chs {

// Write the quads of mesh at the given positions (a deformed state; same count as
// mesh.vertices), keeping the quads as quads. Throws InputError if the file cannot be written.
void writeObj(const std::string& path, const QuadMesh& mesh,
              const std::vector<Eigen::Vector3d>& positions);
void writePly(const std::string& path, const QuadMesh& mesh,
              const std::vector<Eigen::Vector3d>& positions);

// Faces of 3 or 4 corners (a fourth corner of -1 makes a triangle), e.g. an adaptive mesh.
void writeElementsObj(const std::string& path, const std::vector<Eigen::Vector3d>& positions,
                      const std::vector<std::array<int, 4>>& elements);

// The mesh in its own (reference) configuration.
inline void writeObj(const std::string& path, const QuadMesh& mesh) {
  writeObj(path, mesh, mesh.vertices);
}
inline void writePly(const std::string& path, const QuadMesh& mesh) {
  writePly(path, mesh, mesh.vertices);
}

// A dynamics backend's display surface (triangles) as OBJ or ASCII PLY, e.g. one file per frame
// of a sequence. Throws InputError if the file cannot be written.
void writeSurfaceObj(const std::string& path, const DisplaySurface& surface);
void writeSurfacePly(const std::string& path, const DisplaySurface& surface);
// Strands (hair) as polylines: OBJ `l` lines, PLY `edge` elements (Blender and MeshLab read
// both as curves/edges).
void writeStrandsObj(const std::string& path, const rod::Polylines& strands);
void writeStrandsPly(const std::string& path, const rod::Polylines& strands);

}  // namespace chs
