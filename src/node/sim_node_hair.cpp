// ~load_hair and ~remove_hair: hair as a rod body of the node's world (core/rod/hair_dynamics.h).
#include <Eigen/Geometry>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/common/names.h"
#include "cloth_hair_sim/node/sim_node.h"

namespace chs_node {

chs::rod::HairSettings SimNode::hairSettings() const {
  chs::rod::HairSettings s;
  s.grid_spacing = world_.gridSpacing() > 0.0 ? world_.gridSpacing() : hair_grid_spacing_;
  s.kernel_degree = params_.world.kernel_degree;
  s.gravity = params_.gravity;
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
    std::lock_guard<std::mutex> lock(mutex_);
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
      std::lock_guard<std::mutex> lock(mutex_);
      settings = hairSettings();
    }
    // Built and checked off the lock (a strand file may be large); the world is touched last.
    Hair h = buildHair(req, world_from_frame, settings, hair_display_strands_);
    std::lock_guard<std::mutex> lock(mutex_);
    if (garments_.count(req.name) || hairs_.count(req.name))
      return refuse("a garment or hair of that name was loaded meanwhile");
    world_.add(req.name, h.body);  // refuses a body off the world's grid (it changed meanwhile)
    res.strands = h.body->numStrands();
    res.vertices = h.numVertices();
    res.success = true;
    res.message = who + "loaded, " + std::to_string(res.strands) + " strands, " +
                  std::to_string(res.vertices) + " vertices, " + std::to_string(h.display.size()) +
                  " display strands, material " + h.material_name + ", roots on frame '" +
                  h.frame_id + "'";
    hairs_.emplace(req.name, std::move(h));
    substep_cost_ = 0.0;  // the world grew: the next update probes its cost
  } catch (const std::exception& e) {
    return refuse(e.what());
  }
  ROS_INFO("%s", res.message.c_str());
  return true;
}

bool SimNode::removeHair(cloth_hair_sim::RemoveGarment::Request& req,
                         cloth_hair_sim::RemoveGarment::Response& res) {
  std::lock_guard<std::mutex> lock(mutex_);
  res.success = hairs_.erase(req.name) > 0;
  if (res.success) world_.remove(req.name);
  res.message = "hair '" + req.name + "': " + (res.success ? "removed" : "not loaded");
  return true;
}

}  // namespace chs_node
