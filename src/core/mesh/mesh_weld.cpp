#include "cloth_hair_sim/core/mesh/mesh_weld.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace chs {

namespace {

template <class Faces>
void weld(std::vector<Eigen::Vector3d>& mesh_vertices, Faces& faces, double tolerance) {
  const int n = static_cast<int>(mesh_vertices.size());
  // Sort by x, then compare only within the tolerance window: O(n log n) for sheet-like meshes.
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(),
            [&](int a, int b) { return mesh_vertices[a].x() < mesh_vertices[b].x(); });
  std::vector<int> representative(n);
  std::iota(representative.begin(), representative.end(), 0);
  for (int s = 0; s < n; ++s) {
    const int a = order[s];
    if (representative[a] != a) continue;
    for (int t = s + 1; t < n; ++t) {
      const int b = order[t];
      if (mesh_vertices[b].x() - mesh_vertices[a].x() > tolerance) break;
      if (representative[b] == b && (mesh_vertices[b] - mesh_vertices[a]).norm() <= tolerance)
        representative[b] = a;
    }
  }
  // Keep used representatives only, in order of first appearance of their original index.
  std::vector<int> used(n, 0);
  for (const auto& q : faces)
    for (int v : q)
      if (v >= 0 && v < n) used[representative[v]] = 1;
  std::vector<int> new_index(n, -1);
  std::vector<Eigen::Vector3d> vertices;
  for (int v = 0; v < n; ++v)
    if (used[v]) {
      new_index[v] = static_cast<int>(vertices.size());
      vertices.push_back(mesh_vertices[v]);
    }
  for (auto& q : faces)
    for (int& v : q)
      if (v >= 0 && v < n) v = new_index[representative[v]];
  mesh_vertices = std::move(vertices);
}

}  // namespace

void weldVertices(QuadMesh& mesh, double tolerance) {
  weld(mesh.vertices, mesh.quads, tolerance);
}

void weldVertices(PolygonMesh& mesh, double tolerance) {
  weld(mesh.vertices, mesh.faces, tolerance);
}

}  // namespace chs
