#pragma once
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "cloth_hair_sim/core/contact/collider_shape.h"
#include "cloth_hair_sim/core/contact/scripted_motion.h"
#include "cloth_hair_sim/core/drape/drape_problem.h"
#include "cloth_hair_sim/core/mpm/hybrid_shell_dynamics.h"
#include "cloth_hair_sim/core/rod/groom.h"
#include "cloth_hair_sim/core/rod/hair_dynamics.h"
#include "cloth_hair_sim/core/rod/rod_material.h"
#include "cloth_hair_sim/core/world/world.h"

namespace chs {

// A simulation scene file for the simulate tool: garments as bodies of one World
// (world/world.h), scripted rigid obstacles, and how long and how often to record. YAML, SI
// units (m, s, rad, Pa, kg/m^2); every key is checked, unknown keys are errors:
//   name: text                          (default: the file's stem)
//   duration: s                         (default 1)
//   frame_rate: frames per s            (default 30)
//   max_substeps_per_frame: n           (default 10000; a frame that needs more stops the run)
//   gravity: [gx, gy, gz]               (default [0, 0, -9.81])
//   world:                              (all optional)
//     grid_spacing: dx                  (0: the first body's mean control edge)
//     kernel_degree: 2 | 3
//     body_friction: mu between bodies  (default 0.3)
//     contact_distance: m               (0: a quarter of dx)
//     damping: 1/s                      (viscous, on the grid)
//     integration: symplectic_euler | backward_euler | lagrangian_implicit
//     max_time_step: s                  (backward Euler's longest step, default 1/240)
//     safety: fraction of the explicit stability bound taken (default 0.5)
//     cfl: fraction of dx a particle may move in a step (default 0.3)
//     contact_between_layers_only, cfl_between_layers_only: true | false, flip_blend: 0..1,
//     lagrangian_tolerance: m/s, lagrangian_gravity_fraction: 0..1
//                                       (the lagrangian_* steps, HybridShellSettings)
//     display_segments: n               (limit-surface triangles per face edge in the meshes)
//   bodies: a list of garments (bodies and hair: at least one in all), each
//     name: a letter, then letters, digits or _   (default body<i>)
//     rectangle: {size: [lx, ly], cells: [nx, ny], centre: [x, y, z]}  or
//     mesh: path | {file: path, scale: s}        (quad mesh; path relative to the scene)
//     position: [x, y, z], rotation: [roll, pitch, yaw]  (the geometry's pose; default none)
//     material: preset name (cotton_eischen, wool_suiting) or {preset, young, poisson,
//       thickness, areal_density, shear_correction, bending_rigidity}
//     pins: a vertex selector, in the posed (world) coordinates: an index, a list of selectors,
//       or one of {vertex: i}, {vertices: [..]}, {nearest: [x, y, z]},
//       {plane: {axis: x|y|z, value, tolerance}}, {box: {min, max}}, {boundary: true}
//     velocity: [vx, vy, vz]            (initial, of the free vertices)
//   hair: a list of hair bodies (discrete elastic rods, rod/hair_dynamics.h), each
//     name: as for bodies               (default hair<i>; unique among bodies and hair)
//     groom: {strands, length, segments, radii: r | [a, b, c], centre: [x, y, z],
//       direction: [..], cone_angle: rad, curl_radius, curl_pitch, seed}  (rod/groom.h) or
//     file: path | {file: path, scale: s, segments: n}  (io/strand_file.h; resampled to n)
//     position: [x, y, z], rotation: [roll, pitch, yaw]  (the groom's pose; default none)
//     material: human_hair | {preset, young, shear, radius, density}
//     roots: fixed | loose | <collider name>  (clamped in place, free, or carried by that
//       collider's scripted motion; default fixed)
//     pic_blend: xi of Han (4.12)      (default 0)
//     continuum: {enabled, youngs_modulus, poisson_ratio, friction, contact_blend}
//       (the strands' frictional contact on the grid, HairSettings::continuum; default off)
//   colliders: a list of
//     name: as for bodies               (default: the kind and its index, e.g. sphere0)
//     one kind: plane: {} (solid below the frame's z = 0) | sphere: {radius}
//       | box: {size: [sx, sy, sz], edge_radius} | table: {size: [sx, sy], depth, edge_radius}
//       (a box whose top face is centred on the frame) | cylinder: {radius, length, edge_radius}
//       (axis z) | capsule: {radius, length} (cap centres length apart along z)
//       | mesh: {file, scale, voxel_size} (a closed triangle mesh as a distance field)
//     position: [x, y, z], rotation: [roll, pitch, yaw]  (the frame's pose at t = 0)
//     friction: Coulomb mu with the cloth   (default 0.3)
//     motion: {linear_velocity: [..], angular_velocity: [..]} (about the frame's origin) or
//       {keyframes: [{time, position, rotation}, ..]} (times increasing, linear in between)
struct SimulationBody {
  std::string name;
  DrapeProblem problem;  // the posed mesh, material, gravity and pins (bc.pinned), no colliders
  std::string material_name;
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
};

struct SimulationHair {
  std::string name;
  rod::Polylines strands;  // posed, in world coordinates at t = 0
  rod::RodMaterial material;
  std::string material_name;
  std::string roots = "fixed";  // fixed, loose or a collider's name
  int root_collider = -1;       // its index among the scene's colliders, or -1
  double pic_blend = 0.0;
  rod::StrandContinuumSettings continuum;
};

struct SimulationCollider {
  std::string name;
  std::string kind;     // as written: plane, sphere, box, table, cylinder, capsule, mesh
  ColliderShape shape;  // in the collider's frame (a table's offset puts its top at the origin)
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  // of the frame at t = 0
  ScriptedMotion motion;
  double friction = 0.3;

  Eigen::Isometry3d poseAt(double t) const { return motion.pose(pose, t); }
  std::shared_ptr<const RigidSurface> surfaceAt(double t) const {
    return shape.makeSurface(poseAt(t));
  }
};

struct SimulationScene {
  std::string name;
  std::string file;  // "" when parsed from text
  double duration = 1.0, frame_rate = 30.0;
  int max_substeps_per_frame = 10000;
  Eigen::Vector3d gravity = Eigen::Vector3d(0.0, 0.0, -9.81);
  WorldSettings world;
  HybridShellSettings shell;  // every body's; grid spacing and kernel degree are the world's
  std::vector<SimulationBody> bodies;
  std::vector<SimulationHair> hair;
  std::vector<SimulationCollider> colliders;

  // Frames after the initial state: duration * frame_rate, rounded up.
  int numFrames() const;
};

// Throws InputError naming the file and the offending key (unknown keys, nonsense values, a
// missing mesh file, a pin out of range, duplicate names).
SimulationScene loadSimulationScene(const std::string& path);
// base_dir resolves mesh paths; name is used when the text has no `name`.
SimulationScene parseSimulationScene(const std::string& yaml_text, const std::string& base_dir,
                                     const std::string& name);

}  // namespace chs
