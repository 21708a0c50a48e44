#pragma once
#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace chs::mpm {

// Background grid that stores nodes only where particles are: a hash from integer node
// coordinates to dense node arrays, rebuilt (activate) each step. Node i sits at i dx.
// The hash is open addressing with linear probing in a power-of-two table kept between steps
// (clear() empties it without freeing), so a step's lookups allocate nothing.
class SparseGrid {
 public:
  explicit SparseGrid(double dx);

  double spacing() const { return dx_; }
  int size() const { return static_cast<int>(coord_.size()); }
  void clear();
  // Index of node c, created with zero state when new.
  int activate(const Eigen::Vector3i& c);
  // Index of node c, or -1 when the node is not active.
  int find(const Eigen::Vector3i& c) const;
  Eigen::Vector3d position(int node) const { return coord_[node].cast<double>() * dx_; }
  const Eigen::Vector3i& coordinate(int node) const { return coord_[node]; }

  std::vector<double> mass;
  std::vector<Eigen::Vector3d> momentum, velocity;
  std::vector<Eigen::Vector3d> force;  // -dPsi/dx_i of Han (5.40), internal forces only

 private:
  static std::uint64_t key(const Eigen::Vector3i& c);
  std::size_t slot(std::uint64_t key) const;  // home slot of a key in the table
  void grow();

  double dx_;
  std::vector<std::uint64_t> keys_;  // kEmpty or a node key
  std::vector<int> values_;          // node index of the key in the same slot
  int shift_ = 64;                   // 64 - log2(table size)
  std::vector<Eigen::Vector3i> coord_;
};

}  // namespace chs::mpm
