#include "cloth_hair_sim/core/mesh/vertex_selection.h"

#include "cloth_hair_sim/core/mesh/boundary_edges.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <utility>

namespace chs {

std::vector<int> verticesOnPlane(const QuadMesh& mesh, int axis, double value, double tolerance) {
  std::vector<int> out;
  for (int v = 0; v < mesh.numVertices(); ++v)
    if (std::abs(mesh.vertices[v][axis] - value) <= tolerance) out.push_back(v);
  return out;
}

std::vector<int> verticesInBox(const QuadMesh& mesh, const Eigen::Vector3d& lo,
                               const Eigen::Vector3d& hi) {
  std::vector<int> out;
  for (int v = 0; v < mesh.numVertices(); ++v) {
    const auto& p = mesh.vertices[v];
    if ((p.array() >= lo.array()).all() && (p.array() <= hi.array()).all()) out.push_back(v);
  }
  return out;
}

int nearestVertex(const QuadMesh& mesh, const Eigen::Vector3d& point) {
  int best = -1;
  double best_d = std::numeric_limits<double>::infinity();
  for (int v = 0; v < mesh.numVertices(); ++v) {
    const double d = (mesh.vertices[v] - point).squaredNorm();
    if (d < best_d) best_d = d, best = v;
  }
  return best;
}

std::vector<int> boundaryVertices(const QuadMesh& mesh) {
  std::set<int> out;
  for (const auto& [a, b] : boundaryEdges(mesh)) out.insert({a, b});
  return {out.begin(), out.end()};
}

}  // namespace chs
