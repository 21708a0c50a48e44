#pragma once
#include <string>

#include <ros/node_handle.h>
#include <Eigen/Core>

#include "cloth_hair_sim/core/mpm/hybrid_shell_dynamics.h"
#include "cloth_hair_sim/core/particle/particle_dynamics.h"
#include "cloth_hair_sim/core/world/world.h"

namespace chs_node {

// The node's parameters (private namespace, REP 103 units). Colliders are read separately.
struct SimParams {
  std::string world_frame = "world";
  // mpm: the hybrid Lagrangian/MPM subdivision shell (Han ch. 5); particle: seed 000's
  // particle network with RK4.
  std::string dynamics_backend = "mpm";
  double dt = 1e-3;               // [s] largest substep (garments may need smaller: stable step)
  double step_rate = 100.0;       // [Hz] updates per second
  double real_time_factor = 1.0;  // simulated / wall (or /clock) seconds; 0: as fast as possible
  // The node is the clock (run with /use_sim_time): it publishes /clock, advanced by what it
  // simulates, so that the nodes moving its inputs (a robot, a mannequin's animator) move at the
  // speed it simulates however far below real time that is. Off: it follows wall or /clock time.
  bool publish_clock = false;
  int max_substeps = 500;  // per update; beyond it the simulation falls behind
  // [s] an update takes no more substeps than fit in this much wall time at the last update's
  // cost per substep: it holds the simulation's mutex, so services wait for it.
  double max_update_wall = 0.05;
  // [s] of their motion the kinematic inputs (colliders, frame pins, grasps, hair roots) may lag
  // their tf frames when the simulation falls behind real time: they move at their real speed
  // in simulated time and catch up later. Beyond it the rest of their motion is squeezed into
  // the update, faster than real (0: always squeezed).
  double max_input_lag = 0.5;
  double status_rate = 10.0;   // [Hz]
  double marker_rate = 10.0;   // [Hz]
  bool show_colliders = true;  // collider markers in the "colliders" namespace
  Eigen::Vector3d gravity = Eigen::Vector3d(0.0, 0.0, -9.81);  // [m/s^2] in the world frame
  double damping = 0.5;      // [1/s] viscous damping of either backend
  double max_speed = 50.0;   // [m/s] a faster vertex counts as a diverged step
  double tf_timeout = 0.01;  // [s] wait for a collider's transform in each update
  // [s] a tf frame whose latest transform is older counts as missing (stale; 0: any age).
  double tf_max_age = 1.0;
  // Backend settings: ~damping goes to both; the hybrid shell's own under ~mpm/.
  chs::ParticleDynamicsSettings particle;
  chs::HybridShellSettings mpm;
  // The one world the mpm garments share (grid spacing and kernel from ~mpm/, contact between
  // garments: ~mpm/body_friction, ~mpm/contact_distance).
  chs::WorldSettings world;
};

// Reads ~ parameters over the defaults; throws chs::InputError naming a bad one.
SimParams loadSimParams(const ros::NodeHandle& private_nh);

}  // namespace chs_node
