#include "cloth_hair_sim/core/drape/seam_groups.h"

#include <algorithm>
#include <map>
#include <numeric>
#include <string>

#include "cloth_hair_sim/core/common/input_error.h"

namespace chs {

SeamGroups::SeamGroups(int num_vertices, const std::vector<Seam>& seams) {
  std::vector<int> parent(num_vertices);
  std::iota(parent.begin(), parent.end(), 0);
  auto root = [&parent](int v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  };
  for (std::size_t s = 0; s < seams.size(); ++s) {
    const auto& seam = seams[s];
    const std::string name = "seam " + std::to_string(s);
    if (seam.side_a.size() != seam.side_b.size())
      throw InputError(name + ": its sides have " + std::to_string(seam.side_a.size()) + " and " +
                       std::to_string(seam.side_b.size()) + " vertices; they must match");
    if (seam.side_a.empty()) throw InputError(name + " is empty");
    for (std::size_t i = 0; i < seam.side_a.size(); ++i) {
      const int a = seam.side_a[i], b = seam.side_b[i];
      for (int v : {a, b})
        if (v < 0 || v >= num_vertices)
          throw InputError(name + " names vertex " + std::to_string(v) + ", but the mesh has " +
                           std::to_string(num_vertices) + " vertices");
      if (a == b) throw InputError(name + " sews vertex " + std::to_string(a) + " to itself");
      pairs_.emplace_back(a, b);
      parent[root(a)] = root(b);
    }
  }
  std::map<int, std::vector<int>> by_root;
  for (const auto& [a, b] : pairs_)
    for (int v : {a, b}) by_root[root(v)].push_back(v);
  for (auto& [r, members] : by_root) {
    std::sort(members.begin(), members.end());
    members.erase(std::unique(members.begin(), members.end()), members.end());
    groups_.push_back(members);
  }
}

double SeamGroups::maxGap(const std::vector<Eigen::Vector3d>& x) const {
  double gap = 0.0;
  for (const auto& [a, b] : pairs_) gap = std::max(gap, (x[a] - x[b]).norm());
  return gap;
}

void SeamGroups::addSewingForces(const std::vector<Eigen::Vector3d>& x, double stiffness,
                                 std::vector<Eigen::Vector3d>& f) const {
  for (const auto& [a, b] : pairs_) {
    const Eigen::Vector3d pull = stiffness * (x[b] - x[a]);
    f[a] += pull;
    f[b] -= pull;
  }
}

void SeamGroups::average(std::vector<Eigen::Vector3d>& v) const {
  for (const auto& g : groups_) {
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (int i : g) mean += v[i];
    mean /= static_cast<double>(g.size());
    for (int i : g) v[i] = mean;
  }
}

}  // namespace chs
