#pragma once
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <ros/publisher.h>
#include <Eigen/Geometry>

#include "cloth_hair_sim/LoadGarment.h"
#include "cloth_hair_sim/core/drape/drape_problem.h"
#include "cloth_hair_sim/core/particle/particle_dynamics.h"
#include "cloth_hair_sim/node/grasp.h"
#include "cloth_hair_sim/node/sim_params.h"

namespace chs_node {

// A loaded garment: its flat reference problem (in the world frame, colliders left empty: the
// node supplies the current ones) and its dynamic state.
struct Garment {
  std::string name;
  std::string material_name;
  chs::DrapeProblem reference;
  std::shared_ptr<chs::ClothDynamics> dynamics;
  // The same object as a body of the node's world (the mpm backend), or null (particle).
  std::shared_ptr<chs::Body> body;

  std::uint64_t generation = 0;  // set anew on load and reset: a finished drape checks it
  int colour = 0;
  // Pins attached to tf frames at load (also pinned in `reference`, where they were at load).
  std::vector<FrameAttachment> frame_pins;
  ros::Publisher mesh_pub;  // ~garments/<name>/mesh; unadvertised with the garment
  int diverged_stops = 0;   // stopped in place after diverging, since load or reset

  // What buildGarment made it from, so that a saved state (state_io.h) rebuilds it as it was.
  cloth_hair_sim::LoadGarment::Request request;
  Eigen::Isometry3d world_from_request_frame = Eigen::Isometry3d::Identity();
  std::map<std::string, Eigen::Isometry3d> world_from_frames;
  // mpm: Coulomb mu between its layers when reconfigured live (else ~mpm/self_friction).
  std::optional<double> self_friction;
};

// Rigid pose of a geometry_msgs/Pose; throws chs::InputError for NaN/Inf or a quaternion that
// is neither (close to) unit nor all zero (read as the identity).
Eigen::Isometry3d poseFromMsg(const geometry_msgs::Pose& pose);

// Builds and validates a garment from a ~load_garment request; world_from_request_frame places
// the request's frame_id, world_from_frames the frames of req.attached. Throws chs::InputError
// naming the problem (file, mesh, pose, material, vertex indices).
Garment buildGarment(const cloth_hair_sim::LoadGarment::Request& req,
                     const Eigen::Isometry3d& world_from_request_frame,
                     const std::map<std::string, Eigen::Isometry3d>& world_from_frames,
                     const SimParams& params);

// A fresh dynamic state at a garment's reference, with the backend the parameters name (an mpm
// garment on a grid of params.mpm.grid_spacing, the world's once it has one; Coulomb mu between
// its layers self_friction when set), apart from the garment: ~reset builds them before it holds
// the world. Throws chs::InputError when the backend refuses the garment.
struct FreshDynamics {
  std::shared_ptr<chs::ClothDynamics> dynamics;
  std::shared_ptr<chs::Body> body;  // the same object (mpm), or null (particle)
};
FreshDynamics freshDynamics(const chs::DrapeProblem& reference,
                            const std::optional<double>& self_friction, const SimParams& params);

// The garment's dynamics replaced by freshDynamics (reset).
void resetDynamics(Garment& garment, const SimParams& params);

}  // namespace chs_node
