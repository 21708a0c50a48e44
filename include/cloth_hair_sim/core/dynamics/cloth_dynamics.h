#pragma once
#include <array>
#include <memory>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>  // cross

#include "cloth_hair_sim/core/collision/penetration_depth.h"
#include "cloth_hair_sim/core/contact/rigid_surface.h"
#include "cloth_hair_sim/core/io/state_stream.h"

namespace chs {

// Velocity field of a moving rigid obstacle: v(x) = linear + angular x (x - origin).
struct SurfaceVelocity {
  Eigen::Vector3d linear = Eigen::Vector3d::Zero();
  Eigen::Vector3d angular = Eigen::Vector3d::Zero();  // [rad/s]
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  Eigen::Vector3d at(const Eigen::Vector3d& x) const { return linear + angular.cross(x - origin); }
};

// What a dynamics backend shows: a triangle mesh of the cloth's surface now.
struct DisplaySurface {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<std::array<int, 3>> triangles;  // counter-clockwise seen from the front
};

// A restorable copy of a backend's whole state (positions, velocities and any internal state such
// as plastic strain), for rolling back a step that diverged.
class DynamicsSnapshot {
 public:
  virtual ~DynamicsSnapshot() = default;
};

// A dynamic cloth model as a ROS node or a tool drives it: a set of controllable points (the
// particle network's nodes, or the control points of a subdivision shell) that can be pinned,
// moved and read back, stepped among moving rigid obstacles. Units are the caller's (SI).
class ClothDynamics {
 public:
  virtual ~ClothDynamics() = default;

  virtual void step(double dt) = 0;
  virtual double time() const = 0;
  // A step that keeps the explicit integrator stable (the caller may take smaller ones).
  virtual double stableTimeStep() const = 0;

  virtual int numVertices() const = 0;
  virtual const std::vector<Eigen::Vector3d>& positions() const = 0;
  virtual const std::vector<Eigen::Vector3d>& velocities() const = 0;
  virtual void setPositions(const std::vector<Eigen::Vector3d>& x) = 0;  // pins keep targets
  virtual void setVelocities(const std::vector<Eigen::Vector3d>& v) = 0;
  virtual const std::vector<double>& masses() const = 0;
  virtual double kineticEnergy() const = 0;

  // Live changes between steps (a ROS node's dynamic_reconfigure): the gravity acceleration and
  // the viscous damping rate [1/s]. Throw InputError for a non-finite gravity or a damping that
  // is negative or not finite, the previous value kept.
  virtual void setGravity(const Eigen::Vector3d& gravity) = 0;
  virtual void setDamping(double damping) = 0;

  // Obstacles that move (re-posed between steps). velocities: one per collider, or empty for
  // obstacles at rest; frictions: Coulomb mu per collider, or empty for the backend's default.
  // Throws InputError for a null surface or a count mismatch.
  virtual void setColliders(const RigidSurfaces& colliders,
                            const std::vector<SurfaceVelocity>& velocities = {},
                            const std::vector<double>& frictions = {}) = 0;
  virtual const RigidSurfaces& colliders() const = 0;
  // Deepest penetration of the displayed surface into the colliders [m] (>= 0). Throws
  // InputError for a non-finite vertex.
  virtual double deepestPenetration() const {
    return chs::deepestPenetration(displaySurface().vertices, colliders()).depth;
  }

  virtual void pin(int vertex) = 0;                                 // at its current position
  virtual void pin(int vertex, const Eigen::Vector3d& target) = 0;  // or carried to target
  virtual void unpin(int vertex) = 0;
  virtual bool isPinned(int vertex) const = 0;

  // Constraint reaction on each held vertex: the force that keeps it on its prescribed motion
  // (accelerations empty: held still). Throws InputError for a bad index or size.
  virtual std::vector<Eigen::Vector3d> holdingForces(
      const std::vector<int>& vertices,
      const std::vector<Eigen::Vector3d>& accelerations = {}) const = 0;

  virtual std::unique_ptr<DynamicsSnapshot> snapshot() const = 0;
  virtual void restore(const DynamicsSnapshot& snapshot) = 0;
  // The whole dynamic state (what snapshot() holds, the pins and their targets, the time) as
  // records, for a state file; readState takes it into a backend built from the same problem
  // and settings, which then steps on bit for bit as the saved one would have after
  // dropSolverCaches (colliders are the caller's: set them again). readState throws InputError
  // for a record of another backend, a count that does not match this model or a truncated
  // record, and then leaves the state as it was.
  virtual void writeState(StateWriter& out) const = 0;
  virtual void readState(StateReader& in) = 0;
  // What the solvers carry from step to step to start faster (a kept factorisation,
  // quasi-Newton pairs, warm starts) is not state: a save calls this after writeState, so that
  // the saved run and a reload of it continue from the same start.
  virtual void dropSolverCaches() {}

  virtual DisplaySurface displaySurface() const = 0;
};

}  // namespace chs
