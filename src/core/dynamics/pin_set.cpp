#include "cloth_hair_sim/core/dynamics/pin_set.h"

#include <utility>

#include "cloth_hair_sim/core/common/input_error.h"

namespace chs {

PinSet::PinSet(Names names, std::vector<Eigen::Vector3d> positions)
    : names_(std::move(names)), pinned_(positions.size(), 0), targets_(std::move(positions)) {}

void PinSet::check(int vertex) const {
  if (vertex < 0 || vertex >= size())
    throw InputError(names_.backend + ": " + names_.vertex + " " + std::to_string(vertex) +
                     " out of range (" + std::to_string(size()) + " " + names_.vertices + ")");
}

void PinSet::checkHoldingRequest(const std::vector<int>& vertices,
                                 const std::vector<Eigen::Vector3d>& accelerations) const {
  if (!accelerations.empty() && accelerations.size() != vertices.size())
    throw InputError("holding forces: " + std::to_string(accelerations.size()) +
                     " accelerations for " + std::to_string(vertices.size()) + " vertices");
  for (int v : vertices) check(v);
}

void PinSet::pinInPlace(int vertex, const std::vector<Eigen::Vector3d>& positions) {
  check(vertex);
  pin(vertex, positions[vertex]);
}

void PinSet::pin(int vertex, const Eigen::Vector3d& target) {
  check(vertex);
  if (!target.allFinite()) throw InputError(names_.backend + ": pin target is not finite");
  pinned_[vertex] = 1;
  targets_[vertex] = target;
}

void PinSet::unpin(int vertex) {
  check(vertex);
  pinned_[vertex] = 0;
}

void PinSet::write(StateWriter& out) const {
  out.u64(pinned_.size());
  std::vector<int> pinned;
  forEachPinned([&](int v) { pinned.push_back(v); });
  out.ints(pinned);
  out.vectors(targets_);
}

void PinSet::read(StateReader& in) {
  in.expectCount("pinned vertices: vertex count", pinned_.size());
  const std::vector<int> pinned = in.ints("pinned vertices");
  std::vector<Eigen::Vector3d> targets = in.vectors("pin targets", targets_.size());
  std::vector<char> flags(pinned_.size(), 0);
  for (int v : pinned) {
    if (v < 0 || v >= size())
      in.fail("pinned " + names_.vertex + " " + std::to_string(v) + " out of range (" +
              std::to_string(size()) + " " + names_.vertices + ")");
    if (!targets[v].allFinite())
      in.fail("pinned " + names_.vertex + " " + std::to_string(v) + " has a non-finite target");
    flags[v] = 1;
  }
  pinned_ = std::move(flags);
  targets_ = std::move(targets);
}

}  // namespace chs
