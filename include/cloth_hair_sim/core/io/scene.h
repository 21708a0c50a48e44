#pragma once
#include <string>
#include <utility>
#include <vector>

#include "cloth_hair_sim/core/drape/drape_problem.h"
#include "cloth_hair_sim/core/fem_shell/fem_shell_solver.h"
#include "cloth_hair_sim/core/io/collider_spec.h"
#include "cloth_hair_sim/core/particle/particle_static_solver.h"
#include "cloth_hair_sim/core/solid_shell/solid_shell_solver.h"

namespace chs {

enum class DrapeMethod { kFemShell, kParticle, kSolidShell };
std::string methodName(DrapeMethod method);
// Throws InputError for anything but fem_shell | particle | solid_shell.
DrapeMethod parseMethod(const std::string& name);

// File names of a run's results, relative to directory (the drape tool's --out overrides it).
struct SceneOutput {
  std::string directory;  // default drape_output/<scene name>
  std::string obj = "draped.obj";
  std::string ply = "draped.ply";
  std::string report = "report.json";
  std::string convergence = "convergence.png";
  std::string picture = "drape.png";
};

// A drape scene file turned into a validated problem plus how to solve it and where to put the
// results. YAML, SI units (m, Pa, kg/m^2, N); every key is checked, unknown keys are errors:
//   name: text                          (default: the file's stem)
//   method: fem_shell | particle | solid_shell   (default fem_shell)
//   gravity: [gx, gy, gz]               (default [0, 0, -9.81])
//   garment: one of
//     rectangle: {size: [lx, ly], cells: [nx, ny], centre: [x, y, z]}
//     disc: {radius: r, cells: n_across, centre: [x, y, z]}
//     file: path | {path: p, scale: s, translate: [x, y, z]}  (path relative to the scene)
//     panels: [{name, rectangle: {size: [lx, ly], cells: [nx, ny]} | file: path | {path, scale},
//               position: [x, y, z], rpy: [r, p, y] | quaternion: [x, y, z, w]}, ...]
//       flat pieces to sew (a rectangle lies in its own x-y plane, centred on its origin, then
//       posed); flat_tolerance: t [m] (default 1e-4 of a panel's diagonal) bounds a panel's
//       vertices' distance from its best-fit plane
//   seams: [{a: {panel: name, side: left | right | bottom | top} | {panel, vertices: [..]},
//            b: {...}, reverse: false}, ...]   (garment panels only)
//     a's k-th vertex is sewn to b's k-th (b's run reversed with reverse: true); a rectangle's
//     sides run along its own +x (bottom, top) or +y (left, right); vertices index the panel's
//     own mesh and must lie on its boundary; both sides need as many vertices and lengths within
//     1%. Every method pulls the pairs together, then keeps them joined (DrapeProblem::seams).
//   material: preset name (cotton_eischen, wool_suiting) or {preset: name (optional),
//     young [Pa], poisson, thickness [m], areal_density [kg/m^2], shear_correction,
//     bending_rigidity [N m] (instead of young)}: without a preset all four are required;
//     or an orthotropic woven fabric (solid_shell only): {woven: preset name (wool_suiting_kes)
//     or {preset (optional), tensile_warp, tensile_weft [N/m], poisson, shear [N/m],
//     bending_warp, bending_weft [N m], thickness [m], areal_density [kg/m^2]},
//     warp: [x, y, z] (required: the warp direction in the flat garment)}
//   colliders: list of one-key mappings:
//     plane: {point, normal} | box: {min, max} | sphere: {centre, radius}
//     table: {top_centre: [x, y, z], size: [sx, sy], depth}   (a box below its top face)
//     pedestal | cylinder: {top_centre: [x, y, z], radius, depth}  (vertical axis)
//     capsule: {a: [x, y, z], b: [x, y, z], radius}  (a, b: the cap centres) or
//              {centre, axis, length, radius}  (length: between the cap centres)
//     mesh: {file: path (any assimp format, relative to the scene), scale: s | [sx, sy, sz],
//            position: [x, y, z], rpy: [r, p, y] (rad, R = Rz(y) Ry(p) Rx(r) as URDF) |
//            quaternion: [x, y, z, w], voxel_size [m] (default: see MeshSdfResolution),
//            parts: [node or mesh names] (default: all of the file)}
//       a closed triangle mesh as a signed distance field (MeshSdfSurface); the file's
//       coordinates are scaled, then rotated, then moved by position
//   boundary: {clamped: S, pinned: S, fixed: [{vertices: S, axes: [x, y, z]}],
//              loads: [{vertices: S, force: [..], moment: [..]}]}
//     S, a vertex selector: an index, a list of selectors, or one of {vertex: i},
//     {vertices: [..]}, {nearest: [x, y, z]}, {plane: {axis: x|y|z, value, tolerance}},
//     {box: {min, max}}, {boundary: true}
//   fem_shell: FemShellSettings fields by name (seam_steps for the seams)
//   solid_shell: SolidShellSettings fields by name; scheme: static | dynamic | energy,
//     thickness_strain: green | quasi_engineering; adaptive_levels (0-4), refine_threshold,
//     merge_margin, adapt_interval (dynamic), adapt_iterations (energy) for the adaptive 1-4
//     subdivision (results then come on the finest background mesh, the elements in use at the
//     end in active_mesh.obj)
//   particle: ParticleSettings fields by name (numbers and restart; sewing_stiffness,
//     seam_join_distance, max_sewing_iterations for the seams), with stretch_compression and
//     shear_compression for the network's D' and B'
//   output: {directory, obj, ply, report, convergence, picture}
struct Scene {
  std::string name;
  std::string file;  // the scene file, "" when parsed from text
  DrapeProblem problem;
  std::string material_name;            // preset name, "custom", or "<preset> (modified)"
  std::vector<ColliderSpec> colliders;  // problem.colliders was built from these, same order
  DrapeMethod method = DrapeMethod::kFemShell;
  FemShellSettings fem_shell;
  ParticleSettings particle;
  SolidShellSettings solid_shell;
  SceneOutput output;
};

// Throws InputError naming the file and the offending key (unknown keys, nonsense values,
// missing garment file, invalid mesh or boundary conditions).
Scene loadScene(const std::string& path);
// base_dir resolves garment file paths; name is used when the text has no `name`.
Scene parseScene(const std::string& yaml_text, const std::string& base_dir,
                 const std::string& name);

// Named values for reports.
std::vector<std::pair<std::string, double>> settingsList(const FemShellSettings& settings);
std::vector<std::pair<std::string, double>> settingsList(const ParticleSettings& settings);
std::vector<std::pair<std::string, double>> materialList(const ShellMaterial& material);
std::vector<std::pair<std::string, double>> settingsList(const SolidShellSettings& settings);
std::vector<std::pair<std::string, double>> materialList(const WovenFabric& fabric);

}  // namespace chs
