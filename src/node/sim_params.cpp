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

// ~mpm/ parameters of the hybrid shell; the HybridShellDynamics constructor validates them
// again when a garment loads, this names the parameter at startup.
void loadHybridShellSettings(const ros::NodeHandle& nh, chs::HybridShellSettings& s) {
  nh.param("grid_spacing", s.grid_spacing, s.grid_spacing);
  nh.param("kernel_degree", s.kernel_degree, s.kernel_degree);
  nh.param("cfl", s.cfl, s.cfl);
  nh.param("rpic_damping", s.rpic_damping, s.rpic_damping);
  nh.param("safety", s.safety, s.safety);
  nh.param("quadrature_per_edge", s.kirchhoff_love.in_plane_order, s.kirchhoff_love.in_plane_order);
  std::string rule = "gauss";
  nh.param("thickness_rule", rule, rule);
  if (rule == "gauss")
    s.kirchhoff_love.thickness_rule = chs::ThicknessRule::kGauss;
  else if (rule == "han")
    s.kirchhoff_love.thickness_rule = chs::ThicknessRule::kHanQuarter;
  else
    throw chs::InputError("parameter ~mpm/thickness_rule '" + rule + "': use gauss or han");
  double yield = 0.0;  // <= 0 here: purely elastic
  nh.param("yield_stress", yield, yield);
  if (!std::isfinite(yield)) throw chs::InputError("parameter ~mpm/yield_stress must be finite");
  if (yield > 0.0) s.yield_stress = yield;
  nh.param("contact_particles_per_edge", s.contact_particles_per_edge,
           s.contact_particles_per_edge);
  nh.param("contact_normal_stiffness", s.contact.normal_stiffness, s.contact.normal_stiffness);
  nh.param("contact_shear_stiffness", s.contact.shear_stiffness, s.contact.shear_stiffness);
  nh.param("self_friction", s.contact.friction, s.contact.friction);
  nh.param("display_segments", s.display_segments, s.display_segments);
  nh.param("surface_collisions", s.surface_collisions, s.surface_collisions);
  std::string integration = "symplectic_euler";
  nh.param("integration", integration, integration);
  try {
    s.integration = chs::timeIntegrationFromName(integration);
  } catch (const chs::InputError& e) {
    throw chs::InputError(std::string("parameter ~mpm/") + e.what());
  }
  nh.param("implicit_tolerance", s.implicit_tolerance, s.implicit_tolerance);
  nh.param("lagrangian_tolerance", s.lagrangian_tolerance, s.lagrangian_tolerance);
  nh.param("lagrangian_gravity_fraction", s.lagrangian_gravity_fraction,
           s.lagrangian_gravity_fraction);
  if (!(s.lagrangian_gravity_fraction >= 0.0 && s.lagrangian_gravity_fraction < 1.0))
    throw chs::InputError("parameter ~mpm/lagrangian_gravity_fraction must lie in [0, 1)");
  nh.param("contact_between_layers_only", s.contact_between_layers_only,
           s.contact_between_layers_only);
  nh.param("cfl_between_layers_only", s.cfl_between_layers_only, s.cfl_between_layers_only);
  nh.param("flip_blend", s.flip_blend, s.flip_blend);
  nh.param("max_newton_iterations", s.max_newton_iterations, s.max_newton_iterations);
  nh.param("elastic_max_iterations", s.elastic_max_iterations, s.elastic_max_iterations);
  nh.param("obstacle_stiffness", s.obstacle_stiffness, s.obstacle_stiffness);
  nh.param("obstacle_point_stiffness", s.obstacle_point_stiffness, s.obstacle_point_stiffness);
  nh.param("obstacle_offset", s.obstacle_offset, s.obstacle_offset);
  nh.param("obstacle_friction_velocity", s.obstacle_friction_velocity,
           s.obstacle_friction_velocity);
  nh.param("max_krylov_iterations", s.max_krylov_iterations, s.max_krylov_iterations);
  if (!(s.implicit_tolerance > 0.0) || !(s.lagrangian_tolerance > 0.0) ||
      s.max_newton_iterations < 1 || s.max_krylov_iterations < 1 || s.elastic_max_iterations < 1)
    throw chs::InputError(
        "parameters ~mpm/implicit_tolerance, ~mpm/lagrangian_tolerance, "
        "~mpm/max_newton_iterations, ~mpm/elastic_max_iterations and ~mpm/max_krylov_iterations "
        "must be positive");
  if (s.kernel_degree != 2 && s.kernel_degree != 3)
    throw chs::InputError("parameter ~mpm/kernel_degree must be 2 or 3");
  if (s.kirchhoff_love.in_plane_order < 2 || s.kirchhoff_love.in_plane_order > 4)
    throw chs::InputError(
        "parameter ~mpm/quadrature_per_edge must lie in 2..4 (1 leaves the shell spurious "
        "zero-energy modes)");
  if (!(s.cfl > 0.0 && s.safety > 0.0 && s.rpic_damping >= 0.0 && s.rpic_damping <= 1.0))
    throw chs::InputError(
        "parameters ~mpm/cfl and ~mpm/safety must be positive, "
        "~mpm/rpic_damping in [0, 1]");
}

}  // namespace

SimParams loadSimParams(const ros::NodeHandle& nh) {
  SimParams p;
  nh.param("world_frame", p.world_frame, p.world_frame);
  nh.param("dynamics_backend", p.dynamics_backend, p.dynamics_backend);
  nh.param("dt", p.dt, p.dt);
  nh.param("step_rate", p.step_rate, p.step_rate);
  nh.param("real_time_factor", p.real_time_factor, p.real_time_factor);
  nh.param("publish_clock", p.publish_clock, p.publish_clock);
  nh.param("max_substeps", p.max_substeps, p.max_substeps);
  nh.param("max_update_wall", p.max_update_wall, p.max_update_wall);
  nh.param("max_input_lag", p.max_input_lag, p.max_input_lag);
  nh.param("status_rate", p.status_rate, p.status_rate);
  nh.param("marker_rate", p.marker_rate, p.marker_rate);
  nh.param("show_colliders", p.show_colliders, p.show_colliders);
  nh.param("damping", p.damping, p.damping);
  nh.param("max_speed", p.max_speed, p.max_speed);
  nh.param("tf_timeout", p.tf_timeout, p.tf_timeout);
  // Waiting for a transform waits for the clock to advance, and with ~publish_clock that clock
  // is this node's own, stopped while it waits: take the latest transform instead.
  if (p.publish_clock) p.tf_timeout = 0.0;
  nh.param("tf_max_age", p.tf_max_age, p.tf_max_age);
  std::vector<double> g;
  if (nh.getParam("gravity", g)) {
    if (g.size() != 3) throw chs::InputError("parameter ~gravity must be [gx, gy, gz]");
    p.gravity = Eigen::Vector3d(g[0], g[1], g[2]);
    if (!p.gravity.allFinite()) throw chs::InputError("parameter ~gravity must be finite");
  }

  if (p.world_frame.empty()) throw chs::InputError("parameter ~world_frame must not be empty");
  if (p.dynamics_backend != "particle" && p.dynamics_backend != "mpm")
    throw chs::InputError("parameter ~dynamics_backend '" + p.dynamics_backend +
                          "' is unknown: use mpm or particle");
  requirePositive("dt", p.dt);
  requirePositive("step_rate", p.step_rate);
  requirePositive("status_rate", p.status_rate);
  requirePositive("marker_rate", p.marker_rate);
  requirePositive("max_speed", p.max_speed);
  if (!(p.real_time_factor >= 0.0) || !std::isfinite(p.real_time_factor))
    throw chs::InputError("parameter ~real_time_factor must be >= 0 (0: as fast as possible)");
  if (p.max_substeps < 1) throw chs::InputError("parameter ~max_substeps must be at least 1");
  requirePositive("max_update_wall", p.max_update_wall);
  if (!(p.max_input_lag >= 0.0) || !std::isfinite(p.max_input_lag))
    throw chs::InputError("parameter ~max_input_lag must be >= 0 (0: no lag)");
  if (!(p.damping >= 0.0) || !std::isfinite(p.damping))
    throw chs::InputError("parameter ~damping must be >= 0");
  if (!(p.tf_timeout >= 0.0) || !std::isfinite(p.tf_timeout))
    throw chs::InputError("parameter ~tf_timeout must be >= 0");
  if (!(p.tf_max_age >= 0.0) || !std::isfinite(p.tf_max_age))
    throw chs::InputError("parameter ~tf_max_age must be >= 0 (0: any age)");
  p.particle.damping = p.damping;
  loadHybridShellSettings(ros::NodeHandle(nh, "mpm"), p.mpm);
  p.mpm.damping = p.damping;
  p.mpm.max_time_step = p.dt;  // backward Euler's step: ~dt, shortened by the CFL condition
  const ros::NodeHandle mpm(nh, "mpm");
  mpm.param("body_friction", p.world.body_friction, p.world.body_friction);
  mpm.param("contact_distance", p.world.contact_distance, p.world.contact_distance);
  mpm.param("max_particles", p.world.max_particles, p.world.max_particles);
  p.world.grid_spacing = p.mpm.grid_spacing;
  p.world.kernel_degree = p.mpm.kernel_degree;
  p.world.cfl = p.mpm.cfl;  // between garments as within each
  if (!(p.world.body_friction >= 0.0) || !std::isfinite(p.world.body_friction))
    throw chs::InputError("parameter ~mpm/body_friction must be >= 0");
  if (!std::isfinite(p.world.contact_distance))
    throw chs::InputError("parameter ~mpm/contact_distance must be finite");
  if (p.world.max_particles < 1)
    throw chs::InputError("parameter ~mpm/max_particles must be at least 1");
  return p;
}

}  // namespace chs_node
