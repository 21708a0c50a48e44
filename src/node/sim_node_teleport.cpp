// Jumps of tf frames (teleport.h): colliders are placed at their new pose, held garments carried.
#include <set>
#include <string>
#include <vector>

#include "cloth_hair_sim/node/sim_node.h"
#include "cloth_hair_sim/node/teleport.h"

namespace chs_node {

void SimNode::teleportJumps(double duration) {
  // A collider that jumped, or is back after a gap (its motion meanwhile is unknown), is placed
  // at its pose for the whole update with no velocity: cloth it leaves behind falls, cloth it
  // lands in is pushed out by contact.
  std::set<std::string> jumped_now;
  for (const auto& c : colliders_.colliders()) {
    const auto it = collider_from_.find(c.name);
    if (!c.has_pose || it == collider_from_.end()) continue;
    const double d =
        ((it->second * c.shape.offset).translation() - c.shapePose().translation()).norm();
    const bool jump = jumped(d, duration, params_.max_speed);
    if (jump) jumped_now.insert(c.name);
    if (jump)
      ROS_WARN("collider '%s' jumped %.3g m in one update: placed there, not swept", c.name.c_str(),
               d);
    else if (colliders_jumped_.count(c.name) && d > 0.0)
      ROS_INFO("collider '%s': the tail of its jump, %.3g m, placed too", c.name.c_str(), d);
    else if (c.reappeared && d > 0.0)
      ROS_INFO("collider '%s' is back after a gap, %.3g m away: placed there, not swept",
               c.name.c_str(), d);
    else
      continue;
    it->second = c.world_from_frame;
  }
  colliders_jumped_ = std::move(jumped_now);

  // A garment held by a frame that jumped goes along rigidly (a gripper keeps its cloth through
  // a relocalisation), if every vertex held in place moves with that jump; a garment also held
  // elsewhere (world pins, clamps, fixed axes, another gripper) cannot follow, and the grasps
  // that jumped let go instead of tearing it.
  for (auto& [name, g] : garments_) {
    std::vector<FrameAttachment*> held;
    for (auto& a : g.frame_pins) held.push_back(&a);
    for (auto& [grasp_name, grasp] : grasps_)
      if (grasp.garment == name) held.push_back(&grasp.attachment);
    const FrameAttachment* first = nullptr;
    for (auto* a : held) {
      const bool jump = jumped(farthestMove(*a, a->from, a->to), duration, params_.max_speed);
      if (!first && (jump || (a->jumped_before && farthestMove(*a, a->from, a->to) > 0.0)))
        first = a;
      a->jumped_before = jump;
    }
    if (!first) continue;
    const Eigen::Isometry3d jump = first->to * first->from.inverse();
    chs::ClothDynamics& dyn = *g.dynamics;
    std::vector<char> carried(dyn.numVertices(), 0);
    for (const auto* a : held)
      if (!jumped(farthestMove(*a, jump * a->from, a->to), duration, params_.max_speed))
        for (int v : a->vertices) carried[v] = 1;
    bool rigid = g.reference.bc.fixed_components.empty();
    for (int v = 0; v < dyn.numVertices() && rigid; ++v) rigid = carried[v] || !dyn.isPinned(v);
    const double distance = farthestMove(*first, first->from, first->to);
    if (rigid) {
      std::vector<Eigen::Vector3d> x = dyn.positions(), v = dyn.velocities();
      for (auto& p : x) p = jump * p;
      for (auto& u : v) u = jump.linear() * u;
      dyn.setPositions(x);
      dyn.setVelocities(v);
      for (auto* a : held) a->from = jump * a->from;
      ROS_WARN("garment '%s': frame '%s' jumped %.3g m in one update: the garment goes with it",
               name.c_str(), first->frame_id.c_str(), distance);
      continue;
    }
    for (auto it = grasps_.begin(); it != grasps_.end();) {
      FrameAttachment& a = it->second.attachment;
      if (it->second.garment != name ||
          !jumped(farthestMove(a, a.from, a.to), duration, params_.max_speed)) {
        ++it;
        continue;
      }
      ROS_WARN(
          "grasp '%s': frame '%s' jumped %.3g m in one update while garment '%s' is held "
          "elsewhere too: released",
          it->first.c_str(), a.frame_id.c_str(), farthestMove(a, a.from, a.to), name.c_str());
      a.unpin(dyn);
      it->second.wrench_pub.shutdown();
      it = grasps_.erase(it);
    }
    for (const auto& a : g.frame_pins)
      if (jumped(farthestMove(a, a.from, a.to), duration, params_.max_speed))
        ROS_ERROR_THROTTLE(5.0,
                           "garment '%s': its frame '%s' jumped %.3g m in one update while the "
                           "garment is held elsewhere too: it stops where it is until the frames "
                           "agree again",
                           name.c_str(), a.frame_id.c_str(), farthestMove(a, a.from, a.to));
  }
}

}  // namespace chs_node
