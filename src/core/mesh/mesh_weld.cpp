#include "cloth_hair_sim/core/mesh/mesh_weld.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace chs {

void weldVertices(QuadMesh& mesh, double tolerance) {
  const int n = mesh.numVertices();
  // Sort by x, then compare only within the tolerance window: O(n log n) for sheet-like meshes.
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(),
            [&](int a, int b) { return mesh.vertices[a].x() < mesh.vertices[b].x(); });
  std::vector<int> representative(n);
  std::iota(representative.begin(), representative.end(), 0);
  for (int s = 0; s < n; ++s) {
    const int a = order[s];
    if (representative[a] != a) continue;
    for (int t = s + 1; t < n; ++t) {
      const int b = order[t];
      if (mesh.vertices[b].x() - mesh.vertices[a].x() > tolerance) break;
      if (representative[b] == b && (mesh.vertices[b] - mesh.vertices[a]).norm() <= tolerance)
        representative[b] = a;
    }
  }
  // Keep used representatives only, in order of first appearance of their original index.
  std::vector<int> used(n, 0);
  for (const auto& q : mesh.quads)
    for (int v : q)
      if (v >= 0 && v < n) used[representative[v]] = 1;
  std::vector<int> new_index(n, -1);
  std::vector<Eigen::Vector3d> vertices;
  for (int v = 0; v < n; ++v)
    if (used[v]) {
      new_index[v] = static_cast<int>(vertices.size());
      vertices.push_back(mesh.vertices[v]);
    }
  for (auto& q : mesh.quads)
    for (int& v : q)
      if (v >= 0 && v < n) v = new_index[representative[v]];
  mesh.vertices = std::move(vertices);
}

}  // namespace chs
