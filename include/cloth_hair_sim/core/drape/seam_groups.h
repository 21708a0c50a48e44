#pragma once
#include <vector>

#include <Eigen/Core>

#include "cloth_hair_sim/core/drape/drape_problem.h"

namespace chs {

// The vertices that seams join, grouped (a vertex on two seams, e.g. where three panels meet,
// joins both partners): before they meet, sewing springs pull each pair together; once joined,
// each group moves as one particle.
class SeamGroups {
 public:
  // Throws InputError for unequal sides, out-of-range or self-sewn vertices.
  SeamGroups(int num_vertices, const std::vector<Seam>& seams);

  bool empty() const { return pairs_.empty(); }
  const std::vector<std::pair<int, int>>& pairs() const { return pairs_; }
  const std::vector<std::vector<int>>& groups() const { return groups_; }

  // Largest distance between two vertices sewn to each other.
  double maxGap(const std::vector<Eigen::Vector3d>& x) const;
  // Sewing forces: a spring of the given stiffness and zero rest length on every pair.
  void addSewingForces(const std::vector<Eigen::Vector3d>& x, double stiffness,
                       std::vector<Eigen::Vector3d>& f) const;
  // Sets every member of a group to the group mean (positions once joined; forces so that a
  // group takes one step as one particle).
  void average(std::vector<Eigen::Vector3d>& v) const;

 private:
  std::vector<std::pair<int, int>> pairs_;
  std::vector<std::vector<int>> groups_;
};

}  // namespace chs
