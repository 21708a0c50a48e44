#pragma once
#include <vector>

#include <Eigen/Core>

#include "cloth_hair_sim/core/mesh/quad_mesh.h"

namespace chs {

// Vertex selectors for boundary conditions and probes; all return ascending indices.

// Vertices with |x[axis] - value| <= tolerance, e.g. the edge x = -0.1 of a rectangle.
std::vector<int> verticesOnPlane(const QuadMesh& mesh, int axis, double value, double tolerance);

// Vertices inside the axis-aligned box [lo, hi] (inclusive).
std::vector<int> verticesInBox(const QuadMesh& mesh, const Eigen::Vector3d& lo,
                               const Eigen::Vector3d& hi);

// The vertex closest to point (lowest index on ties); -1 for a mesh without vertices.
int nearestVertex(const QuadMesh& mesh, const Eigen::Vector3d& point);

// Vertices on the open boundary (on an edge that only one quad uses).
std::vector<int> boundaryVertices(const QuadMesh& mesh);

}  // namespace chs
