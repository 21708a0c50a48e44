#pragma once
#include <memory>
#include <string>
#include <vector>

#include <ros/publisher.h>
#include <visualization_msgs/Marker.h>
#include <Eigen/Geometry>

#include "cloth_hair_sim/LoadHair.h"
#include "cloth_hair_sim/core/dynamics/holding_wrench.h"
#include "cloth_hair_sim/core/rod/display_strands.h"
#include "cloth_hair_sim/core/rod/groom.h"
#include "cloth_hair_sim/core/rod/hair_dynamics.h"

namespace chs_node {

// Loaded hair (~load_hair): a rod body of the node's world whose roots are clamped to a tf frame.
// Within an update the frame moves from `from` to `to` (the previous and the current lookup);
// each substep moves the clamps to the interpolated pose (HairDynamics::setRootFrame).
struct Hair {
  std::string name, material_name, frame_id;
  cloth_hair_sim::LoadHair::Request request;  // what built it (a state file rebuilds from it)
  chs::rod::Polylines rest;  // the guides' rest shapes in the root frame's coordinates
  chs::rod::RodMaterial material;
  std::vector<chs::rod::DisplayStrand> display;  // blended from the guides for the markers
  std::shared_ptr<chs::rod::HairDynamics> body;
  Eigen::Isometry3d attached_at = Eigen::Isometry3d::Identity();  // the frame when built
  Eigen::Isometry3d from = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d to = Eigen::Isometry3d::Identity();
  bool stale = false;  // the last lookup failed: `to` holds the last pose
  bool loose = false;  // roots not clamped
  int diverged_stops = 0;

  int numVertices() const;
  // Clamps the roots where the frame is at fraction alpha of the update.
  void clampAt(double alpha);
  // The guides now, then the display strands.
  chs::rod::Polylines drawnStrands() const;
};

// A gripper's grasp of a lock of hair (~grasp on hair): a grip of its body
// (HairDynamics::addGrip) carried by a tf frame, moving from `from` to `to` within an update as
// Hair's roots do, and the publisher of the wrench it feels.
struct HairGrasp {
  std::string name, hair, frame_id;
  int grip = -1;
  Eigen::Isometry3d attached_at = Eigen::Isometry3d::Identity();  // the frame when gripped
  Eigen::Isometry3d from = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d to = Eigen::Isometry3d::Identity();
  bool stale = false;
  ros::Publisher wrench_pub;
  // The grip's wrench summed over the update's substeps, about the frame origin of each: the
  // published wrench is their mean (as Grasp's).
  chs::HoldingWrench sum;
  int samples = 0;

  // Carries the grip where the frame is at fraction alpha of the update.
  void gripAt(chs::rod::HairDynamics& body, double alpha) const;
};

// Builds hair from a ~load_hair request, its body on `settings` (the world's grid) at the root
// frame's pose world_from_frame. display_default: the count of display strands when the request
// asks for ~hair/display_strands. Throws chs::InputError naming the problem (file, groom,
// material, display strands), with nothing built.
Hair buildHair(const cloth_hair_sim::LoadHair::Request& req,
               const Eigen::Isometry3d& world_from_frame, const chs::rod::HairSettings& settings,
               int display_default);

// A fresh body at the rest shape with the root frame at world_from_frame (load and ~reset).
void rebuildHairBody(Hair& hair, const Eigen::Isometry3d& world_from_frame,
                     const chs::rod::HairSettings& settings);

// Every strand drawn (guides and display strands) as one LINE_LIST in namespace "hair":
// a segment's two ends per pair of points.
visualization_msgs::Marker hairMarker(const Hair& hair, int id, const std::vector<float>& rgba,
                                      double line_width);

}  // namespace chs_node
