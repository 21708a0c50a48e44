#include "cloth_hair_sim/core/mesh/boundary_edges.h"

#include <algorithm>
#include <map>
#include <utility>

namespace chs {

std::vector<std::array<int, 2>> boundaryEdges(const QuadMesh& mesh) {
  struct Use {
    int count = 0;
    std::array<int, 2> directed{};
  };
  std::map<std::pair<int, int>, Use> uses;
  for (const auto& q : mesh.quads)
    for (int k = 0; k < 4; ++k) {
      const int a = q[k], b = q[(k + 1) % 4];
      Use& u = uses[{std::min(a, b), std::max(a, b)}];
      ++u.count;
      u.directed = {a, b};
    }
  std::vector<std::array<int, 2>> edges;
  for (const auto& [key, u] : uses)
    if (u.count == 1) edges.push_back(u.directed);
  return edges;
}

}  // namespace chs
