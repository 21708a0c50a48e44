#pragma once
#include <Eigen/Geometry>

#include "cloth_hair_sim/node/grasp.h"

namespace chs_node {

// Kinematic inputs (colliders and attachment frames from tf) move from their pose at the start
// of an update to the current one over its substeps. One that would need more than a fifth of
// max_speed (~max_speed, the speed at which the node rolls a step back as diverged) to get there
// within the update's simulated `duration` did not move, it jumped: a relocalised or glitched
// frame, a frame back after a gap. Swept it would fling the cloth, so the node teleports it
// instead (sim_node_teleport.cpp). Why a fifth: tf interpolates between the stamps either side
// of a jump, so an update that overlaps that interval by a sliver sees any speed up to the
// jump's; at max_speed itself such a sliver dragged a grasped cloth at just below the divergence
// speed and the node rolled back tens of thousands of substeps (tf_robustness.test, one run in
// a few). No robot frame moves at 10 m/s.
inline bool jumped(double distance, double duration, double max_speed) {
  return distance > 0.2 * max_speed * duration;
}

// The farthest any of the attachment's vertices is carried from pose `from` to pose `to` [m].
double farthestMove(const FrameAttachment& a, const Eigen::Isometry3d& from,
                    const Eigen::Isometry3d& to);

}  // namespace chs_node
