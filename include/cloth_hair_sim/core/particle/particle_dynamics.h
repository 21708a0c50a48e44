#pragma once
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>  // cross

#include "cloth_hair_sim/core/drape/drape_problem.h"
#include "cloth_hair_sim/core/dynamics/cloth_dynamics.h"
#include "cloth_hair_sim/core/dynamics/pin_set.h"
#include "cloth_hair_sim/core/particle/particle_loads.h"
#include "cloth_hair_sim/core/particle/particle_network.h"

namespace chs {

struct ParticleDynamicsSettings {
  ParticleNetworkOptions network;  // D', B' as in the static model
  double damping = 0.0;            // [1/s] viscous damping force -damping m v
  double restitution = 0.0;        // normal velocity after an impact = -restitution x before
  double contact_tolerance = 0.0;  // gap counted as contact; 0: 1e-6 b
  double friction = 0.0;           // Coulomb mu against obstacles without their own
};

// The dynamic particle model of seed 000 section 3.3: m dv/dt = W + F_ext + F_stretch + F_bend
// + F_shear - damping m v (eq. 50), integrated with classical fourth-order Runge-Kutta on the
// state (x, v). Masses are lumped from the areal density (a quarter of each adjacent quad).
// Obstacles: while a node touches one, the inward normal part of its resultant is cancelled as
// in the static model; after each step a penetrating node is put back on the surface and its
// inward normal velocity reversed times the restitution. Coulomb friction: the normal velocity
// an obstacle takes away during a step buys at most mu times as much tangential slip.
//
// Clamped and pinned vertices of the problem start pinned at their reference positions; pins
// can be added, moved and released between steps (a ROS node drives them). A pin moved to a new
// target carries its vertex there at constant velocity over the next step (a moved clamp
// translates its held direction but does not turn it). Fixed components stay held. Seams are
// not modelled here: sew with solveParticleStatic first and hand its positions over. Explicit RK4
// is conditionally stable: keep dt below stableTimeStep().
class ParticleDynamics : public ClothDynamics {
 public:
  // Throws InputError for a bad problem or settings (the areal density must be positive).
  explicit ParticleDynamics(const DrapeProblem& problem,
                            const ParticleDynamicsSettings& settings = {});

  void step(double dt) override;
  double time() const override { return time_; }
  int numVertices() const override { return static_cast<int>(x_.size()); }

  const std::vector<Eigen::Vector3d>& positions() const override { return x_; }
  const std::vector<Eigen::Vector3d>& velocities() const override { return v_; }
  void setPositions(const std::vector<Eigen::Vector3d>& x) override;  // pins keep targets
  void setVelocities(const std::vector<Eigen::Vector3d>& v) override;
  // Obstacles that move (a ROS node re-poses them from tf between steps). velocities: one per
  // collider, or empty for obstacles at rest; an impact then leaves the vertex with the
  // obstacle's normal velocity, so a moving obstacle carries the cloth along instead of only
  // projecting it out each step. Throws InputError for a null surface or a count mismatch.
  // frictions: Coulomb mu per collider, or empty for settings.friction on all.
  void setColliders(const RigidSurfaces& colliders,
                    const std::vector<SurfaceVelocity>& velocities = {},
                    const std::vector<double>& frictions = {}) override;
  const RigidSurfaces& colliders() const override { return surfaces_; }

  void pin(int vertex) override;                                 // at its current position
  void pin(int vertex, const Eigen::Vector3d& target) override;  // or move it to target
  void unpin(int vertex) override;
  bool isPinned(int vertex) const override { return pins_.isPinned(vertex); }

  const std::vector<double>& masses() const override { return loads_.masses(); }
  double kineticEnergy() const override;
  void setGravity(const Eigen::Vector3d& gravity) override;
  void setDamping(double damping) override;
  double elasticEnergy() const { return network_.elasticEnergy(x_); }
  double externalPotential() const { return loads_.potential(x_); }  // gravity, nodal forces
  double potentialEnergy() const { return elasticEnergy() + externalPotential(); }
  Eigen::Vector3d centreOfMass() const;
  // 1 / omega_max, omega_max^2 bounded by the largest stiffness bound / mass: half of the step
  // 2 / omega_max that stays inside RK4's stability interval (|omega dt| < 2.8) for the undamped
  // network, the other half a margin for contact stiffening.
  double stableTimeStep() const override;
  // Forces the obstacles exert on the nodes now touching them.
  std::vector<ContactReaction> contactReactions() const;
  // Resultant of the applied forces on each vertex now (internal, weight, nodal loads,
  // damping), before pins, fixed axes and contacts act: what a support must balance.
  std::vector<Eigen::Vector3d> appliedForces() const;
  // r_i = m_i a_i - f_i with f the applied forces now: contacts of the held vertices are not
  // split off, so a support pressing a held vertex onto an obstacle carries that share too.
  std::vector<Eigen::Vector3d> holdingForces(
      const std::vector<int>& vertices,
      const std::vector<Eigen::Vector3d>& accelerations = {}) const override;
  std::unique_ptr<DynamicsSnapshot> snapshot() const override;
  void restore(const DynamicsSnapshot& snapshot) override;
  void writeState(StateWriter& out) const override;
  void readState(StateReader& in) override;
  // The quads split into triangles over the current positions.
  DisplaySurface displaySurface() const override;

 private:
  void acceleration(const std::vector<Eigen::Vector3d>& x, const std::vector<Eigen::Vector3d>& v,
                    std::vector<Eigen::Vector3d>& a, std::vector<ContactReaction>* reactions,
                    std::vector<double>* pushed = nullptr) const;

  ParticleDynamicsSettings settings_;
  ParticleNetwork network_;
  ParticleLoads loads_;
  RigidSurfaces surfaces_;
  std::vector<SurfaceVelocity> surface_velocities_;  // empty: at rest
  std::vector<double> surface_friction_;             // empty: settings_.friction
  double contact_tolerance_ = 0.0;
  std::vector<Eigen::Vector3d> mask_;  // 1 where an axis is free
  PinSet pins_;
  std::vector<std::array<int, 4>> quads_;  // for display
  std::vector<Eigen::Vector3d> x_, v_;
  double time_ = 0.0;
};

}  // namespace chs
