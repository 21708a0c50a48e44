#include "cloth_hair_sim/node/teleport.h"

#include <algorithm>

namespace chs_node {

double farthestMove(const FrameAttachment& a, const Eigen::Isometry3d& from,
                    const Eigen::Isometry3d& to) {
  double d = 0.0;
  for (const Eigen::Vector3d& o : a.offsets) d = std::max(d, (to * o - from * o).norm());
  return d;
}

}  // namespace chs_node
