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
  double friction = 0.0;    // Coulomb mu of cloth on this collider
  bool has_pose = false;    // seen at least once; until then the collider is inactive
  bool stale = true;        // the last lookup failed or was too old: the last pose is held
  bool reappeared = false;  // stale at the previous update, posed again now (teleported)
  Eigen::Isometry3d world_from_frame = Eigen::Isometry3d::Identity();

  Eigen::Isometry3d shapePose() const { return world_from_frame * shape.offset; }
};

// Parses the ~colliders parameter: a list of {name, frame_id, shape:
// plane|sphere|box|cylinder|capsule|mesh, dimensions: [...], offset: {xyz: [x, y, z], rpy: [r, p,
// y]} (optional), edge_radius (optional), friction (optional Coulomb mu, default 0)}. A mesh takes
// no dimensions but file: <path, file:// or package:// URL>, scale: <number or [x, y, z]>
// (optional, 0.001 for a file in mm) and voxel_size (optional, m; default in MeshSdfResolution);
// its distance field is built here, so a broken mesh is reported at startup. Throws
// chs::InputError naming the collider and key at fault.
std::vector<TrackedCollider> parseColliders(XmlRpc::XmlRpcValue& list);

// A mesh location as a file path: "package://<pkg>/<path>" is looked up in the packages under
// ROS_PACKAGE_PATH and the share/ folders of CMAKE_PREFIX_PATH (as rospack finds them: a folder
// holding a package.xml with that <name>), "file://<path>" is the path, anything without a
// scheme is taken as a path. Throws chs::InputError for another scheme or an unknown package.
std::string resolveMeshUrl(const std::string& url);

// True if a transform stamped `stamp` is older than max_age_s at `now` (max_age_s <= 0: never).
bool tooOld(const ros::Time& stamp, const ros::Time& now, double max_age_s);

// Keeps the colliders' world poses current from tf. A frame that cannot be looked up, or whose
// latest transform is older than max_age_s (a frame no longer published: tf keeps its last
// transform forever; 0: any age), keeps its last pose (so the cloth is never teleported by a
// dropped transform) and is reported stale.
class ColliderTracker {
 public:
  ColliderTracker(const tf2_ros::Buffer& buffer, std::string world_frame, double timeout_s,
                  double max_age_s);
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
  double max_age_s_;
  std::vector<TrackedCollider> colliders_;
};

}  // namespace chs_node
