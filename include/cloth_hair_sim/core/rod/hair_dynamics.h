#pragma once
#include <map>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "cloth_hair_sim/core/dynamics/holding_wrench.h"
#include "cloth_hair_sim/core/mpm/collider_candidates.h"
#include "cloth_hair_sim/core/mpm/drucker_prager.h"
#include "cloth_hair_sim/core/mpm/grid_collider.h"
#include "cloth_hair_sim/core/mpm/hencky_solid.h"
#include "cloth_hair_sim/core/mpm/mpm_particles.h"
#include "cloth_hair_sim/core/mpm/sparse_grid.h"
#include "cloth_hair_sim/core/mpm/support_nodes.h"
#include "cloth_hair_sim/core/rod/discrete_elastic_rod.h"
#include "cloth_hair_sim/core/rod/obstacle_contact.h"
#include "cloth_hair_sim/core/rod/rod_material.h"
#include "cloth_hair_sim/core/rod/strand_collisions.h"
#include "cloth_hair_sim/core/rod/strand_newton_solver.h"
#include "cloth_hair_sim/core/world/body.h"

namespace chs::rod {

// Han (4.3)-(4.6), (4.10)-(4.11): the strands' frictional contact with each other as a granular
// continuum on the grid. Each free vertex carries an elastic deformation gradient F^E of the
// hair's bulk (not of its strand), moved by the grid's velocity gradient; the St.Venant-Kirchhoff
// Hencky energy (mpm/hencky_solid.h) of F^E pushes converging strands apart on the grid, and the
// cohesionless Drucker-Prager return (mpm/drucker_prager.h) lets them separate freely and slide
// on each other with Coulomb friction c_F. The grid update is explicit in substeps within the
// world's step (HairDynamics::updateGrid): the bulk's dilatational wave, c = sqrt((lambda +
// 2 mu) / rho_hair) with the strands' own density, sets their number, ceil(dt c / (cfl dx)).
// The modulus is a contact penalty, not a property of hair: stiffer stops faster strands in a
// shorter distance, at more substeps. The strands meet at about a grid cell ("visible
// separation if dx is too large", Han section 5.6).
// The grid holds the bulk's velocity, not each strand's within a cell, so it stops strands that
// interleave within a cell only where their velocities take the grid's: contact_blend below
// (test_rod_continuum: crossed bundles 7 mm thick on a 4 mm grid closing at 0.6 m/s, 0 missed
// crossings and thrown back; 3928 with the continuum at xi = 0 alone, 7700 without it). A
// strand's own vertices are no contact: the stress and the blend act in the share of the grid
// mass that other strands bring, so a strand alone is exactly as without the continuum.
// Off by default: bundles thinner than a cell are not resolved (Han's Fig. 4.7 scaled to 3 mm
// bundles on a 1 cm grid: 272 crossings against 256 without; Han's xi = 0.95 everywhere, 58).
struct StrandContinuumSettings {
  bool enabled = false;
  double youngs_modulus = 1000.0;  // [Pa]
  double poisson_ratio = 0.3;
  double friction = 0.3;  // c_F between strands
  // xi of (4.12) across the strand for a vertex whose bulk is compressed (pressed into other
  // strands), scaled by the share of the grid mass around it that other strands bring
  // (strand_contact_share.h); along the strand, apart and alone, pic_blend holds. The grid's
  // velocity is then the bulk's where strands press into each other (Han's 0.95), while a
  // strand alone, strands flying apart and each strand's stretching keep pic_blend's exactness.
  double contact_blend = 0.95;
};

// What the continuum did in the last step.
struct StrandContinuumStats {
  int substeps = 0;    // of the grid update (the bulk's wave)
  int compressed = 0;  // vertices whose bulk resists compression (elastic or sliding)
  int slid = 0;        // of which on the friction cone (sliding)
  // Vertices whose F^E the grid inverted or flattened (a step beyond its bound): reset to no
  // strain, so that one bad step does not poison the next.
  int reset = 0;
};

struct HairSettings {
  double grid_spacing = 0.01;  // dx [m]: the world's
  int kernel_degree = 2;       // the world's
  // xi of Han (4.12): the share of the grid's velocity (PIC) in the vertices' new velocity; the
  // rest is the Lagrangian velocity plus the grid's change (FLIP). Han uses 0.95, but a strand
  // whose segments are shorter than dx then loses to the grid's averaging the corrections its
  // stiff stretching makes along it: a 10 cm hair (2.5 mm segments, dx = 1 cm) swinging at
  // 1/240 s stretched by 1.8 % with xi = 0.95 (test_rod_world). 0: the grid only adds its change.
  double pic_blend = 0.0;
  Eigen::Vector3d gravity = Eigen::Vector3d(0.0, 0.0, -9.81);
  // Obstacles: boundary condition on the grid (grid_collider.h), default Coulomb mu, and their
  // contact inside each strand's implicit solve (obstacle_contact.h).
  mpm::ColliderBoundary boundary = mpm::ColliderBoundary::kSeparating;
  double friction = 0.3;
  ObstacleContactSettings obstacle_contact;
  // stableTimeStep(): min(max_time_step, cfl dx / w), w the speed at which vertices approach the
  // obstacles, and each other when the continuum is on (mpm/approach_speed.h): hair that moves
  // with its head is not held to the head's speed. The implicit elasticity sets no bound of its
  // own, and the strand-strand impulses are continuous in time.
  double cfl = 0.5;
  double max_time_step = 1.0 / 120.0;
  // Each strand's implicit solve per step. Stopped once a Newton step moves no vertex by more
  // than 1e-6 of a segment (4 nm on hair's 4 mm segments: 5e-7 m/s at 1/120 s), where the
  // quadratic convergence leaves an error of the order of that step squared; statics keep
  // StrandNewtonSettings' 1e-9. 1e-6 instead of 1e-9 saves one iteration in four.
  StrandNewtonSettings newton{1e-6, 30};
  // Han (4.13): the geometric strand-strand impulses (strand_collisions.h) on the vertices'
  // new velocities, between all segments of all strands of this body (off by default: see
  // StrandCollisionSettings::enabled; without them strands pass through each other).
  StrandCollisionSettings strand_collisions;
  StrandContinuumSettings continuum;
  int max_vertices = 1000000;  // over all strands; more is refused (memory, a typo in a groom)
};

// Hair as a body of the world (world/body.h), Han section 4.2 with the strands as discrete
// elastic rods (discrete_elastic_rod.h). A step's stages:
//   beginStep        the Lagrangian update (4.7), done implicitly: per strand, backward Euler on
//                    the incremental potential (strand_newton_solver.h) with the rod's
//                    elasticity, gravity, the applied vertex forces and the obstacles' normal
//                    penalty and lagged Coulomb friction potential (obstacle_contact.h: the
//                    capstan needs friction where the tension is solved), roots clamped; gives
//                    the vertices' velocities v* = (x - x^n) / dt.
//   transferToGrid   APIC transfer of the vertices' mass and momentum m v* to the field (4.8-4.9)
//                    from their step-start positions; clamped vertices carry no mass there (the
//                    scalp's motion is a boundary condition, not momentum).
//   updateGrid       the strand continuum's stress onto the nodes (4.10, symplectic), then the
//                    obstacles' Coulomb conditions on the nodes inside them (grid_collider.h).
//   [world]          contact with other bodies' fields (world/field_contact.h).
//   transferFromGrid the change of grid velocity back to the vertices, blended with xi (4.12);
//                    then each vertex that still ends inside an obstacle
//                    (the solve keeps them a radius off it) gets the grid's Coulomb projection as
//                    an impulse; then the strand-strand collision impulses (strand_collisions.h:
//                    proximity, continuous collisions in Jacobi passes, rigid impact zones) so
//                    that no segment passes through another over the step; positions move,
//                    x^{n+1} = x^n + dt v^{n+1} (4.13), a vertex moved by the impulses into an
//                    obstacle put back on its surface; the rod's frames are transported there;
//                    F^E moved by the grid's velocity gradient and returned to the cone.
// Gravity acts in the Lagrangian update rather than on the grid as in Han (4.10): a stiff strand
// solved implicitly without it would spring back each step from the sag the grid's gravity gave
// it, and the hanging shape would lag by dt^2 g.
// Strands of this body meet each other through the continuum (and the impulses, when enabled);
// other bodies' fields they meet through the world.
// One vertex of one strand.
struct StrandVertex {
  int strand = 0;
  int vertex = 0;
};

class HairDynamics : public Body {
 public:
  // Throws InputError for a bad setting.
  explicit HairDynamics(const HairSettings& settings = {});

  // Adds a strand whose rest shape is `rest` (also its initial shape), at rest. clamped: its
  // root vertex, first edge and first material frame are held to the strand's root frame
  // (identity now, setRootFrame moves it). Returns its index. Throws InputError (nothing
  // added) for a bad strand or material (DiscreteElasticRod) or beyond max_vertices.
  int addStrand(const std::vector<Eigen::Vector3d>& rest, const RodMaterial& material,
                bool clamped = true,
                const Eigen::Vector3d& first_director = Eigen::Vector3d::Zero());
  int numStrands() const { return static_cast<int>(strands_.size()); }
  const DiscreteElasticRod& strand(int s) const { return strands_[s].rod; }
  const std::vector<Eigen::Vector3d>& velocities(int s) const { return strands_[s].v; }
  void setVelocities(int s, const std::vector<Eigen::Vector3d>& v);
  // Replaces strand s's natural curvature and twist (DiscreteElasticRod::setNaturalShape): a
  // strand added in a wrapped shape made naturally straight. Throws InputError as that does.
  void setNaturalShape(int s, const std::vector<Eigen::Vector2d>& curvature,
                       const std::vector<double>& twist);
  // The rigid motion from the strand's root as added to where its clamp should be: the clamp
  // moves there at constant velocity over the next step (a scalp on a moving head link).
  void setRootFrame(int s, const Eigen::Isometry3d& pose);
  // Force and moment about the root vertex that strand s's clamp applied to it in the last step
  // (zero for a free strand): what a scalp or a gripper holding the root feels, reversed. From
  // the implicit update, where the clamp acts; the grid stages do not touch clamped vertices.
  HoldingWrench clampWrench(int s) const;
  // Grips: a gripper holding a lock. The vertices are held where they are when gripped, then
  // carried by the grip's rigid motion (setGripFrame, from where they were gripped; identity
  // until set), which they reach at constant velocity over the next step, held like a clamp in
  // each strand's implicit solve. Vertices already held (a clamped root's first two, another
  // grip's) are left out. Returns the grip's id; throws InputError (nothing gripped) for a bad
  // strand or vertex or when none of them is free.
  int addGrip(const std::vector<StrandVertex>& vertices);
  void setGripFrame(int grip, const Eigen::Isometry3d& motion);
  // The grip's vertices free again, with the velocity they had.
  void removeGrip(int grip);
  const std::vector<StrandVertex>& gripVertices(int grip) const;
  // Force the grip applied to its vertices in the last step and its moment about origin, at
  // their positions now: the vertices' weight and acceleration and the pull of the rest of the
  // strands (what the gripper feels, reversed). From the implicit update, as clampWrench.
  HoldingWrench gripWrench(int grip, const Eigen::Vector3d& origin) const;
  // The vertices within radius of centre that are not held (by a clamp or a grip).
  std::vector<StrandVertex> freeVerticesNear(const Eigen::Vector3d& centre, double radius) const;

  // An applied force [N] on one vertex, kept until changed.
  void setVertexForce(int s, int vertex, const Eigen::Vector3d& force);
  void setGravity(const Eigen::Vector3d& gravity);
  const HairSettings& settings() const { return settings_; }
  double totalMass() const;
  double time() const { return time_; }
  // Newton iterations of the slowest strand in the last step (over its lag passes).
  int lastNewtonIterations() const { return last_iterations_; }
  // The Newton iterations of all strands in the last step.
  long lastTotalNewtonIterations() const { return last_total_iterations_; }
  // The strand-strand collision stage of the last step (zero when disabled).
  const StrandCollisionStats& lastStrandCollisions() const { return last_collisions_; }
  const StrandContinuumStats& lastContinuum() const { return last_continuum_; }
  // Elastic deformation gradient of the strands' bulk at strand s's vertex i (identity when
  // the continuum is disabled or the vertex is held).
  const Eigen::Matrix3d& bulkDeformation(int s, int i) const;
  // The contact distance between centrelines the collision stage uses [m].
  double strandThickness() const;

  // Body stages.
  void beginStep(double dt) override;
  void transferToGrid() override;
  bool updateGrid(double dt) override;
  void reapplyColliders() override;
  void transferFromGrid(double dt) override;
  void endStep(double dt) override;
  mpm::SparseGrid& field() override { return grid_; }
  std::vector<mpm::MassCarriers> fieldCarriers() const override;
  void fieldNormals(std::vector<Eigen::Vector3d>& normals) const override { normals.clear(); }
  int kernelDegree() const override { return settings_.kernel_degree; }
  double stableTimeStep() const override;
  mpm::MotionGroup motion() const override;
  Eigen::Vector3d linearMomentum() const override;
  double kineticEnergy() const override;  // vertices' translation and edges' spin
  bool finite() const override;
  void setColliders(const RigidSurfaces& colliders,
                    const std::vector<SurfaceVelocity>& velocities = {},
                    const std::vector<double>& frictions = {}) override;
  const std::vector<mpm::ColliderImpulse>& colliderImpulses() const override {
    return collider_impulse_;
  }
  std::unique_ptr<DynamicsSnapshot> snapshot() const override;
  void restore(const DynamicsSnapshot& snapshot) override;
  // The whole state for a state file (io/state_stream.h): the strands, their velocities, root
  // frames and holds, the grips, the particles' affine velocities and bulk deformation, the
  // clock. readState takes it into a body built with the same strands (a ~load_hair request
  // rebuilt); throws InputError naming what does not match. Colliders are not part of it.
  void writeState(StateWriter& out) const;
  void readState(StateReader& in);

 private:
  struct Strand {
    explicit Strand(DiscreteElasticRod r) : rod(std::move(r)) {}
    DiscreteElasticRod rod;
    std::vector<Eigen::Vector3d> v;  // vertex velocities
    // The vertices' change of velocity over the last step / its dt: the implicit solve starts
    // from x + dt v + dt^2 a (solveStrandStep).
    std::vector<Eigen::Vector3d> accel;
    std::vector<double> omega;  // edge angle rates
    std::vector<Eigen::Vector3d> force;
    bool clamped = true;
    // The clamp in the frame it was added in: x_0, x_1 and the first material director.
    Eigen::Vector3d root_x0, root_x1, root_m1;
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    HoldingWrench clamp;                                 // last step's, about the root vertex
    std::vector<mpm::ColliderImpulse> obstacle_impulse;  // this step's, from the implicit solve
    // Per vertex: the grip holding it (-1: none), where it was gripped, and the force the hold
    // (clamp or grip) applied to it in the last step.
    std::vector<int> grip;
    std::vector<Eigen::Vector3d> grip_x, hold_force;
    int offset = 0;  // first vertex among the particles
    // This step: step-start configuration and the clamp's targets.
    Eigen::VectorXd q_start;
  };
  struct Grip {
    std::vector<StrandVertex> vertices;
    Eigen::Isometry3d motion = Eigen::Isometry3d::Identity();
  };
  void checkStrand(int s) const;
  const Grip& grip(int id) const;
  bool held(const Strand& s, int i) const { return (s.clamped && i < 2) || s.grip[i] >= 0; }
  void solveStrandStep(Strand& strand, double dt, StrandNewtonResult& result);
  void returnToCone(std::vector<Eigen::Matrix3d>& F, bool last);

  HairSettings settings_;
  std::vector<Strand> strands_;
  mpm::Particles particles_;  // every strand's vertices; mass: what the grid sees
  mpm::SparseGrid grid_;
  std::vector<mpm::SupportNodes> supports_;
  std::vector<Eigen::Vector3d> grid_v_star_, grid_dv_, dv_p_;
  mpm::Particles scratch_;
  RigidSurfaces surfaces_;
  std::vector<mpm::GridCollider> colliders_;
  std::vector<StrandObstacle> obstacles_;  // the same, for the strands' implicit solves
  // During beginStep: the colliders near each point (the strands' obstacle contact asks those
  // alone).
  const mpm::ColliderCandidates* near_obstacles_ = nullptr;
  std::vector<mpm::ColliderImpulse> collider_impulse_;
  // Per strand, per collider (strand k's impulse on collider c at k * colliders + c).
  std::vector<mpm::ColliderImpulse> strand_grid_impulse_;
  std::map<int, Grip> grips_;
  int next_grip_ = 0;
  StrandCollisions collisions_;
  StrandCollisionStats last_collisions_;
  std::optional<mpm::HenckySolid> bulk_;
  std::optional<mpm::DruckerPrager> bulk_return_;
  static constexpr int kMaxBulkSubsteps = 256;
  double bulk_wave_speed_ = 0.0, bulk_substep_ = 0.0;
  mpm::Particles bulk_scratch_;
  std::vector<Eigen::Matrix3d> bulk_stress_;
  std::vector<char> bulk_compressed_;  // per vertex, after the last return
  std::vector<double> bulk_share_;     // other strands' share of each vertex's grid mass
  StrandContinuumStats last_continuum_;
  std::vector<Eigen::Vector3d> x_start_, v_free_;
  std::vector<double> inverse_mass_;
  std::vector<int> strand_offsets_;  // each strand's first particle, then the count
  bool converged_ = true;
  int last_iterations_ = 0;
  long last_total_iterations_ = 0;
  double time_ = 0.0;
};

}  // namespace chs::rod
