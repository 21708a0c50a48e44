#pragma once
#include <string>
#include <vector>

#include <tf2_ros/buffer.h>
#include <xmlrpcpp/XmlRpcValue.h>
#include <Eigen/Geometry>

#include "cloth_hair_sim/core/contact/collider_shape.h"
#include "cloth_hair_sim/core/contact/rigid_surface.h"

namespace chs_node {

// A collider carried by a tf frame.
struct TrackedCollider {
  std::string name;
  std::string frame_id;
  chs::ColliderShape shape;
  double friction = 0.0;  // Coulomb mu of cloth on this collider
  bool has_pose = false;  // seen at least once; until then the collider is inactive
  bool stale = true;      // the last lookup failed: the last pose is held
  Eigen::Isometry3d world_from_frame = Eigen::Isometry3d::Identity();

  Eigen::Isometry3d shapePose() const { return world_from_frame * shape.offset; }
};

// Parses the ~colliders parameter: a list of {name, frame_id, shape:
// plane|sphere|box|cylinder|capsule, dimensions: [...], offset: {xyz: [x, y, z], rpy: [r, p, y]}
// (optional), edge_radius (optional), friction (optional Coulomb mu, default 0)}. Throws
// chs::InputError naming the collider and key at fault.
std::vector<TrackedCollider> parseColliders(XmlRpc::XmlRpcValue& list);

// Keeps the colliders' world poses current from tf. A frame that cannot be looked up keeps its
// last pose (so the cloth is never teleported by a dropped transform) and is reported stale.
class ColliderTracker {
 public:
  ColliderTracker(const tf2_ros::Buffer& buffer, std::string world_frame, double timeout_s);
  void setColliders(std::vector<TrackedCollider> colliders) { colliders_ = std::move(colliders); }
  // Looks every frame up at the latest available time. Returns false if any lookup failed.
  bool update();
  const std::vector<TrackedCollider>& colliders() const { return colliders_; }
  // Surfaces of the colliders with a known pose, in the world frame.
  chs::RigidSurfaces surfaces() const;
  // Their friction coefficients, in the same order.
  std::vector<double> frictions() const;
  std::vector<std::string> staleNames() const;
  int activeCount() const;

 private:
  const tf2_ros::Buffer& buffer_;
  std::string world_frame_;
  double timeout_s_;
  std::vector<TrackedCollider> colliders_;
};

}  // namespace chs_node
