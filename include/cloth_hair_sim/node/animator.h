#pragma once
#include <string>
#include <utility>
#include <vector>

namespace chs_node {

// Joint motions of urdf/mannequin.urdf for mannequin_animator: kinematic (no dynamics), smooth
// and starting from the rest pose, so cloth draped at rest is pushed gently, never teleported.
enum class Motion {
  kStill,      // rest pose: arms and legs hanging
  kArmsRaise,  // both arms rise forward to horizontal and come back down
  kWalk,       // a walk cycle in place: legs and opposite arms swing, knees and elbows bend
};

// Throws chs::InputError for anything but still | arms_raise | walk.
Motion parseMotion(const std::string& name);

// The revolute joints of the mannequin, in a fixed order.
const std::vector<std::string>& mannequinJoints();

// Joint angles [rad] at time t [s] since the motion started, in mannequinJoints() order.
// period [s] is one full cycle; before t = 0 the pose is the rest pose. Motions ease in over
// their first cycle.
std::vector<double> mannequinPose(Motion motion, double t, double period);

}  // namespace chs_node
