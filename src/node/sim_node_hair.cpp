// ~load_hair and ~remove_hair: hair as a rod body of the node's world (core/rod/hair_dynamics.h).
#include <algorithm>
#include <limits>
#include <set>
#include <sstream>
#include <string>

#include <geometry_msgs/WrenchStamped.h>
#include <Eigen/Geometry>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/common/names.h"
#include "cloth_hair_sim/node/sim_node.h"

namespace chs_node {

namespace {

std::string continuumNote(const chs::rod::StrandContinuumSettings& c) {
  if (!c.enabled) return "";
  std::ostringstream s;
  s << ", strand continuum on (E " << c.youngs_modulus << " Pa, friction " << c.friction << ")";
  return s.str();
}

}  // namespace

chs::rod::HairSettings SimNode::hairSettings() const {
  chs::rod::HairSettings s;
  s.grid_spacing = world_.gridSpacing() > 0.0 ? world_.gridSpacing() : hair_grid_spacing_;
  s.kernel_degree = params_.world.kernel_degree;
  s.gravity = params_.gravity;
  s.continuum = hair_continuum_;
  return s;
}

bool SimNode::diverged(const Hair& h) const {
  if (!h.body->finite()) return true;
  for (int s = 0; s < h.body->numStrands(); ++s)
    for (const auto& v : h.body->velocities(s))
      if (v.norm() > params_.max_speed) return true;
  return false;
}

bool SimNode::loadHair(cloth_hair_sim::LoadHair::Request& req,
                       cloth_hair_sim::LoadHair::Response& res) {
  res.success = false;
  const std::string who = "hair '" + req.name + "': ";
  const auto refuse = [&](const std::string& why) {
    res.message = who + why;
    ROS_WARN("%s", res.message.c_str());
    return true;
  };
  try {
    chs::checkName(req.name);
  } catch (const chs::InputError& e) {
    return refuse(e.what());
  }
  {
    const WorldLock lock(*this);
    if (garments_.count(req.name) || hairs_.count(req.name))
      return refuse("a garment or hair of that name is loaded; remove it first");
  }
  if (req.frame_id.empty()) req.frame_id = params_.world_frame;
  Eigen::Isometry3d world_from_frame;
  std::string error;
  if (!lookupFrame(req.frame_id, 0.5, world_from_frame, &error))
    return refuse("root frame '" + req.frame_id + "' has no transform to '" + params_.world_frame +
                  "' (" + error + ")");
  try {
    chs::rod::HairSettings settings;
    {
      const WorldLock lock(*this);
      settings = hairSettings();
    }
    // Built and checked off the lock (a strand file may be large); the world is touched last.
    Hair h = buildHair(req, world_from_frame, settings, hair_display_strands_);
    const WorldLock lock(*this);
    if (garments_.count(req.name) || hairs_.count(req.name))
      return refuse("a garment or hair of that name was loaded meanwhile");
    world_.add(req.name, h.body);  // refuses a body off the world's grid (it changed meanwhile)
    res.strands = h.body->numStrands();
    res.vertices = h.numVertices();
    res.success = true;
    res.message = who + "loaded, " + std::to_string(res.strands) + " strands, " +
                  std::to_string(res.vertices) + " vertices, " + std::to_string(h.display.size()) +
                  " display strands, material " + h.material_name +
                  (h.loose ? ", loose (roots free)" : ", roots on frame '" + h.frame_id + "'") +
                  continuumNote(settings.continuum);
    hairs_.emplace(req.name, std::move(h));
    refreshCatalogue();
    substep_cost_ = 0.0;  // the world grew: the next update probes its cost
  } catch (const std::exception& e) {
    return refuse(e.what());
  }
  ROS_INFO("%s", res.message.c_str());
  return true;
}

bool SimNode::removeHair(cloth_hair_sim::RemoveGarment::Request& req,
                         cloth_hair_sim::RemoveGarment::Response& res) {
  const WorldLock lock(*this);
  res.success = hairs_.erase(req.name) > 0;
  if (res.success) world_.remove(req.name);
  refreshCatalogue();
  res.message = "hair '" + req.name + "': " + (res.success ? "removed" : "not loaded");
  for (const std::string& n : dropHairGrasps(req.name)) res.message += "; grasp " + n + " released";
  return true;
}

void SimNode::graspHair(const cloth_hair_sim::GraspGarment::Request& req,
                        const Eigen::Isometry3d& pose, Hair& hair,
                        cloth_hair_sim::GraspGarment::Response& res) {
  const std::string who = "grasp '" + req.name + "': ";
  const std::vector<chs::rod::StrandVertex> held =
      hair.body->freeVerticesNear(pose.translation(), req.radius);
  if (held.empty()) {
    double nearest = std::numeric_limits<double>::infinity();
    for (int s = 0; s < hair.body->numStrands(); ++s)
      for (const Eigen::Vector3d& x : hair.body->strand(s).positions())
        nearest = std::min(nearest, (x - pose.translation()).norm());
    res.message = who + "no free vertex of hair '" + hair.name + "' within " +
                  std::to_string(req.radius) + " m of frame '" + req.frame_id +
                  "' (the nearest vertex is " + std::to_string(nearest) + " m away)";
    return;
  }
  std::vector<int> first(hair.body->numStrands(), 0);  // each strand's first vertex's index
  for (int s = 1; s < hair.body->numStrands(); ++s)
    first[s] = first[s - 1] + hair.body->strand(s - 1).numVertices();
  HairGrasp g;
  g.name = req.name;
  g.hair = hair.name;
  g.frame_id = req.frame_id;
  g.grip = hair.body->addGrip(held);  // held where they are, from now on
  g.attached_at = g.from = g.to = pose;
  g.wrench_pub = pnh_.advertise<geometry_msgs::WrenchStamped>("grasp_wrench/" + req.name, 10);
  std::set<int> strands;
  for (const auto& sv : held) {
    res.vertices.push_back(first[sv.strand] + sv.vertex);
    strands.insert(sv.strand);
  }
  res.success = true;
  res.message = who + std::to_string(held.size()) + " vertices of " +
                std::to_string(strands.size()) + " strands of hair '" + hair.name +
                "' held by frame '" + req.frame_id + "'; wrench on " + g.wrench_pub.getTopic();
  hair_grasps_.emplace(req.name, std::move(g));
}

std::vector<std::string> SimNode::dropHairGrasps(const std::string& hair) {
  return dropGraspsOf(hair_grasps_, hair, [](const HairGrasp& g) { return g.hair; });
}

void SimNode::publishHairGraspWrenches() {
  const ros::Time now = ros::Time::now();
  for (auto& [name, grasp] : hair_grasps_) {
    const auto it = hairs_.find(grasp.hair);
    if (it == hairs_.end()) continue;
    const Eigen::Isometry3d& frame = grasp.from;  // where the update left it
    // The mean over the update's substeps; nothing simulated (paused): the last step's. The
    // grip's reaction already carries the held vertices' inertia (HairDynamics::gripWrench).
    chs::HoldingWrench hold = it->second.body->gripWrench(grasp.grip, frame.translation());
    if (grasp.samples > 0) {
      hold.force = grasp.sum.force / grasp.samples;
      hold.torque = grasp.sum.torque / grasp.samples;
    }
    grasp.sum = chs::HoldingWrench();
    grasp.samples = 0;
    // The lock pulls on the gripper with the opposite wrench, in the gripper frame.
    const Eigen::Vector3d f = frame.linear().transpose() * -hold.force;
    const Eigen::Vector3d t = frame.linear().transpose() * -hold.torque;
    geometry_msgs::WrenchStamped msg;
    msg.header.stamp = now;
    msg.header.frame_id = grasp.frame_id;
    msg.wrench.force.x = f.x();
    msg.wrench.force.y = f.y();
    msg.wrench.force.z = f.z();
    msg.wrench.torque.x = t.x();
    msg.wrench.torque.y = t.y();
    msg.wrench.torque.z = t.z();
    grasp.wrench_pub.publish(msg);
  }
}

}  // namespace chs_node
