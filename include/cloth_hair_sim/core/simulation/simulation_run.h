#pragma once
#include <array>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "cloth_hair_sim/core/io/simulation_scene.h"
#include "cloth_hair_sim/core/mpm/hybrid_shell_dynamics.h"
#include "cloth_hair_sim/core/rod/hair_dynamics.h"
#include "cloth_hair_sim/core/world/world.h"

namespace chs {

// What one body looked like at the end of a frame.
struct BodyFrame {
  double kinetic_energy = 0.0;  // J
  // m, of a garment's limit surface, or of a hair's vertices, into the colliders
  double deepest_penetration = 0.0;
  // largest length over reference length: of the limit surface between neighbouring control
  // vertices' points (garment, vertexStencils) or of a segment (hair)
  double largest_stretch = 1.0;
};

// One recorded frame: frame 0 is the initial state (no substeps, no wall time).
struct FrameRecord {
  int frame = 0;
  double time = 0.0;         // simulated, s
  double wall_time_s = 0.0;  // to step this frame
  int substeps = 0;          // world steps taken, halves of a rolled-back step included
  int rollbacks = 0;         // diverged steps rolled back and retried as halves
  int unconverged = 0;       // steps whose implicit solve fell short (redone explicitly)
  double kinetic_energy = 0.0;
  std::vector<BodyFrame> bodies;  // as the scene's bodies, then its hair
  // Per collider: World::colliderLoads over the frame's substeps, weighted by their length; the
  // moment about the collider frame's origin at the frame's end.
  std::vector<ColliderLoad> collider_loads;
};

// A scene's bodies stepped together in one World among its scripted colliders, frame by frame.
// Each frame is substeps of min(World::stableTimeStep(), time left in the frame); a step that
// diverges (a body non-finite, or the kinetic energy not finite) is rolled back
// (World::snapshot / restore) and retried as two halves, down to max_halvings levels; a step
// that still diverges, or a frame that needs more than the scene's max_substeps_per_frame,
// stops the run where the last good substep left it.
class SimulationRun {
 public:
  // Builds the bodies (HybridShellDynamics on the world's grid) and the hair (HairDynamics on
  // it; dx 1 cm when the world has no spacing of its own and no garment). Throws InputError for
  // a body the shell or the rods refuse.
  explicit SimulationRun(const SimulationScene& scene, int max_halvings = 4);

  int numFrames() const { return scene_.numFrames(); }
  int framesDone() const { return frames_done_; }
  bool finished() const { return frames_done_ >= numFrames() || stopped(); }
  bool stopped() const { return !stop_reason_.empty(); }
  const std::string& stopReason() const { return stop_reason_; }

  // The state now as a record (frame 0 before any advance).
  FrameRecord record() const;
  // Steps the next frame and returns its record; on a stop the record is of the partial frame
  // and stopped() is true. Throws std::logic_error once finished().
  FrameRecord advanceFrame();

  const World& world() const { return world_; }
  int numBodies() const { return static_cast<int>(bodies_.size()); }
  const HybridShellDynamics& body(int i) const { return *bodies_[i]; }
  int numHair() const { return static_cast<int>(hair_.size()); }
  const rod::HairDynamics& hair(int i) const { return *hair_[i]; }
  // Collider frames now, as the scene's colliders.
  std::vector<Eigen::Isometry3d> colliderPoses() const;

 private:
  // Sets the colliders at their pose at t1 with the velocity that moves them there from t0.
  void placeColliders(double t0, double t1);
  // One step of dt, rolled back and retried as halves down to `depth` more levels; false if a
  // step still diverged (the world is then at the last good state).
  bool guardedStep(double dt, int depth, FrameRecord& rec, std::vector<ColliderLoad>& load_sum);
  bool diverged(const WorldStepReport& report) const;
  // Hair roots carried by their collider to its pose at t (HairDynamics::setRootFrame).
  void placeRoots(double t);

  SimulationScene scene_;
  int max_halvings_;
  World world_;
  std::vector<std::shared_ptr<HybridShellDynamics>> bodies_;
  // Per body: its control edges, the limit surface's points at the control vertices
  // (vertexStencils) and the rest length between those points along each edge.
  std::vector<std::vector<std::array<int, 2>>> edges_;
  std::vector<std::vector<SurfaceStencil>> vertex_stencils_;
  std::vector<std::vector<double>> rest_lengths_;
  std::vector<std::shared_ptr<rod::HairDynamics>> hair_;
  int frames_done_ = 0;
  std::string stop_reason_;
};

}  // namespace chs
