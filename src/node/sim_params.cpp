#include "cloth_hair_sim/node/sim_params.h"

#include <cmath>
#include <vector>

#include "cloth_hair_sim/core/common/input_error.h"

namespace chs_node {
namespace {

void requirePositive(const std::string& name, double value) {
  if (!(value > 0.0) || !std::isfinite(value))
    throw chs::InputError("parameter ~" + name + " must be positive and finite");
}

}  // namespace

SimParams loadSimParams(const ros::NodeHandle& nh) {
  SimParams p;
  nh.param("world_frame", p.world_frame, p.world_frame);
  nh.param("dynamics_backend", p.dynamics_backend, p.dynamics_backend);
  nh.param("dt", p.dt, p.dt);
  nh.param("step_rate", p.step_rate, p.step_rate);
  nh.param("real_time_factor", p.real_time_factor, p.real_time_factor);
  nh.param("max_substeps", p.max_substeps, p.max_substeps);
  nh.param("status_rate", p.status_rate, p.status_rate);
  nh.param("marker_rate", p.marker_rate, p.marker_rate);
  nh.param("show_colliders", p.show_colliders, p.show_colliders);
  nh.param("damping", p.damping, p.damping);
  nh.param("max_speed", p.max_speed, p.max_speed);
  nh.param("tf_timeout", p.tf_timeout, p.tf_timeout);
  std::vector<double> g;
  if (nh.getParam("gravity", g)) {
    if (g.size() != 3) throw chs::InputError("parameter ~gravity must be [gx, gy, gz]");
    p.gravity = Eigen::Vector3d(g[0], g[1], g[2]);
    if (!p.gravity.allFinite()) throw chs::InputError("parameter ~gravity must be finite");
  }

  if (p.world_frame.empty()) throw chs::InputError("parameter ~world_frame must not be empty");
  if (p.dynamics_backend != "particle")
    throw chs::InputError("parameter ~dynamics_backend '" + p.dynamics_backend +
                          "' is unknown: the only backend so far is particle");
  requirePositive("dt", p.dt);
  requirePositive("step_rate", p.step_rate);
  requirePositive("status_rate", p.status_rate);
  requirePositive("marker_rate", p.marker_rate);
  requirePositive("max_speed", p.max_speed);
  if (!(p.real_time_factor >= 0.0) || !std::isfinite(p.real_time_factor))
    throw chs::InputError("parameter ~real_time_factor must be >= 0 (0: as fast as possible)");
  if (p.max_substeps < 1) throw chs::InputError("parameter ~max_substeps must be at least 1");
  if (!(p.damping >= 0.0) || !std::isfinite(p.damping))
    throw chs::InputError("parameter ~damping must be >= 0");
  if (!(p.tf_timeout >= 0.0) || !std::isfinite(p.tf_timeout))
    throw chs::InputError("parameter ~tf_timeout must be >= 0");
  return p;
}

}  // namespace chs_node
