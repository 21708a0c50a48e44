#include "cloth_hair_sim/core/collision/penetration_depth.h"

#include <string>

#include "cloth_hair_sim/core/common/input_error.h"

namespace chs {

DeepestPenetration deepestPenetration(
    const std::vector<Eigen::Vector3d>& points, const RigidSurfaces& colliders,
    const std::function<const std::vector<int>&(const Eigen::Vector3d&)>& candidates) {
  for (std::size_t c = 0; c < colliders.size(); ++c)
    if (!colliders[c])
      throw InputError("penetration depth: collider " + std::to_string(c) + " is null");
  DeepestPenetration deepest;
  for (std::size_t p = 0; p < points.size(); ++p) {
    // A NaN gap would compare false and hide the point, so reject it up front.
    if (!points[p].allFinite())
      throw InputError("penetration depth: point " + std::to_string(p) +
                       " has a non-finite coordinate");
    for (int c : candidates(points[p])) {
      const double depth = -colliders[c]->project(points[p]).gap;
      if (depth > deepest.depth) deepest = {depth, static_cast<int>(p), c};
    }
  }
  return deepest;
}

DeepestPenetration deepestPenetration(const std::vector<Eigen::Vector3d>& points,
                                      const RigidSurfaces& colliders) {
  std::vector<int> all(colliders.size());
  for (std::size_t c = 0; c < colliders.size(); ++c) all[c] = static_cast<int>(c);
  return deepestPenetration(
      points, colliders, [&all](const Eigen::Vector3d&) -> const std::vector<int>& { return all; });
}

}  // namespace chs
