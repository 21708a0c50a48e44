// dynamic_reconfigure of cloth_hair_sim_node (cfg/Sim.cfg): the values a user tunes live.
#include <cmath>
#include <string>

#include "cloth_hair_sim/node/live_material.h"
#include "cloth_hair_sim/node/sim_node.h"

namespace chs_node {
namespace {

bool nonNegative(double value) {
  return std::isfinite(value) && value >= 0.0;
}

}  // namespace

void SimNode::startReconfigure() {
  reconfigure_ = std::make_unique<dynamic_reconfigure::Server<cloth_hair_sim::SimConfig>>(
      reconfigure_mutex_, pnh_);
  // The server starts from its own defaults and same-named parameters; it shows the node's
  // values instead (~gravity is one list here, three numbers there).
  cloth_hair_sim::SimConfig c;
  reconfigure_->getConfigDefault(c);
  c.real_time_factor = params_.real_time_factor;
  c.damping = params_.damping;
  c.gravity_x = params_.gravity.x();
  c.gravity_y = params_.gravity.y();
  c.gravity_z = params_.gravity.z();
  c.show_colliders = params_.show_colliders;
  c.marker_rate = params_.marker_rate;
  reconfigure_->updateConfig(c);
  live_ = c;
  reconfigure_->setCallback(
      [this](cloth_hair_sim::SimConfig& config, uint32_t) { onReconfigure(config); });
}

void SimNode::onReconfigure(cloth_hair_sim::SimConfig& c) {
  const WorldLock lock(*this);
  // Each refused value goes back to the last accepted one, which the server then reports.
  auto refuse = [](const std::string& what) {
    ROS_ERROR("dynamic_reconfigure: %s; the previous value is kept", what.c_str());
  };
  if (c.real_time_factor != live_.real_time_factor) {
    if (nonNegative(c.real_time_factor)) {
      params_.real_time_factor = c.real_time_factor;
      ROS_INFO("dynamic_reconfigure: real_time_factor %g", c.real_time_factor);
    } else {
      refuse("real_time_factor " + std::to_string(c.real_time_factor) +
             " must be >= 0 (0: as fast as possible)");
      c.real_time_factor = live_.real_time_factor;
    }
  }
  if (c.damping != live_.damping) {
    if (nonNegative(c.damping)) {
      params_.damping = params_.particle.damping = params_.mpm.damping = c.damping;
      for (auto& [name, g] : garments_) g.dynamics->setDamping(c.damping);
      ROS_INFO("dynamic_reconfigure: damping %g 1/s", c.damping);
    } else {
      refuse("damping " + std::to_string(c.damping) + " must be >= 0 (1/s)");
      c.damping = live_.damping;
    }
  }
  const Eigen::Vector3d gravity(c.gravity_x, c.gravity_y, c.gravity_z);
  if (gravity != params_.gravity) {
    if (gravity.allFinite()) {
      params_.gravity = gravity;
      for (auto& [name, g] : garments_) {
        g.reference.gravity = gravity;
        g.dynamics->setGravity(gravity);
      }
      ROS_INFO("dynamic_reconfigure: gravity (%g, %g, %g) m/s^2", gravity.x(), gravity.y(),
               gravity.z());
    } else {
      refuse("gravity must be finite");
      c.gravity_x = live_.gravity_x;
      c.gravity_y = live_.gravity_y;
      c.gravity_z = live_.gravity_z;
    }
  }
  params_.show_colliders = c.show_colliders;
  if (c.marker_rate != live_.marker_rate) {
    if (std::isfinite(c.marker_rate) && c.marker_rate > 0.0) {
      params_.marker_rate = c.marker_rate;
      marker_timer_.setPeriod(ros::Duration(1.0 / c.marker_rate));
    } else {
      refuse("marker_rate " + std::to_string(c.marker_rate) + " must be positive (Hz)");
      c.marker_rate = live_.marker_rate;
    }
  }
  reconfigureMaterial(c);
  live_ = c;
  refreshCatalogue();  // load_params_: garments loaded from now on take the new damping
}

void SimNode::reconfigureMaterial(cloth_hair_sim::SimConfig& c) {
  auto show = [&](const Garment* g) {
    const chs::ShellMaterial none;
    const chs::ShellMaterial& m = g ? g->reference.material : none;
    c.young = m.young;
    c.poisson = m.poisson;
    c.thickness = m.thickness;
    c.areal_density = m.areal_density;
    c.self_friction = !g || params_.dynamics_backend != "mpm" ? 0.0
                      : g->self_friction                      ? *g->self_friction
                                                              : params_.mpm.contact.friction;
  };
  const auto it = garments_.find(c.garment);
  if (c.garment != live_.garment) {  // a new selection shows its garment's values
    if (c.garment.empty() || it != garments_.end()) {
      show(c.garment.empty() ? nullptr : &it->second);
    } else {
      ROS_ERROR("dynamic_reconfigure: garment '%s' is not loaded; the selection stays '%s'",
                c.garment.c_str(), live_.garment.c_str());
      c.garment = live_.garment;
      const auto kept = garments_.find(c.garment);
      show(kept == garments_.end() ? nullptr : &kept->second);
    }
    return;
  }
  MaterialChange change;
  auto changed = [](double now, double before, std::optional<double>& field) {
    if (now != before) field = now;  // NaN != anything: taken, then refused by the checks
  };
  changed(c.young, live_.young, change.young);
  changed(c.poisson, live_.poisson, change.poisson);
  changed(c.thickness, live_.thickness, change.thickness);
  changed(c.areal_density, live_.areal_density, change.areal_density);
  changed(c.self_friction, live_.self_friction, change.self_friction);
  if (!change.young && !change.poisson && !change.thickness && !change.areal_density &&
      !change.self_friction)
    return;
  if (it == garments_.end()) {
    const std::string why = c.garment.empty()
                                ? "no garment is selected (set garment to a loaded one)"
                                : "garment '" + c.garment + "' is not loaded";
    ROS_ERROR("dynamic_reconfigure: material: %s; nothing changed", why.c_str());
    show(nullptr);
    return;
  }
  Garment& g = it->second;
  try {
    changeMaterial(g, change, garmentParams());
    world_ = worldOf(garments_);
  } catch (const std::exception& e) {
    ROS_ERROR("dynamic_reconfigure: garment '%s': %s; the previous material is kept",
              g.name.c_str(), e.what());
    show(&g);
    return;
  }
  g.generation = next_generation_++;  // a drape solve under way used the old material
  g.dynamics->setColliders(colliders_.surfaces(), {}, colliders_.frictions());
  for (auto& [name, grasp] : grasps_)
    if (grasp.garment == g.name) grasp.attachment.pinAt(*g.dynamics, 1.0);
  show(&g);
  refreshCatalogue();  // the material's name
  const chs::ShellMaterial& m = g.reference.material;
  ROS_INFO(
      "dynamic_reconfigure: garment '%s': E %g Pa, nu %g, thickness %g m, %g kg/m^2, self "
      "friction %g",
      g.name.c_str(), m.young, m.poisson, m.thickness, m.areal_density, c.self_friction);
}

}  // namespace chs_node
