#pragma once
#include <memory>
#include <string>
#include <vector>

#include "cloth_hair_sim/core/dynamics/cloth_dynamics.h"
#include "cloth_hair_sim/core/mpm/approach_speed.h"
#include "cloth_hair_sim/core/mpm/grid_collider.h"
#include "cloth_hair_sim/core/mpm/particle_projection.h"
#include "cloth_hair_sim/core/mpm/sparse_grid.h"

namespace chs {

// A body of the world (world/world.h): anything that puts particles on the world's grid and takes
// velocities back. Each body keeps its own velocity field on the grid (a SparseGrid of the world's
// spacing: node i at i dx in every field, so fields share nodes by coordinate), and the world
// resolves contact between the fields where they overlap. One world step calls the stages below
// over all bodies, in this order (Han's algorithm boxes, sections 4.3, 5.5 and 6.1):
//   beginStep -> transferToGrid -> updateGrid -> [world: contact between fields]
//   -> reapplyColliders -> transferFromGrid -> endStep
// A body type adds its own work to these stages and never reaches into another body.
class Body {
 public:
  virtual ~Body() = default;

  // Stage 1: the kinematic inputs of this step (pins' velocities) and the body's own Lagrangian
  // update, if it has one (a rod's implicit elastic solve, Han (4.7)).
  virtual void beginStep(double dt) = 0;
  // Stage 2: mass and momentum of the body's particles onto its field (P2G).
  virtual void transferToGrid() = 0;
  // Stage 3: the field's momentum update: internal forces, gravity, damping and the obstacles'
  // conditions. False if an implicit solve stopped short of its tolerance (the world reports it).
  virtual bool updateGrid(double dt) = 0;
  // Stage 4b: the obstacles' conditions once more, after contact with other bodies moved the
  // field (a layer pressed onto one lying on a table must not push it into the table).
  virtual void reapplyColliders() = 0;
  // Stage 5: the field's velocities back to the particles, positions and trial state (G2P).
  virtual void transferFromGrid(double dt) = 0;
  // Stage 6: return mappings (plasticity, friction) and the body's clock.
  virtual void endStep(double dt) = 0;

  // The body's velocity field on the world's grid, valid from transferToGrid to transferFromGrid.
  virtual mpm::SparseGrid& field() = 0;
  // The particles that carry the field's mass, at the step start (for contact normals).
  virtual std::vector<mpm::MassCarriers> fieldCarriers() const = 0;
  // A surface normal per node of the field (any sign and length), or nothing when the body has
  // no surface (contact between fields then takes the normal from where the masses lie).
  virtual void fieldNormals(std::vector<Eigen::Vector3d>& normals) const = 0;
  virtual int kernelDegree() const = 0;

  // The largest step the body tolerates now (its explicit bound, or the CFL bound from how fast
  // its particles approach the obstacles and each other: mpm/approach_speed.h).
  virtual double stableTimeStep() const = 0;
  // The body's particles now, for the CFL bound between bodies (World::stableTimeStep).
  virtual mpm::MotionGroup motion() const = 0;
  virtual Eigen::Vector3d linearMomentum() const = 0;
  virtual double kineticEnergy() const = 0;
  virtual bool finite() const = 0;  // positions and velocities

  // Obstacles, as ClothDynamics::setColliders; the world hands every body the same list.
  virtual void setColliders(const RigidSurfaces& colliders,
                            const std::vector<SurfaceVelocity>& velocities,
                            const std::vector<double>& frictions) = 0;
  // Momentum each collider gave the body in the last step (one entry per collider).
  virtual const std::vector<mpm::ColliderImpulse>& colliderImpulses() const = 0;

  // The body's whole state (not its constant model), for rollback and save/restore.
  virtual std::unique_ptr<DynamicsSnapshot> snapshot() const = 0;
  virtual void restore(const DynamicsSnapshot& snapshot) = 0;
};

}  // namespace chs
