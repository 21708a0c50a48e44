#include "cloth_hair_sim/core/mpm/sparse_grid.h"

#include <algorithm>

#include "cloth_hair_sim/core/common/input_error.h"

namespace chs::mpm {
namespace {

// No node key has all 64 bits set (keys use 63).
constexpr std::uint64_t kEmpty = ~std::uint64_t{0};
constexpr int kInitialBits = 10;

}  // namespace

SparseGrid::SparseGrid(double dx) : dx_(dx) {
  if (!(dx > 0.0)) throw InputError("MPM grid spacing must be positive");
  keys_.assign(std::size_t{1} << kInitialBits, kEmpty);
  values_.assign(keys_.size(), -1);
  shift_ = 64 - kInitialBits;
}

void SparseGrid::clear() {
  std::fill(keys_.begin(), keys_.end(), kEmpty);
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

std::size_t SparseGrid::slot(std::uint64_t key) const {
  // Fibonacci hashing: the top bits of key * 2^64 / golden ratio mix all three axes.
  return static_cast<std::size_t>((key * 0x9E3779B97F4A7C15ull) >> shift_);
}

void SparseGrid::grow() {
  const std::vector<std::uint64_t> old_keys = std::move(keys_);
  const std::vector<int> old_values = std::move(values_);
  keys_.assign(2 * old_keys.size(), kEmpty);
  values_.assign(keys_.size(), -1);
  --shift_;
  const std::size_t mask = keys_.size() - 1;
  for (std::size_t s = 0; s < old_keys.size(); ++s) {
    if (old_keys[s] == kEmpty) continue;
    std::size_t t = slot(old_keys[s]);
    while (keys_[t] != kEmpty) t = (t + 1) & mask;
    keys_[t] = old_keys[s];
    values_[t] = old_values[s];
  }
}

int SparseGrid::activate(const Eigen::Vector3i& c) {
  const std::uint64_t k = key(c);
  const std::size_t mask = keys_.size() - 1;
  std::size_t s = slot(k);
  for (; keys_[s] != kEmpty; s = (s + 1) & mask)
    if (keys_[s] == k) return values_[s];
  // New node. Keep the load factor at most 1/2 so that probe sequences stay short.
  if (2 * (coord_.size() + 1) > keys_.size()) {
    grow();
    return activate(c);
  }
  const int node = size();
  keys_[s] = k;
  values_[s] = node;
  coord_.push_back(c);
  mass.push_back(0.0);
  momentum.push_back(Eigen::Vector3d::Zero());
  velocity.push_back(Eigen::Vector3d::Zero());
  force.push_back(Eigen::Vector3d::Zero());
  return node;
}

int SparseGrid::find(const Eigen::Vector3i& c) const {
  const std::uint64_t k = key(c);
  const std::size_t mask = keys_.size() - 1;
  for (std::size_t s = slot(k); keys_[s] != kEmpty; s = (s + 1) & mask)
    if (keys_[s] == k) return values_[s];
  return -1;
}

}  // namespace chs::mpm
