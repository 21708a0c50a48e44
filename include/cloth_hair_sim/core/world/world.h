#pragma once
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "cloth_hair_sim/core/world/body.h"
#include "cloth_hair_sim/core/world/field_contact.h"

namespace chs {

// The constant model of a world: its grid and how bodies meet on it (MuJoCo's mjModel, with the
// bodies' own models inside them). Lengths in m.
struct WorldSettings {
  // dx of the grid all bodies share; <= 0: the first body's spacing, kept until the world is empty.
  double grid_spacing = 0.0;
  int kernel_degree = 2;  // B-spline degree of every body's field, 2 or 3
  // Contact between bodies (world/field_contact.h): Coulomb mu, and the distance delta at which
  // two bodies stop approaching (<= 0: a quarter of dx).
  double body_friction = 0.3;
  double contact_distance = 0.0;
  // No two bodies close on each other by more than cfl dx in a step (each body bounds its own
  // approach to the obstacles and to itself: mpm/approach_speed.h).
  double cfl = 0.3;
  // The particles all bodies may put on the grid together (control points, strand vertices,
  // solid particles): a body that would bring the world beyond it is refused by name and never
  // joins, so a load too large for the machine's memory fails with a message instead of
  // swapping or aborting a world that is stepping.
  int max_particles = 2000000;
};

// What one step did.
struct WorldStepReport {
  bool converged = true;                 // every body's implicit solve reached its tolerance
  std::vector<std::string> unconverged;  // names of the bodies whose solve did not
  std::vector<std::string> diverged;     // bodies with non-finite positions or velocities after it
  FieldContactStats contact;
};

// Force and moment a collider takes from the bodies in the last step: the opposite of the
// momentum its boundary conditions gave their grid nodes and particles, per unit time. The
// moment is about the world origin (momentAbout moves it).
struct ColliderLoad {
  Eigen::Vector3d force = Eigen::Vector3d::Zero();
  Eigen::Vector3d moment = Eigen::Vector3d::Zero();
  Eigen::Vector3d momentAbout(const Eigen::Vector3d& point) const {
    return moment - point.cross(force);
  }
};

// One world, many bodies: the bodies (shells now; rods, solids and rigid bodies to come) meet on
// one grid, each with its own velocity field there, and one step runs the stages of body.h over
// all of them with the contact between fields in the middle. The world owns the clock, the
// colliders (handed to every body) and the grid's spacing; the bodies own their models and
// states. A world's state is its time and the bodies' states (snapshot / restore).
class World {
 public:
  explicit World(const WorldSettings& settings = {});

  const WorldSettings& settings() const { return settings_; }
  // dx now: settings().grid_spacing, or the first body's, or 0 while the world is empty and has
  // none set. A body added later must be built with it (HybridShellSettings::grid_spacing).
  double gridSpacing() const;

  // Adds a body under a unique name (core/common/names.h) and hands it the colliders. The world
  // shares the body with its driver (a ROS node's garment, a tool's scene), which keeps its own
  // handle for pins and read-out. Throws InputError (and adds nothing) for a bad or duplicate
  // name, a null body, a body whose field has another spacing or kernel degree than the
  // world's, or one that would bring the world over settings().max_particles.
  Body& add(const std::string& name, std::shared_ptr<Body> body);
  // Removes the body; false if there is none of that name.
  bool remove(const std::string& name);
  int numBodies() const { return static_cast<int>(bodies_.size()); }
  // Particles the bodies put on the grid (Body::motion), all together.
  long numParticles() const;
  Body& body(int index) { return *bodies_[index].body; }
  const Body& body(int index) const { return *bodies_[index].body; }
  const std::string& name(int index) const { return bodies_[index].name; }
  Body* find(const std::string& name);

  void setColliders(const RigidSurfaces& colliders,
                    const std::vector<SurfaceVelocity>& velocities = {},
                    const std::vector<double>& frictions = {});
  int numColliders() const { return static_cast<int>(colliders_.size()); }

  // The stages of body.h over all bodies, with contact between their fields after the grid
  // update. Throws InputError for a non-positive or non-finite dt.
  WorldStepReport step(double dt);
  double time() const { return time_; }
  // The largest step every body tolerates now, and at which no two bodies close on each other by
  // more than settings().cfl dx.
  double stableTimeStep() const;
  // Per collider, over the last step (zero before the first).
  std::vector<ColliderLoad> colliderLoads() const;

  // The world's state: time and every body's state, for rollback and save/restore (the bodies'
  // models are not copied). restore takes a snapshot of this world with the same bodies.
  struct Snapshot {
    double time = 0.0;
    std::vector<std::string> names;
    std::vector<std::unique_ptr<DynamicsSnapshot>> bodies;
  };
  Snapshot snapshot() const;
  void restore(const Snapshot& snapshot);

 private:
  struct Entry {
    std::string name;
    std::shared_ptr<Body> body;
  };
  // Runs a stage of every body, side by side when there are several.
  void forEachBody(const std::function<void(Entry&)>& stage);
  WorldSettings settings_;
  double spacing_ = 0.0;
  std::vector<Entry> bodies_;
  RigidSurfaces colliders_;
  std::vector<SurfaceVelocity> collider_velocities_;
  std::vector<double> collider_frictions_;
  double time_ = 0.0, last_dt_ = 0.0;
};

}  // namespace chs
