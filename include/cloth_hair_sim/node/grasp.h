#pragma once
#include <string>
#include <vector>

#include <ros/publisher.h>
#include <Eigen/Geometry>

#include "cloth_hair_sim/core/dynamics/holding_wrench.h"
#include "cloth_hair_sim/core/particle/particle_dynamics.h"

namespace chs_node {

// Garment vertices carried by a tf frame (a gripper, or pins given at load time). Within an
// update the frame moves from `from` (where the last update left it) towards `to` (the current
// lookup; all the way unless the node's inputs lag); each substep pins the vertices at the
// interpolated pose, so a frame that moved between updates does not jerk the cloth in one
// substep.
struct FrameAttachment {
  std::string frame_id;
  std::vector<int> vertices;
  std::vector<Eigen::Vector3d> offsets;                           // vertex positions in the frame
  Eigen::Isometry3d attached_at = Eigen::Isometry3d::Identity();  // the frame's pose then
  Eigen::Isometry3d from = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d to = Eigen::Isometry3d::Identity();
  bool stale = false;  // the last lookup failed: `to` holds the last pose
  // The frame jumped in the previous update: tf, asked for a time just after a jump, interpolates
  // across it, so the jump's tail comes an update later and is carried too, not swept.
  bool jumped_before = false;

  // Attaches vertices at their positions x, the frame being at world_from_frame now.
  FrameAttachment(std::string frame, std::vector<int> vertices,
                  const std::vector<Eigen::Vector3d>& x, const Eigen::Isometry3d& world_from_frame);
  // Pins the vertices where the frame is at fraction alpha of the update.
  void pinAt(chs::ClothDynamics& dynamics, double alpha) const;
  void unpin(chs::ClothDynamics& dynamics) const;
};

// A gripper's grasp of a garment and the publisher of the wrench it feels.
struct Grasp {
  std::string name, garment;
  FrameAttachment attachment;
  ros::Publisher wrench_pub;
  // Velocities of the held vertices at the end of the previous update: their acceleration
  // enters the holding force (empty until the first update).
  std::vector<Eigen::Vector3d> last_velocity;
  // Holding wrench summed over the substeps of the current update (about the frame origin of
  // each substep): the published wrench is its mean, as a sensor low-passed at the update rate
  // would read, not a sample of the stiff cloth's fast stretch vibration.
  chs::HoldingWrench sum;
  int samples = 0;
};

// Removes the grasps (a map from name to Grasp or HairGrasp) whose body, as body_of gives it, is
// `body`, closing their wrench topics; returns their names.
template <class Grasps, class BodyOf>
std::vector<std::string> dropGraspsOf(Grasps& grasps, const std::string& body, BodyOf body_of) {
  std::vector<std::string> names;
  for (auto it = grasps.begin(); it != grasps.end();) {
    if (body_of(it->second) == body) {
      names.push_back(it->first);
      it->second.wrench_pub.shutdown();
      it = grasps.erase(it);
    } else {
      ++it;
    }
  }
  return names;
}

// Pose at fraction t in [0, 1] from a to b: translation lerp, rotation slerp.
Eigen::Isometry3d interpolate(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b, double t);

// Constant rigid velocity that carries a to b in `duration` seconds (zero for duration <= 0).
chs::SurfaceVelocity rigidVelocity(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b,
                                   double duration);

// Vertices within radius of centre that are not pinned yet.
std::vector<int> freeVerticesNear(const chs::ClothDynamics& dynamics, const Eigen::Vector3d& centre,
                                  double radius);

}  // namespace chs_node
