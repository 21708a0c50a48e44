#pragma once
#include <array>
#include <vector>

#include <Eigen/Core>

namespace chs {

// A surface mesh of bilinear quadrilaterals: the control net of the FEM shell and the
// particle network alike. Quads list their corners counter-clockwise seen from the side
// their normal points to.
struct QuadMesh {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<std::array<int, 4>> quads;

  int numVertices() const { return static_cast<int>(vertices.size()); }
  int numQuads() const { return static_cast<int>(quads.size()); }
};

}  // namespace chs
