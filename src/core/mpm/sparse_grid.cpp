#include "cloth_hair_sim/core/mpm/sparse_grid.h"

#include "cloth_hair_sim/core/common/input_error.h"

namespace chs::mpm {

SparseGrid::SparseGrid(double dx) : dx_(dx) {
  if (!(dx > 0.0)) throw InputError("MPM grid spacing must be positive");
}

void SparseGrid::clear() {
  index_.clear();
  coord_.clear();
  mass.clear();
  momentum.clear();
  velocity.clear();
  force.clear();
}

std::uint64_t SparseGrid::key(const Eigen::Vector3i& c) {
  // 21 bits per axis with an offset: +-1e6 cells, far beyond any garment scene.
  constexpr std::int64_t kOffset = 1 << 20;
  const auto u = [](int v) { return static_cast<std::uint64_t>(v + kOffset) & 0x1FFFFF; };
  return u(c.x()) | (u(c.y()) << 21) | (u(c.z()) << 42);
}

int SparseGrid::activate(const Eigen::Vector3i& c) {
  const auto [it, inserted] = index_.try_emplace(key(c), size());
  if (inserted) {
    coord_.push_back(c);
    mass.push_back(0.0);
    momentum.push_back(Eigen::Vector3d::Zero());
    velocity.push_back(Eigen::Vector3d::Zero());
    force.push_back(Eigen::Vector3d::Zero());
  }
  return it->second;
}

int SparseGrid::find(const Eigen::Vector3i& c) const {
  const auto it = index_.find(key(c));
  return it == index_.end() ? -1 : it->second;
}

}  // namespace chs::mpm
