#pragma once
#include <Eigen/Geometry>

#include "cloth_hair_sim/node/grasp.h"

namespace chs_node {

// Kinematic inputs (colliders and attachment frames from tf) move from their pose at the start
// of an update to the current one over its substeps. One that would need more than max_speed
// (~max_speed, the speed at which the node already rolls a step back as diverged) to get there
// within the update's simulated `duration` did not move, it jumped: a relocalised or glitched
// frame, a frame back after a gap. Swept at that speed it would fling the cloth, so the node
// teleports it instead (sim_node_teleport.cpp).
inline bool jumped(double distance, double duration, double max_speed) {
  return distance > max_speed * duration;
}

// The farthest any of the attachment's vertices is carried from pose `from` to pose `to` [m].
double farthestMove(const FrameAttachment& a, const Eigen::Isometry3d& from,
                    const Eigen::Isometry3d& to);

}  // namespace chs_node
