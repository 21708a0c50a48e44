// SimNode's side of /diagnostics: what the simulation state says about its health.
#include <chrono>

#include "cloth_hair_sim/node/sim_node.h"

namespace chs_node {

HealthSample SimNode::healthSample() {
  HealthSample h;
  const WorldLock lock(*this);
  h.stamp = ros::Time::now();
  h.running = !paused_ && !garments_.empty();
  h.sim_time = sim_time_;
  h.last_update_rtf = last_.real_time_factor;
  h.rollbacks = rollbacks_;
  h.unconverged_solves = unconverged_solves_;
  for (const auto& [name, g] : garments_) {
    h.diverged_stops[name] = g.diverged_stops;
    for (const auto& a : g.frame_pins)
      if (a.stale) h.stale_frames.push_back("frame '" + a.frame_id + "' (pins of '" + name + "')");
  }
  for (const auto& [name, grasp] : grasps_)
    if (grasp.attachment.stale)
      h.stale_frames.push_back("frame '" + grasp.attachment.frame_id + "' (grasp '" + name + "')");
  for (const auto& c : colliders_.colliders())
    if (c.stale)
      h.stale_frames.push_back("collider '" + c.name + "' (frame '" + c.frame_id + "', " +
                               (c.has_pose ? "holding its last pose" : "never seen") + ")");
  h.drape_running = drape_running_;
  if (h.drape_running) {
    h.drape_garment = drape_garment_;
    h.drape_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - drape_started_).count();
  }
  return h;
}

}  // namespace chs_node
