#pragma once
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "cloth_hair_sim/core/contact/rigid_surface.h"
#include "cloth_hair_sim/core/material/shell_material.h"
#include "cloth_hair_sim/core/material/woven_fabric.h"
#include "cloth_hair_sim/core/mesh/quad_mesh.h"

namespace chs {

// A prescribed nodal force and moment (the moment acts on the director; used by the beam cases).
struct NodalLoad {
  int vertex = -1;
  Eigen::Vector3d force = Eigen::Vector3d::Zero();
  Eigen::Vector3d moment = Eigen::Vector3d::Zero();
};

// A single translational degree of freedom held at its initial value.
struct FixedComponent {
  int vertex = -1;
  int axis = 0;  // 0 = x, 1 = y, 2 = z
};

struct BoundaryConditions {
  std::vector<int> clamped;  // position and director held
  std::vector<int> pinned;   // position held, director free
  std::vector<FixedComponent> fixed_components;
  std::vector<NodalLoad> loads;  // scaled by the load factor
};

// A seam (seed 000 section 3.2.1): side_a[i] is sewn to side_b[i]. The sides are runs of
// boundary vertices, possibly on different panels of one mesh, listed in matching order.
struct Seam {
  std::vector<int> side_a, side_b;
};

// A static drape: a garment in its flat (stress-free) state, its material, gravity, the rigid
// obstacles and the boundary conditions. Shared by the FEM shell and the particle method.
struct DrapeProblem {
  QuadMesh mesh;  // reference (stress-free) configuration
  ShellMaterial material;
  // An orthotropic woven fabric (solid_shell method only); material then holds its isotropic
  // equivalent (thickness, areal density, E from the mean bending rigidity).
  std::optional<WovenFabric> fabric;
  Eigen::Vector3d gravity = Eigen::Vector3d(0.0, 0.0, -9.81);
  RigidSurfaces colliders;
  BoundaryConditions bc;
  // Seams between the panels (pairs of boundary vertices): each method first pulls them
  // together, then keeps them joined (the particle method merges the particles, the FEM shell
  // ties the positions, see solveFemShell).
  std::vector<Seam> seams;

  // Throws InputError naming the problem: material, mesh, indices out of range.
  void validate() const;
  // A static solve also needs something to hold the garment: throws InputError when nothing is
  // clamped, pinned or fixed and there is no collider (dynamics may fall freely).
  void checkStaticSupport() const;
};

// Contact force a rigid surface exerts on one vertex.
struct ContactReaction {
  int vertex = -1;
  int surface = -1;  // index into DrapeProblem::colliders
  Eigen::Vector3d force = Eigen::Vector3d::Zero();
};

// One line of progress: shown while a solve runs, kept for the report.
struct ProgressEvent {
  int load_step = 0;
  double load_factor = 0.0;
  int iteration = 0;
  double residual = 0.0;  // relative residual norm
  int active_contacts = 0;
  int total_iterations = 0;  // of the whole solve so far (iteration restarts each load step)
  // On a coarser grid of a nested start (FemShellSettings::coarse_levels): how many levels below
  // the problem's own; 0 on the problem's grid.
  int coarser_grids = 0;
};
using ProgressCallback = std::function<void(const ProgressEvent&)>;

// Stability of the returned state (FEM shell): the lowest eigenvalue of the symmetrised,
// constrained tangent scaled to unit diagonal (core/solver/stability.h).
struct DrapeStability {
  bool assessed = false;  // false: not an equilibrium, or no eigenvalue computed
  double lowest_eigenvalue = 0.0;
  int negative_eigenvalues = 0;
  bool stable = false;
  std::string verdict;  // "stable", "unstable (saddle)", or why it was not assessed
};

struct DrapeResult {
  bool converged = false;
  bool cancelled = false;  // stopped on request (a CancelFlag): positions hold the last good state
  std::string status;      // what happened, in words
  std::vector<Eigen::Vector3d> positions;
  std::vector<Eigen::Vector3d> directors;  // FEM shell only (unit normals of the fibres)
  // The mesh positions are on when the solver refined the problem's (the adaptive solid shell's
  // finest background mesh, its inactive nodes interpolated); empty: the problem's mesh.
  std::optional<QuadMesh> refined_mesh;
  // Its elements in use at the end (a triangle's fourth node -1) and the most nodes in use at once.
  std::vector<std::array<int, 4>> active_elements;
  int peak_active_nodes = 0;
  int load_steps = 0;
  int iterations = 0;  // total Newton (or relaxation) iterations
  // Of those, the ones on the coarser grids of a nested start (FemShellSettings::coarse_levels).
  int coarse_iterations = 0;
  double load_factor = 0.0;
  double residual = 0.0;
  std::vector<ProgressEvent> history;
  std::vector<ContactReaction> reactions;
  double wall_time_s = 0.0;
  DrapeStability stability;
};

}  // namespace chs
