#pragma once
#include <string>
#include <vector>

#include <ros/node_handle.h>

#include "cloth_hair_sim/node/collider_tracker.h"

namespace chs_node {

// The collision geometry of a robot, one collider per URDF collision element, carried by the
// link's tf frame with the collision origin as its offset. urdfdom 3 (Debian 12) has no capsule
// tag, so a URDF writes a capsule as a cylinder capped by two spheres of its radius at its end
// centres; such a triple in one link becomes one capsule collider (smooth, one distance query).
// A <mesh filename="package://... or file://..." scale="x y z"/> becomes a mesh collider, its
// distance field built while parsing; a mesh that is missing or not closed is skipped with a
// warning.
struct UrdfColliders {
  std::vector<TrackedCollider> colliders;
  std::vector<std::string> warnings;  // skipped geometry (unreadable or open meshes), by link
};

// Throws chs::InputError when the text is not a URDF urdfdom can parse. frame_prefix is put in
// front of every link name (for a robot_state_publisher with a tf prefix).
UrdfColliders parseUrdfColliders(const std::string& urdf_xml, const std::string& frame_prefix = "");

// The node's startup hook: with ~urdf_colliders true, reads the URDF from the parameter named by
// ~robot_description (default "robot_description", resolved in the node's namespace), logs the
// skipped geometry and appends the link colliders to `colliders`. ~urdf_frame_prefix prefixes the
// link frames. Throws chs::InputError for a missing or broken URDF or a name clash.
std::vector<TrackedCollider> withUrdfColliders(const ros::NodeHandle& private_nh,
                                               std::vector<TrackedCollider> colliders);

}  // namespace chs_node
