#pragma once
#include <limits>
#include <memory>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "cloth_hair_sim/core/drape/drape_problem.h"
#include "cloth_hair_sim/core/dynamics/cloth_dynamics.h"
#include "cloth_hair_sim/core/dynamics/holding_wrench.h"
#include "cloth_hair_sim/core/dynamics/pin_set.h"
#include "cloth_hair_sim/core/mpm/grid_collider.h"
#include "cloth_hair_sim/core/mpm/hencky_solid.h"
#include "cloth_hair_sim/core/mpm/layer_proximity.h"
#include "cloth_hair_sim/core/mpm/mass_supported_gradient.h"
#include "cloth_hair_sim/core/mpm/mpm_particles.h"
#include "cloth_hair_sim/core/mpm/particle_projection.h"
#include "cloth_hair_sim/core/mpm/sparse_grid.h"
#include "cloth_hair_sim/core/mpm/support_nodes.h"
#include "cloth_hair_sim/core/mpm/surface_collisions.h"
#include "cloth_hair_sim/core/mpm/time_integration.h"
#include "cloth_hair_sim/core/shell/contact_potential.h"
#include "cloth_hair_sim/core/shell/hencky_lamina.h"
#include "cloth_hair_sim/core/shell/implicit_elasticity.h"
#include "cloth_hair_sim/core/shell/kirchhoff_love_quadrature.h"
#include "cloth_hair_sim/core/solver/newton_krylov.h"
#include "cloth_hair_sim/core/subdiv/clamped_edges.h"
#include "cloth_hair_sim/core/subdiv/first_order_stencils.h"
#include "cloth_hair_sim/core/subdiv/limit_surface.h"
#include "cloth_hair_sim/core/world/body.h"

namespace chs {

// Resolution and model knobs of the hybrid shell. Zero or negative lengths and stiffnesses
// mean "derive from the mesh and material" as documented per field.
struct HybridShellSettings {
  double grid_spacing = 0.0;  // dx [m]; <= 0: the mean control-mesh edge length
  int kernel_degree = 2;      // B-spline degree of the grid, 2 or 3
  // No particle closes on an obstacle, or on another particle near it, by more than cfl dx in a
  // step (Han section 5.6; mpm/approach_speed.h: a garment carried as a whole is not held back).
  double cfl = 0.3;
  double rpic_damping = 0.0;  // nu of Han (5.52): 0 = APIC, 1 = RPIC
  double damping = 0.0;       // [1/s] viscous damping -c m v on the grid (settling drapes)
  double safety = 0.5;        // fraction of the elastic stability bound stableTimeStep() takes
  TimeIntegration integration = TimeIntegration::kSymplecticEuler;
  // Backward Euler: the longest step stableTimeStep() proposes [s] (the CFL bound shortens it),
  // and the Newton-Krylov solve (solver/newton_krylov.h) of each step. It stops when the
  // mass-weighted RMS of the velocity residual, sqrt(sum |r_i|^2 / m_i / sum m_i) with
  // r_i = m_i (v_i - v~_i) - dt f_i(x*), is below implicit_tolerance [m/s]; krylov_tolerance is
  // the tightest GMRES forcing term (adaptive from 0.5, NewtonKrylovSettings).
  // The Lagrangian implicit step uses the same step length for its elastic solve and its grid
  // contact solve, each stopped at lagrangian_tolerance in the same measure (the elastic solve
  // after at most elastic_max_iterations, the contact solve max_newton_iterations),
  // and keeps its Cholesky factor across iterations and steps while each iteration still halves
  // the residual, with elastic_history L-BFGS pairs on top of it (ImplicitElasticitySettings).
  // 1e-4 m/s is 0.4 % of the velocity gravity gives in a step of 1/400 s (the towel's CFL step)
  // and costs 0.6 of the step at 1e-5 (docs/BENCHMARKS.md), with the validation rows unchanged
  // within their tolerances (docs/VALIDATION.md). Longer steps stop at that share of gravity's
  // velocity in the step, lagrangian_gravity_fraction |g| dt where it is the larger: the force
  // left unbalanced is then 0.4 % of the weight (RMS) at any step, and a solve at 1/60 s stops at
  // 6.5e-4 m/s, which saved the towel's last Newton iteration in most steps (the node's towel
  // RTF 0.65-0.83 -> 0.91-1.02, docs/BENCHMARKS.md). 0: lagrangian_tolerance alone.
  double max_time_step = 1.0 / 240.0;
  double implicit_tolerance = 1e-5;
  double lagrangian_tolerance = 1e-4;
  double lagrangian_gravity_fraction = 0.004;
  int max_newton_iterations = 8;
  // A solve stopped short is accepted by the simulate tool and redone as two half steps by the
  // node (which configures 16: on its Lagrangian demo 8 left 75 % of the 1/60 s steps short, 16
  // left 6 %, and the run simulated 1.36 x as much, docs/BENCHMARKS.md).
  int elastic_max_iterations = 8;
  bool reuse_factorization = true;
  int elastic_history = 8;
  // The Lagrangian implicit step's transfer back, Han (4.12): the control points take the grid's
  // velocity (APIC) plus flip_blend times what the transfer averaged away of their elastic
  // velocity, except where the grid stage changed a node of their support (contact between
  // layers, with an obstacle or another body: there the nodes' velocity resolves the contact,
  // and they take it alone). 0: the grid's velocity everywhere (before 2026-12-07); 1: a lone
  // layer keeps its elastic motion's sub-cell detail, which the grid's velocity alone averaged
  // away as damping (the swinging sheet: 23.4 instead of 25.6 % per swing with backward Euler,
  // 7.1 instead of 14.4 % with BDF2; docs/VALIDATION.md). With every fibre in contact
  // (contact_between_layers_only false) the grid changes nearly every node, so the blend acts
  // with the broad phase below.
  double flip_blend = 1.0;
  // The Lagrangian steps' elastic solve meets the obstacles through a penalty and lagged Coulomb
  // friction (shell/implicit_elasticity.h, ObstaclePenalty): stiffness of the fibres' mid-surface
  // points and of the control points (each at rest yields by g dt^2 / (sum of both), 0.07 mm at
  // 1/60 s), acting within obstacle_offset [m] of the obstacles, the stick creeping at most
  // obstacle_friction_velocity [m/s]. obstacle_stiffness 0 leaves the obstacles to the grid
  // alone, as in Han. Chosen on the cloth dropped on a sphere (docs/BENCHMARKS.md, 2026-12-07:
  // at 10 the samples under folds and over the rim, loaded with several times their weight, sank
  // through the band and the grid's stages pushed them back out every step).
  double obstacle_stiffness = 40.0;
  double obstacle_point_stiffness = 1.0;
  double obstacle_offset = 1e-3;
  double obstacle_friction_velocity = 1e-3;
  int max_krylov_iterations = 60;
  double krylov_tolerance = 1e-2;
  // Kirchhoff-Love quadrature (type iv): in-plane Gauss points per face edge and the rule
  // through the thickness (see KirchhoffLoveQuadrature).
  KirchhoffLoveQuadrature kirchhoff_love;
  double yield_stress = std::numeric_limits<double>::infinity();  // c_vM of Han (5.13) [Pa]
  // Contact particles (type iii) per face edge, and their share of the cloth's mass (the rest is
  // lumped on the control points, type ii). Default 0: (5.54) slaves a contact particle's
  // position to the control points, so momentum it carried would be a second copy of the
  // surface's motion that the step never reconciles: a hanging cloth then keeps a steady
  // velocity field, its supports carry 0.9 % less than its weight, and (5.54) moves angular
  // momentum (1e-5 relative in 200 steps). Massless, the step conserves both momenta exactly.
  int contact_particles_per_edge = 2;
  double contact_mass_fraction = 0.0;
  // Fibre contact model of Han (5.21)-(5.30); stiffnesses <= 0 take the lamina's Young modulus
  // (k^c = E, gamma = E / 10) so that contact is as stiff as the cloth's stretch.
  ContactMaterial contact{0.0, 0.0, 0.3};
  // Broad phase of the Lagrangian steps' fibre contact: a fibre keeps its contact only where
  // another layer of the garment shares grid nodes with it (mpm/layer_proximity.h), and is the
  // surface normal elsewhere, as after a separation (5.29). The contact solve then takes one
  // force evaluation where no layers meet (the towel: 1 instead of 5-8 per step). The lone
  // layer's fibre forces had held back some of the grid velocity's averaging (without them and
  // with flip_blend 0, the swinging sheet lost 37.9 % per swing); flip_blend keeps that motion
  // instead. false: every fibre carries contact, as in the explicit and grid backward Euler steps.
  bool contact_between_layers_only = true;
  // With contact_between_layers_only: the step bound (stableTimeStep) counts two control points of
  // one layer only by the speed at which they close in, not their whole relative speed, as the
  // grid carries no force between them (mpm/approach_speed.h). A lone towel swinging from two
  // corners then steps at max_time_step (1/60 s: 30 steps in its first 0.5 s instead of 168),
  // its elastic solves refactorising at each Newton iteration (ImplicitElasticity::solve). A
  // tube wrung through itself crosses from 0.76 instead of 0.88 turns (docs/BENCHMARKS.md,
  // 2026-12-07). false: every pair of the shell's particles counts by its relative speed.
  bool cfl_between_layers_only = true;
  // Obstacles (grid boundary conditions, Han section 3.4) and their default Coulomb mu.
  mpm::ColliderBoundary boundary = mpm::ColliderBoundary::kSeparating;
  double friction = 0.0;
  int display_segments = 3;  // limit-surface tessellation per face edge for displaySurface()
  // Keep that tessellated limit surface, not only the control points, out of the obstacles
  // (mpm/surface_collisions.h); false: the grid and the control points alone, as in Han.
  bool surface_collisions = true;
  // Larger garments are refused at construction: each control point brings ~20 quadrature
  // points and ~1 kB of stencils, and an explicit step of 8K points already takes ~0.1 s.
  int max_control_points = 100000;
};

// Wall time spent in each stage of step(), summed since construction [s].
struct HybridStageTimes {
  double elastic_solve = 0.0, transfer_to_grid = 0.0, shell_forces = 0.0, grid_update = 0.0,
         transfer_to_particles = 0.0, plasticity = 0.0;
  int steps = 0;
};

// The hybrid Lagrangian/MPM thin shell of Han chapter 5: a garment's quad mesh is the control
// net of a Catmull-Clark limit surface (section 5.4); its control points are MPM particles of
// type (ii), contact particles on the surface carry the fibre a3^E (type iii), Kirchhoff-Love
// quadrature points carry the lamina's elastoplastic state (type iv). One background grid
// resolves contact with obstacles (boundary conditions) and between layers of the cloth
// (the fibre contact potential). The ClothDynamics vertices are the control points.
// Optionally the grid also carries type (i) particles of an elastic solid (addSolid): solid and
// garment then meet on the same nodes, so each pushes the other through the grid velocities.
//
// Each step is the fixed sequence of Han section 5.5:
//   transfer to grid (5.37-5.38) -> grid forces (5.46-5.49)
//   -> grid momentum (5.40) and obstacle conditions -> transfer to particles (5.50-5.52)
//   -> positions and trial elastic state (5.53-5.54, 5.44) -> plasticity (5.5.5).
// With backward Euler the grid forces and the grid momentum are one stage, a Newton-Krylov solve
// for the end-of-step grid velocities.
//
// As a Body of a World (world/world.h) the same stages run interleaved with the other bodies'
// (its grid is then its velocity field on the world's grid, of the world's spacing); step() runs
// them for this shell alone.
class HybridShellDynamics : public ClothDynamics, public Body {
 public:
  // Uses the problem's mesh (reference state), material (E, nu, thickness, areal density),
  // gravity, colliders, pinned vertices (held where they are), clamped vertices (limit
  // surface position and tangent plane held along their edges, subdiv/clamped_edges.h) and
  // fixed components (held at their reference value). All act on the control points. A clamp
  // adds one ghost control point per clamped vertex after the mesh's vertices; clamped points
  // and ghosts move with their interior neighbours and cannot be pinned or unpinned. Throws
  // InputError for a bad mesh, material, clamp or setting.
  explicit HybridShellDynamics(const DrapeProblem& problem,
                               const HybridShellSettings& settings = {});

  void step(double dt) override;
  double time() const override { return time_; }

  // Body stages (world/body.h); updateGrid integrates as settings().integration says.
  void beginStep(double dt) override;
  void transferToGrid() override;
  bool updateGrid(double dt) override;
  void reapplyColliders() override;
  void transferFromGrid(double dt) override;
  void endStep(double dt) override;
  mpm::SparseGrid& field() override { return grid_; }
  std::vector<mpm::MassCarriers> fieldCarriers() const override { return massCarriers(); }
  // The limit surface's normals at the contact particles, spread with their weights.
  void fieldNormals(std::vector<Eigen::Vector3d>& normals) const override;
  int kernelDegree() const override { return settings_.kernel_degree; }
  bool finite() const override;
  const std::vector<mpm::ColliderImpulse>& colliderImpulses() const override {
    return collider_impulse_;
  }
  // Symplectic Euler: min(elastic bound (membrane and bending waves over the control spacing,
  // fibre contact, the solid's dilatational wave over dx) times settings.safety, CFL cfl dx /
  // the speed at which control and solid particles approach the obstacles and each other).
  // Backward Euler: min(settings.max_time_step, CFL);
  // a step whose solve falls short of the tolerance is redone with explicit substeps
  // (implicitFallbacks()).
  double stableTimeStep() const override;
  mpm::MotionGroup motion() const override;

  int numVertices() const override { return static_cast<int>(control_.x.size()); }
  const std::vector<Eigen::Vector3d>& positions() const override { return control_.x; }
  const std::vector<Eigen::Vector3d>& velocities() const override { return control_.v; }
  // Places the control points (pins keep their targets); the contact fibres restart unstressed.
  void setPositions(const std::vector<Eigen::Vector3d>& x) override;
  void setVelocities(const std::vector<Eigen::Vector3d>& v) override;
  const std::vector<double>& masses() const override { return control_.mass; }
  double kineticEnergy() const override;  // of control, contact and solid particles
  void setGravity(const Eigen::Vector3d& gravity) override;
  void setDamping(double damping) override;  // settings().damping

  void setColliders(const RigidSurfaces& colliders,
                    const std::vector<SurfaceVelocity>& velocities = {},
                    const std::vector<double>& frictions = {}) override;
  const RigidSurfaces& colliders() const override { return surfaces_; }
  void dropSolverCaches() override;

  void pin(int vertex) override;
  void pin(int vertex, const Eigen::Vector3d& target) override;
  void unpin(int vertex) override;
  bool isPinned(int vertex) const override {
    return pins_.isPinned(vertex) || clamps_.isSlaved(vertex);
  }
  // Support force on each held control point in the last step, m a - f - m g with f the
  // shell's force on it: the prescribed acceleration is already in it (accelerations are
  // checked for size only). A clamped point reports its clamp's net force on the cloth there
  // (its ghost's and neighbour's shares included; ghosts report zero); clampWrench() also gives
  // the clamps' moment.
  std::vector<Eigen::Vector3d> holdingForces(
      const std::vector<int>& vertices,
      const std::vector<Eigen::Vector3d>& accelerations = {}) const override;

  // Force and moment about `origin` that all clamps (bc.clamped) exert on the cloth in the last
  // step: what a gripper holding the clamped edges feels, reversed.
  HoldingWrench clampWrench(const Eigen::Vector3d& origin) const;

  std::unique_ptr<DynamicsSnapshot> snapshot() const override;
  void restore(const DynamicsSnapshot& snapshot) override;
  void writeState(StateWriter& out) const override;
  void readState(StateReader& in) override;
  // The limit surface tessellated with settings.display_segments per face edge.
  DisplaySurface displaySurface() const override;

  // Type (i) particles (Han chapter 3) of one elastic solid of Hencky material (Han (4.5)) on the
  // shell's grid, stepped with the shell: transferred to the grid with it, their stress
  // (3.9) added to its forces, moved by the same grid velocities after the same damping and
  // obstacle conditions, F updated by (3.17). Their momentum, mass and energy count in the
  // diagnostics; snapshot/restore carry them. Throws InputError for arrays of different
  // lengths, no particles, non-finite state, non-positive mass or volume, det F <= 0, or a
  // second solid.
  void addSolid(mpm::Particles particles, const mpm::HenckySolid& material);
  const mpm::Particles& solidParticles() const { return solid_; }

  // Diagnostics.
  const HybridShellSettings& settings() const { return settings_; }
  double gridSpacing() const { return dx_; }
  int numContactParticles() const { return contact_.size(); }
  int numQuadraturePoints() const { return static_cast<int>(kl_points_.size()); }
  int numGridNodes() const { return grid_.size(); }
  double totalMass() const;  // control, contact and solid particles
  Eigen::Vector3d linearMomentum() const override;
  Eigen::Vector3d angularMomentum() const;  // about the origin, particles' x m v + APIC spin
  double elasticEnergy() const;             // Kirchhoff-Love lamina energy now
  // Deepest penetration of the tessellated limit surface into the colliders (>= 0).
  double deepestPenetration() const override;
  const HybridStageTimes& stageTimes() const { return times_; }
  // The Newton-Krylov solve of the last backward Euler step, and how many backward Euler steps
  // fell short of the tolerance and were redone with explicit substeps (since construction).
  const NewtonKrylovResult& lastImplicitSolve() const { return last_solve_; }
  // The Lagrangian implicit step's elastic solve of the last step.
  const ImplicitElasticityResult& lastElasticSolve() const { return last_elastic_; }
  int implicitFallbacks() const { return implicit_fallbacks_; }
  const LimitSurface& limitSurface() const { return *surface_; }
  // Points of the limit surface now (the display samples), for audits.
  std::vector<Eigen::Vector3d> surfacePoints() const;

 private:
  // One step of the stages below with this integration.
  void advance(double dt, TimeIntegration integration);
  bool updateGrid(double dt, TimeIntegration integration);
  bool lagrangian() const {
    return settings_.integration == TimeIntegration::kLagrangianImplicit ||
           settings_.integration == TimeIntegration::kLagrangianBdf2;
  }
  // BDF2's state velocities from the positions after the grid (kLagrangianBdf2).
  void updateBdf2History(double dt);
  // The Lagrangian implicit step's elastic stage: the control points' end-of-step positions under
  // elasticity, gravity and damping, taken as their velocities for the grid.
  void buildElasticity();  // elasticity_ over the control points and their clamps
  void solveElasticity(double dt);
  double explicitTimeStep() const;           // elastic bound times safety, and CFL
  double cflTimeStep(double longest) const;  // the CFL bound up to `longest`
  // The lagrangian_* steps' solves stop below this [m/s] (HybridShellSettings).
  double lagrangianTolerance(double dt) const;
  // The stages of step(), Han section 5.5.
  void computeGridForces();
  void updateGridMomentum(double dt);
  // Backward Euler: computeGridForces + updateGridMomentum as one solve. With contact_only, the
  // Lagrangian implicit step's grid stage: the fibres' contact forces alone, no gravity or
  // damping (the elastic stage took them).
  void solveGridMomentum(double dt, bool contact_only = false);
  // Forces on the grid with the grid moved by node_velocity over dt (x* = x_i + dt v_i).
  void computeTrialGridForces(const std::vector<Eigen::Vector3d>& node_velocity, double dt,
                              bool with_elasticity = true);
  // Adds the solid's stress forces at trial deformation gradients (I + dt grad v) F^n to the grid.
  void scatterTrialSolidStress(const std::vector<Eigen::Vector3d>& node_velocity, double dt);
  // -dPsi/dx_i on the grid (into grid_.force) for control points at x_control and contact
  // fibres `fibres`, through the weights at the particles' step-start positions.
  void scatterShellForces(const std::vector<Eigen::Vector3d>& x_control,
                          const std::vector<Eigen::Vector3d>& fibres, bool with_elasticity = true);
  void dampGridMomentum(double dt);
  // The particles that give the grid its mass (control points without the pinned ones, contact
  // particles if they carry mass, the solid), at the step start.
  std::vector<mpm::MassCarriers> massCarriers() const;
  // The velocity field the contact fibres move with: S v = P(v) / m (mpm/particle_projection.h).
  void carriedVelocity(const std::vector<Eigen::Vector3d>& node_velocity,
                       std::vector<Eigen::Vector3d>& carried);
  void placeClamped(double dt);  // clamped points and ghosts from their interior neighbours
  void checkNotClamped(int vertex) const;  // InputError for a clamped point or a ghost
  void transferToParticles(double dt);
  void updatePositionsAndTrialState(double dt);
  void updatePlasticity();

  HybridShellSettings settings_;
  double thickness_ = 0.0, areal_density_ = 0.0, young_ = 0.0, poisson_ = 0.0;
  double control_spacing_ = 0.0;  // mean control edge length
  double dx_ = 0.0;
  Eigen::Vector3d gravity_;
  ClampedEdges clamps_;  // the control mesh with ghost faces across clamped edges
  std::shared_ptr<const LimitSurface> surface_;
  HenckyLamina lamina_;
  std::vector<KirchhoffLovePoint> kl_points_;  // type (iv)
  ContactMaterial contact_material_;

  mpm::Particles control_;   // type (ii): F is the per-step velocity gradient map, reset each step
  struct ContactParticles {  // type (iii)
    FirstOrderStencils stencil;
    mpm::Particles p;                          // F: as for control_
    std::vector<Eigen::Vector3d> fibre;        // a3^E, Han (5.5)
    std::vector<Eigen::Vector3d> fibre_force;  // -V dchi/da3 at the start of the step
    int size() const { return p.size(); }
  } contact_;
  mpm::Particles solid_;  // type (i), empty unless addSolid
  std::optional<mpm::HenckySolid> solid_material_;
  double solid_wave_speed_ = 0.0;  // fastest dilatational wave of the solid's particles
  std::vector<SurfaceStencil> display_stencils_;
  std::vector<std::array<int, 3>> display_triangles_;
  // The displayed surface held out of the obstacles (null: settings.surface_collisions off), the
  // control positions at the step's start, which points may move, and their clearances.
  std::unique_ptr<mpm::SurfaceCollisions> surface_collisions_;
  std::vector<Eigen::Vector3d> surface_start_;
  std::vector<char> movable_;
  std::vector<mpm::Clearance> clearance_;

  mpm::SparseGrid grid_;
  // The contact particles' mass-supported weight gradients, from transferToGrid to
  // transferFromGrid.
  mpm::MassSupportedGradientTable fibre_weight_gradients_;
  std::vector<mpm::SupportNodes> supports_;     // of control_, contact_.p, solid_ (transferToGrid)
  std::vector<Eigen::Vector3d> control_force_;  // -dPsi/dx_p on control points this step
  std::vector<Eigen::Vector3d> kl_gradient_;    // dPsi^KL/dx_p
  std::vector<Eigen::Vector3d> grid_force_;     // control_force_ without pinned or clamped points
  std::vector<double> transfer_mass_;           // masses the grid sees (pinned, clamped: none)
  // Fibre velocity field S v, its gradient at the contact particles, and scratch for P(.).
  std::vector<Eigen::Vector3d> fibre_velocity_, projected_, shell_node_force_;
  // The Lagrangian step's contact solve starts from the change its last solution made at each
  // node (where that node is active again): on a resting cloth that change is the same every step
  // (docs/BENCHMARKS.md, 2026-12-07). Solver state, not model state: a snapshot does not keep it.
  mpm::SparseGrid last_contact_nodes_{1.0};
  std::vector<Eigen::Vector3d> last_contact_change_;
  // kLagrangianBdf2: each control point's position and velocity one step before the step's
  // start, whether it has them (else backward Euler), the length of that step; and this step's
  // start and the coefficients each point took.
  struct Bdf2History {
    std::vector<Eigen::Vector3d> x, v;
    std::vector<char> valid;
    double dt = 0.0;
  } bdf2_;
  std::vector<Eigen::Vector3d> step_start_x_, step_start_v_;
  std::vector<char> second_order_;
  std::vector<Eigen::Matrix3d> fibre_gradient_;

  RigidSurfaces surfaces_;
  std::vector<mpm::GridCollider> grid_colliders_;

  std::vector<Eigen::Vector3d> free_axes_;  // 1 where an axis is free, 0 where bc fixes it
  std::vector<Eigen::Vector3d> reference_;  // where fixed components are held
  PinSet pins_;
  std::vector<Eigen::Vector3d> pin_force_;       // support force on each control point, last step
  std::vector<Eigen::Vector3d> clamp_residual_;  // m a - f - m g of clamped points and ghosts
  // Of pinned and clamped points, for their acceleration.
  std::vector<Eigen::Vector3d> step_start_velocity_;

  // Backward Euler scratch: trial control positions and contact fibres.
  std::vector<Eigen::Vector3d> trial_control_, trial_shift_, trial_fibre_;
  std::vector<Eigen::Matrix3d> solid_gradient_, solid_stress_;  // grad v and V^0 P(F*) F^nT
  NewtonKrylovResult last_solve_;
  // Lagrangian implicit step: the elastic solver (its factor is a cache, not state), the
  // velocities it gave the control points, -dPsi^KL/dx at its solution, and the grid velocity
  // right after the transfer (the FLIP transfer back hands on the change from it).
  std::unique_ptr<ImplicitElasticity> elasticity_;
  // The Lagrangian steps' broad phase of the fibres' contact, and per contact particle whether
  // another layer shares its grid nodes in this step (empty: every fibre carries contact); a
  // face of each control point, for the step bound's pairs on one layer (motion()).
  std::unique_ptr<mpm::LayerProximity> layers_;
  std::vector<char> near_layer_;
  std::vector<int> control_face_;
  std::vector<char> pic_nodes_;  // per grid node: the grid stage changed its velocity
  bool fibreInContact(int p) const { return near_layer_.empty() || near_layer_[p]; }
  // No fibre carries contact this step and no solid shares the grid: the contact solve has
  // nothing to solve.
  bool contactFree() const;
  ImplicitElasticityResult last_elastic_;
  std::vector<Eigen::Vector3d> lagrangian_velocity_, elastic_force_, transferred_velocity_,
      transferred_at_particles_;
  std::vector<mpm::ColliderImpulse> collider_impulse_;  // per collider, this step
  int implicit_fallbacks_ = 0;

  double time_ = 0.0;
  HybridStageTimes times_;
};

}  // namespace chs
