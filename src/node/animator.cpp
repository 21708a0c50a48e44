#include "cloth_hair_sim/node/animator.h"

#include <algorithm>
#include <cmath>

#include "cloth_hair_sim/core/common/input_error.h"

namespace chs_node {
namespace {

enum Joint { kNeck, kShoulderL, kShoulderR, kElbowL, kElbowR, kHipL, kHipR, kKneeL, kKneeR };

}  // namespace

Motion parseMotion(const std::string& name) {
  if (name == "still") return Motion::kStill;
  if (name == "arms_raise") return Motion::kArmsRaise;
  if (name == "walk") return Motion::kWalk;
  throw chs::InputError("motion '" + name + "' is unknown: use still, arms_raise or walk");
}

const std::vector<std::string>& mannequinJoints() {
  static const std::vector<std::string> names{"neck",    "shoulder_l", "shoulder_r",
                                              "elbow_l", "elbow_r",    "hip_l",
                                              "hip_r",   "knee_l",     "knee_r"};
  return names;
}

std::vector<double> mannequinPose(Motion motion, double t, double period) {
  std::vector<double> q(mannequinJoints().size(), 0.0);
  if (t <= 0.0 || motion == Motion::kStill) return q;
  const double phase = 2.0 * M_PI * t / period;
  // Amplitudes grow smoothly over the first cycle, so velocities start at zero too.
  const double ease = t >= period ? 1.0 : 0.5 - 0.5 * std::cos(M_PI * t / period);
  if (motion == Motion::kArmsRaise) {
    const double lift = ease * (0.5 - 0.5 * std::cos(phase));  // 0 .. 1 .. 0 per cycle
    q[kShoulderL] = q[kShoulderR] = 1.6 * lift;                // about 90 degrees forward
    q[kElbowL] = q[kElbowR] = 0.3 * lift;
    q[kNeck] = -0.2 * lift;  // looks up at the hands
  } else {
    const double s = std::sin(phase);
    q[kHipL] = 0.45 * ease * s;
    q[kHipR] = -0.45 * ease * s;
    // A knee bends while its leg swings forward.
    q[kKneeL] = 0.9 * ease * std::max(0.0, std::sin(phase + 0.6));
    q[kKneeR] = 0.9 * ease * std::max(0.0, -std::sin(phase + 0.6));
    q[kShoulderL] = -0.35 * ease * s;  // arms swing against the legs
    q[kShoulderR] = 0.35 * ease * s;
    q[kElbowL] = q[kElbowR] = 0.25 * ease;
    q[kNeck] = 0.05 * ease * std::sin(2.0 * phase);
  }
  return q;
}

}  // namespace chs_node
