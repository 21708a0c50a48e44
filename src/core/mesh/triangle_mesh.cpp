#include "cloth_hair_sim/core/mesh/triangle_mesh.h"

#include <algorithm>
#include <map>
#include <sstream>
#include <string>
#include <utility>

#include "cloth_hair_sim/core/common/input_error.h"

namespace chs {

void checkClosedSurface(const TriangleMesh& mesh) {
  const int nv = mesh.numVertices(), nt = mesh.numTriangles();
  if (nv == 0 || nt == 0)
    throw InputError("triangle mesh is empty: " + std::to_string(nv) + " vertices, " +
                     std::to_string(nt) + " triangles");
  for (int v = 0; v < nv; ++v)
    if (!mesh.vertices[v].allFinite()) {
      std::ostringstream s;
      s << "triangle mesh: vertex " << v << " has a non-finite coordinate ("
        << mesh.vertices[v].transpose() << ")";
      throw InputError(s.str());
    }
  std::map<std::pair<int, int>, int> uses;  // undirected edge -> number of triangles using it
  for (int t = 0; t < nt; ++t) {
    const auto& tri = mesh.triangles[t];
    for (int k = 0; k < 3; ++k) {
      if (tri[k] < 0 || tri[k] >= nv)
        throw InputError("triangle mesh: triangle " + std::to_string(t) + " has corner index " +
                         std::to_string(tri[k]) + " outside [0, " + std::to_string(nv) + ")");
    }
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[2] == tri[0]) continue;  // zero area
    for (int k = 0; k < 3; ++k) {
      const int a = tri[k], b = tri[(k + 1) % 3];
      ++uses[{std::min(a, b), std::max(a, b)}];
    }
  }
  int open = 0;
  std::pair<int, int> first{-1, -1};
  for (const auto& [edge, count] : uses)
    if (count % 2 != 0) {
      if (open++ == 0) first = edge;
    }
  if (open > 0) {
    std::ostringstream s;
    s << "triangle mesh is not closed (not watertight): " << open
      << " edges are used by an odd number of triangles (a hole), the first is edge " << first.first
      << "-" << first.second << " at (" << mesh.vertices[first.first].transpose() << ") - ("
      << mesh.vertices[first.second].transpose() << ")";
    throw InputError(s.str());
  }
}

}  // namespace chs
