#pragma once
#include <vector>

#include <Eigen/Core>

namespace chs {

// A mesh of polygons (3 or more corners each, counter-clockwise seen from the normal side),
// e.g. a triangulated garment panel as a file holds it.
struct PolygonMesh {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<std::vector<int>> faces;
};

}  // namespace chs
