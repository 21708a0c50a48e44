#pragma once
#include <functional>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "cloth_hair_sim/core/contact/rigid_surface.h"
#include "cloth_hair_sim/core/dynamics/cloth_dynamics.h"
#include "cloth_hair_sim/core/solver/symmetric_band_matrix.h"

namespace chs::rod {

struct ObstacleContactSettings {
  // Normal penalty per vertex, relative to the stretching stiffness EA / l of the strand's mean
  // segment: a vertex pressed with force N sinks N l / EA into the contact distance (hair at
  // 1 mm segments: 6e-8 m per mN), and the Newton matrix stays as well conditioned as the
  // strand's own. ObstacleContact takes it in N/m.
  double stiffness = 1.0;
  // eps_v of the smoothed friction [m/s]: below it friction acts as a stiff spring (a stuck
  // vertex creeps at a fraction of eps_v), above it as Coulomb's mu lambda.
  double slip_velocity = 1e-7;
  // Passes of the lagged normal forces per step, at most: each re-solves the strand with the
  // normal forces and normals of the previous pass (the first: of the step's start), until no
  // normal force changes by more than lag_tolerance of the largest. The forces are relaxed,
  // lambda <- lambda + omega (lambda(x) - lambda) with omega = 1 / (1 + 2 mu theta), theta the
  // strand's turning over its contacts: taken whole (omega = 1) the passes alternate, since
  // more friction lowers the tension and with it the normal force it rests on (the error
  // shrinks at most by mu theta per pass and grows beyond mu theta = 1; a capstan at mu = 0.3
  // over theta = pi held 2.27 instead of e^{mu theta} = 2.57 after 3 passes, and left the
  // cylinder after 6; 1 / (1 + mu theta) still lost the helical full wrap at mu = 0.3 in one
  // run of two).
  int lag_passes = 24;
  double lag_tolerance = 1e-3;
  // [m/s] A vertex that starts the step deeper than the contact distance (the obstacle jumped,
  // or the strand was held still while it moved on) is pushed out at most this fast beyond the
  // obstacle's own motion (as a rigid-body engine's depenetration speed): the stiff implicit
  // penalty would push it out within the step, at depth / dt, which at small steps exceeds any
  // real speed and flings the strand. The step's end removes depth from positions no faster
  // (HairDynamics::transferFromGrid).
  double recovery_speed = 0.1;
};

// An obstacle as a strand's implicit solve sees it: its signed distance, its motion over the
// step and its Coulomb mu.
struct StrandObstacle {
  std::shared_ptr<const RigidSurface> surface;
  SurfaceVelocity velocity;
  double friction = 0.0;
};

// One vertex against one obstacle, with the lagged quantities of IPC's friction (Li et al.,
// "Incremental Potential Contact", SIGGRAPH 2020, section 5): normal force lambda and normal n.
struct LaggedContact {
  int vertex = 0;
  int obstacle = 0;
  double normal_force = 0.0;  // lambda [N]
  double gap = 0.0;           // the vertex's signed distance from the obstacle at the lag
  // Where the penalty rests the vertex: the contact distance d, or less for a vertex that
  // started the step deeper (ObstacleContactSettings::recovery_speed).
  double rest_distance = 0.0;
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();          // n, outward
  Eigen::Vector3d obstacle_motion = Eigen::Vector3d::Zero();  // dt v_obstacle at the vertex
};

// The obstacles' contact with a strand's vertices as terms of its incremental potential
// (strand_newton_solver.h), so that friction acts inside the implicit solve and tension can
// build along a strand held by it (the capstan). Per contact, with d the contact distance (the
// strand's radius: the centreline rests a radius off the surface) and g the signed distance of
// the vertex from the obstacle moved by its step's motion:
//   normal    k / 2 (d_c - g)^2 for g < d_c (lambda = k (d_c - g) is the normal force), with
//             d_c = min(d, g_0 + dt v_r), g_0 the vertex's distance at the step's start and v_r
//             the recovery speed (d_c = d but for a vertex that starts inside),
//   friction  mu lambda f0(|P (x - x^n - dt v_obstacle)|), P = I - n n^T,
// IPC's smoothed friction dissipation potential (Li et al. 2020, (14)-(17)) with
// f0(y) = -y^3 / (3 e^2) + y^2 / e + e / 3 for y < e = eps_v dt, y beyond: its gradient is
// Coulomb's mu lambda against the slip beyond e and a spring of stiffness 2 mu lambda / e
// below. lambda and n are lagged (fixed while Newton solves, updated between passes).
class ObstacleContact {
 public:
  ObstacleContact(const std::vector<StrandObstacle>& obstacles,
                  const ObstacleContactSettings& settings, double contact_distance, double dt,
                  const std::vector<Eigen::Vector3d>& x_start);

  // The lag of the next pass from the configuration q (the first pass: the step's start): every
  // vertex within `reach` of the contact distance is a candidate (its penalty acts once it
  // comes within d; its friction from the next pass on, when its lambda is known). Vertices
  // flagged in `skip` (held ones) get none.
  // From the second pass on, a contact that the previous lag also had keeps its normal force
  // relaxed towards the new one (see ObstacleContactSettings::lag_passes). Returns the largest
  // change of a normal force, unrelaxed, relative to the largest normal force (0 without any).
  double updateLag(const Eigen::VectorXd& q, double reach, const std::vector<char>& skip);
  // With many obstacles: those near a point (their indices, ascending) with every other farther
  // than `beyond` from it now (mpm::ColliderCandidates over the same obstacles); a vertex then
  // asks those alone while reach, the contact distance and the obstacle's motion over the step
  // fit within `beyond`.
  void setNearObstacles(std::function<const std::vector<int>&(const Eigen::Vector3d&)> near,
                        double beyond);
  const std::vector<LaggedContact>& contacts() const { return contacts_; }
  bool empty() const { return contacts_.empty(); }

  double energy(const Eigen::VectorXd& q) const;
  // Adds the gradient (vertex i's at 4 i) and the Hessian (positive semi-definite, the normal's
  // curvature dropped); hessian may be null.
  void addDerivatives(const Eigen::VectorXd& q, Eigen::VectorXd& gradient,
                      SymmetricBandMatrix* hessian) const;
  // The force each contact applies to its vertex at q (minus its gradient).
  std::vector<Eigen::Vector3d> forces(const Eigen::VectorXd& q) const;

 private:
  double frictionGain(const Eigen::VectorXd& q) const;
  double normalGap(const LaggedContact& c, const Eigen::Vector3d& x, Eigen::Vector3d* normal) const;
  double contactEnergy(const LaggedContact& c, const Eigen::Vector3d& x) const;
  void contactDerivatives(const LaggedContact& c, const Eigen::Vector3d& x, Eigen::Vector3d& g,
                          Eigen::Matrix3d* h) const;

  const std::vector<StrandObstacle>& obstacles_;
  ObstacleContactSettings settings_;
  double distance_, dt_;
  std::vector<Eigen::Vector3d> x_start_;
  std::function<const std::vector<int>&(const Eigen::Vector3d&)> near_;
  double near_beyond_ = 0.0;
  std::vector<double> near_move_;  // per vertex, the most an obstacle moves at it over the step
  std::vector<LaggedContact> contacts_;
};

}  // namespace chs::rod
