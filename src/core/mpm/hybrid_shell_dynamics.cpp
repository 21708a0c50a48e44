#include "cloth_hair_sim/core/mpm/hybrid_shell_dynamics.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <utility>

#include <Eigen/LU>

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "cloth_hair_sim/core/collision/penetration_depth.h"
#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/common/rigid_velocity.h"
#include "cloth_hair_sim/core/mesh/mesh_check.h"
#include "cloth_hair_sim/core/mpm/bdf2.h"
#include "cloth_hair_sim/core/mpm/bspline_kernel.h"
#include "cloth_hair_sim/core/mpm/collider_candidates.h"
#include "cloth_hair_sim/core/mpm/elastic_solid.h"
#include "cloth_hair_sim/core/mpm/grid_forces.h"
#include "cloth_hair_sim/core/mpm/grid_interpolation.h"
#include "cloth_hair_sim/core/mpm/mass_supported_gradient.h"
#include "cloth_hair_sim/core/mpm/node_sums.h"
#include "cloth_hair_sim/core/mpm/transfers.h"

namespace chs {
namespace {

using Vec3 = Eigen::Vector3d;
using Clock = std::chrono::steady_clock;

// Adds the wall time of its scope to a stage's total.
class StageTimer {
 public:
  explicit StageTimer(double& total) : total_(total), start_(Clock::now()) {}
  ~StageTimer() { total_ += std::chrono::duration<double>(Clock::now() - start_).count(); }

 private:
  double& total_;
  Clock::time_point start_;
};

const DrapeProblem& validated(const DrapeProblem& problem, const HybridShellSettings& s) {
  problem.validate();
  checkMesh(problem.mesh);
  auto positive = [](double v, const char* what) {
    if (!(std::isfinite(v) && v > 0.0))
      throw InputError(std::string("hybrid shell: ") + what + " must be positive and finite");
  };
  positive(problem.material.young, "Young's modulus");
  positive(problem.material.thickness, "thickness");
  positive(problem.material.areal_density, "areal density");
  if (!std::isfinite(s.grid_spacing)) throw InputError("hybrid shell: grid spacing is not finite");
  if (s.kernel_degree != 2 && s.kernel_degree != 3)
    throw InputError("hybrid shell: kernel degree must be 2 or 3");
  positive(s.cfl, "CFL number");
  positive(s.safety, "time step safety factor");
  if (!(s.rpic_damping >= 0.0 && s.rpic_damping <= 1.0))
    throw InputError("hybrid shell: RPIC damping must lie in [0, 1]");
  if (!(s.flip_blend >= 0.0 && s.flip_blend <= 1.0))
    throw InputError("hybrid shell: FLIP blend (Han's xi) must lie in [0, 1]");
  if (!(s.damping >= 0.0 && std::isfinite(s.damping)))
    throw InputError("hybrid shell: damping must be >= 0 and finite");
  if (s.contact_particles_per_edge < 1 || s.contact_particles_per_edge > 8)
    throw InputError("hybrid shell: contact particles per face edge must lie in 1..8");
  if (!(s.contact_mass_fraction >= 0.0 && s.contact_mass_fraction < 1.0))
    throw InputError("hybrid shell: contact mass fraction must lie in [0, 1)");
  if (!(s.friction >= 0.0 && std::isfinite(s.friction)))
    throw InputError("hybrid shell: collider friction must be >= 0 and finite");
  if (s.kirchhoff_love.in_plane_order < 2)
    throw InputError(
        "hybrid shell: Kirchhoff-Love quadrature needs at least 2 x 2 points per face (1 x 1 "
        "leaves the shell spurious zero-energy modes)");
  if (s.display_segments < 1 || s.display_segments > 16)
    throw InputError("hybrid shell: display segments per face edge must lie in 1..16");
  positive(s.max_time_step, "maximum time step");
  positive(s.implicit_tolerance, "implicit solve tolerance");
  positive(s.lagrangian_tolerance, "Lagrangian solve tolerance");
  if (!(s.lagrangian_gravity_fraction >= 0.0 && s.lagrangian_gravity_fraction < 1.0))
    throw InputError("hybrid shell: Lagrangian gravity fraction must lie in [0, 1)");
  if (!(s.obstacle_stiffness >= 0.0 && std::isfinite(s.obstacle_stiffness) &&
        s.obstacle_point_stiffness >= 0.0 && std::isfinite(s.obstacle_point_stiffness)))
    throw InputError("hybrid shell: obstacle penalty stiffnesses must be >= 0 and finite");
  positive(s.obstacle_offset, "obstacle penalty offset");
  positive(s.obstacle_friction_velocity, "obstacle friction velocity");
  if (s.elastic_history < 0 || s.elastic_history > 64)
    throw InputError("hybrid shell: L-BFGS history of the elastic solve must lie in 0..64");
  if (s.max_newton_iterations < 1 || s.max_krylov_iterations < 1 || s.elastic_max_iterations < 1)
    throw InputError("hybrid shell: Newton and Krylov iteration limits must be at least 1");
  if (!(s.krylov_tolerance > 0.0 && s.krylov_tolerance < 1.0))
    throw InputError("hybrid shell: Krylov tolerance must lie in (0, 1)");
  if (problem.mesh.numVertices() > s.max_control_points)
    throw InputError("hybrid shell: the garment has " + std::to_string(problem.mesh.numVertices()) +
                     " control points, more than the limit of " +
                     std::to_string(s.max_control_points) +
                     " (HybridShellSettings::max_control_points); coarsen the mesh");
  return problem;
}

double meanEdgeLength(const QuadMesh& mesh) {
  double sum = 0.0;
  int n = 0;
  for (const auto& q : mesh.quads)
    for (int k = 0; k < 4; ++k, ++n)
      sum += (mesh.vertices[q[(k + 1) % 4]] - mesh.vertices[q[k]]).norm();
  return sum / n;
}

struct HybridSnapshot : DynamicsSnapshot {
  mpm::Particles control, contact;
  std::vector<Vec3> fibre;
  std::vector<Eigen::Matrix3d> plastic;  // F^{KL,P} of each quadrature point
  std::vector<Vec3> pin_force, clamp_residual;
  mpm::Particles solid;
  std::optional<mpm::HenckySolid> solid_material;
  double solid_wave_speed = 0.0;
  double time = 0.0;
  std::vector<Vec3> bdf2_x, bdf2_v;  // BDF2's history (kLagrangianBdf2)
  std::vector<char> bdf2_valid;
  double bdf2_dt = 0.0;
};

// Particle state of a state file: kinematics always, mass and volume for a set that the model
// does not rebuild (the solid).
void writeParticles(StateWriter& out, const mpm::Particles& p, bool with_mass) {
  out.vectors(p.x);
  out.vectors(p.v);
  out.matrices(p.C);
  out.matrices(p.F);
  if (!with_mass) return;
  out.reals(p.mass);
  out.reals(p.volume0);
}

// Into a copy of `like` (its mass and volume kept unless with_mass); n: the expected count.
mpm::Particles readParticles(StateReader& in, const mpm::Particles& like, std::size_t n,
                             bool with_mass, const char* what) {
  const std::string w(what);
  mpm::Particles p = like;
  p.x = in.vectors((w + " positions").c_str(), n);
  p.v = in.vectors((w + " velocities").c_str(), n);
  p.C = in.matrices((w + " affine velocities").c_str(), n);
  p.F = in.matrices((w + " deformation gradients").c_str(), n);
  if (with_mass) {
    p.mass = in.reals((w + " masses").c_str(), n);
    p.volume0 = in.reals((w + " volumes").c_str(), n);
  }
  return p;
}

}  // namespace

HybridShellDynamics::HybridShellDynamics(const DrapeProblem& problem,
                                         const HybridShellSettings& settings)
    : settings_(settings),
      thickness_(validated(problem, settings).material.thickness),
      areal_density_(problem.material.areal_density),
      young_(problem.material.young),
      poisson_(problem.material.poisson),
      control_spacing_(meanEdgeLength(problem.mesh)),
      dx_(settings.grid_spacing > 0.0 ? settings.grid_spacing : control_spacing_),
      gravity_(problem.gravity),
      clamps_(problem.mesh, problem.bc.clamped),
      surface_(std::make_shared<LimitSurface>(clamps_.extendedMesh())),
      lamina_(problem.material.young, problem.material.poisson, settings.yield_stress),
      kl_points_(buildKirchhoffLovePoints(
          clamps_.numMeshFaces(),
          [this](int f, double u, double v) { return surface_->stencil(f, u, v); },
          clamps_.extendedMesh().vertices, problem.material.thickness, settings.kirchhoff_love)),
      grid_(dx_),
      pins_({"hybrid shell", "control point", "control points"}, clamps_.extendedMesh().vertices) {
  contact_material_ = settings.contact;
  if (contact_material_.normal_stiffness <= 0.0) contact_material_.normal_stiffness = young_;
  if (contact_material_.shear_stiffness <= 0.0) contact_material_.shear_stiffness = 0.1 * young_;
  contact_material_.validate();

  // Ghost faces (clamped edges) shape the limit surface but carry no cloth: mass, contact
  // particles, quadrature points and display come from the mesh's own faces.
  const std::vector<Vec3>& x0 = clamps_.extendedMesh().vertices;
  const int nc = static_cast<int>(x0.size());
  const double frac = settings.contact_mass_fraction;
  // Type (ii): control points, mass lumped as the integral of rho_A N_p over the limit surface
  // (the basis is a partition of unity, so the masses sum to rho_A times the area).
  std::vector<double> lumped(nc, 0.0);
  const double g = 0.5 / std::sqrt(3.0);  // 2-point Gauss on [0, 1] at 1/2 -+ g
  const int n = settings.contact_particles_per_edge;
  std::vector<SurfaceStencil> contact_stencils;
  for (int f = 0; f < clamps_.numMeshFaces(); ++f) {
    for (int a = 0; a < n; ++a)
      for (int b = 0; b < n; ++b) {
        // Type (iii): one contact particle at the centre of each of n x n sub-cells; the cell's
        // area comes from 2 x 2 Gauss points, which also lump the control masses.
        double cell_area = 0.0;
        for (double gu : {0.5 - g, 0.5 + g})
          for (double gv : {0.5 - g, 0.5 + g}) {
            const SurfaceStencil s = surface_->stencil(f, (a + gu) / n, (b + gv) / n);
            const double da =
                0.25 * s.combine(s.du, x0).cross(s.combine(s.dv, x0)).norm() / (n * n);
            cell_area += da;
            for (int k = 0; k < s.size(); ++k)
              lumped[s.points[k]] += (1.0 - frac) * areal_density_ * da * s.w[k];
          }
        SurfaceStencil s = surface_->stencil(f, (a + 0.5) / n, (b + 0.5) / n);
        contact_.p.add(s.position(x0), Vec3::Zero(), frac * areal_density_ * cell_area,
                       cell_area * thickness_);
        // Unstressed: a3^E = a3 (5.5).
        contact_.fibre.push_back(s.combine(s.du, x0).cross(s.combine(s.dv, x0)).normalized());
        contact_stencils.push_back(std::move(s));
      }
  }
  contact_.stencil = FirstOrderStencils(contact_stencils);
  if (lagrangian() && settings.contact_between_layers_only) {
    std::vector<int> face(contact_.size());
    for (int p = 0; p < contact_.size(); ++p) face[p] = p / (n * n);
    // Two particles share a node when they lie within (degree + 1) cells of each other along
    // each axis, so at most sqrt(3) (degree + 1) cells apart.
    layers_ =
        std::make_unique<mpm::LayerProximity>(clamps_.extendedMesh(), std::move(face),
                                              std::sqrt(3.0) * (settings.kernel_degree + 1) * dx_);
    control_face_.assign(nc, -1);
    const auto& quads = clamps_.extendedMesh().quads;
    for (int f = static_cast<int>(quads.size()) - 1; f >= 0; --f)
      for (int c : quads[f]) control_face_[c] = f;
  }
  contact_.fibre_force.assign(contact_.size(), Vec3::Zero());
  for (int p = 0; p < nc; ++p) control_.add(x0[p], Vec3::Zero(), lumped[p], 0.0);
  for (int p = 0; p < nc; ++p)
    if (!(lumped[p] > 0.0))
      throw InputError("hybrid shell: control point " + std::to_string(p) +
                       " carries no mass (it influences no part of the limit surface)");
  control_force_.assign(nc, Vec3::Zero());

  const LimitTessellation t =
      surface_->tessellate(settings.display_segments, clamps_.numMeshFaces());
  for (const SurfacePoint& sp : t.samples)
    display_stencils_.push_back(surface_->stencil(sp.face, sp.u, sp.v));
  display_triangles_ = t.triangles;
  if (settings.surface_collisions)
    surface_collisions_ = std::make_unique<mpm::SurfaceCollisions>(display_stencils_);

  free_axes_.assign(nc, Vec3::Ones());
  for (const auto& f : problem.bc.fixed_components) {
    checkNotClamped(f.vertex);
    free_axes_[f.vertex][f.axis] = 0.0;
  }
  reference_ = x0;
  pin_force_.assign(nc, Vec3::Zero());
  clamp_residual_.assign(nc, Vec3::Zero());
  step_start_velocity_.assign(nc, Vec3::Zero());
  for (int v : problem.bc.pinned) {
    checkNotClamped(v);
    pins_.pinInPlace(v, x0);
  }
  setColliders(problem.colliders);
  // The elastic solve's pattern and fill-reducing order now, with the garment (the node builds
  // it outside the world's lock), not in its first step: 0.4 s for a 90 x 90 curtain.
  if (lagrangian()) buildElasticity();
}

void HybridShellDynamics::step(double dt) {
  if (!(dt > 0.0 && std::isfinite(dt)))
    throw InputError("hybrid shell: time step must be positive, got " + std::to_string(dt));
  if (settings_.integration != TimeIntegration::kBackwardEuler) {
    advance(dt, settings_.integration);
    return;
  }
  // A backward Euler solve that stops short of its tolerance (Newton stalls at the kinks of
  // the Coulomb return and the fibres' separation once layers touch) would keep an iterate that
  // can let layers pass through each other: the step is redone with explicit substeps instead,
  // the pins moving along the same straight path.
  const std::unique_ptr<DynamicsSnapshot> start = snapshot();
  advance(dt, TimeIntegration::kBackwardEuler);
  if (last_solve_.converged()) return;
  restore(*start);
  ++implicit_fallbacks_;
  const double t0 = time_, t1 = time_ + dt;
  const std::vector<Vec3> from = control_.x;
  const PinSet held = pins_;
  while (time_ < t1 - 1e-12 * dt) {
    const double h = std::min(explicitTimeStep(), t1 - time_);
    const double f = (time_ + h - t0) / dt;
    held.forEachPinned([&](int p) { pins_.pin(p, from[p] + (held.target(p) - from[p]) * f); });
    advance(h, TimeIntegration::kSymplecticEuler);
  }
  pins_ = held;
}

void HybridShellDynamics::advance(double dt, TimeIntegration integration) {
  beginStep(dt);
  transferToGrid();
  updateGrid(dt, integration);
  transferFromGrid(dt);
  endStep(dt);
}

void HybridShellDynamics::beginStep(double dt) {
  // Pins carry their control points to the target at constant velocity over this step.
  pins_.forEachPinned([&](int p) {
    step_start_velocity_[p] = control_.v[p];
    control_.v[p] = (pins_.target(p) - control_.x[p]) / dt;
  });
  for (const ClampedEdges::Clamp& c : clamps_.clamps()) {
    step_start_velocity_[c.boundary] = control_.v[c.boundary];
    step_start_velocity_[c.ghost] = control_.v[c.ghost];
  }
  collider_impulse_.assign(grid_colliders_.size(), mpm::ColliderImpulse());
  if (lagrangian()) {
    StageTimer t(times_.elastic_solve);
    solveElasticity(dt);
  }
}

void HybridShellDynamics::buildElasticity() {
  const int n = numVertices();
  ControlPointLinks links;
  links.owner.resize(n);
  links.map.assign(n, Eigen::Matrix3d::Identity());
  for (int p = 0; p < n; ++p) links.owner[p] = p;
  for (const ClampedEdges::Clamp& c : clamps_.clamps()) {
    // The slaving of clamped_edges.h: x_B = c - (I - t t^T)(x_N - c) / 2, x_G = c + R (x_N - c).
    const Eigen::Matrix3d tt = c.direction * c.direction.transpose();
    links.owner[c.boundary] = links.owner[c.ghost] = c.interior;
    links.map[c.boundary] = -0.5 * (Eigen::Matrix3d::Identity() - tt);
    links.map[c.ghost] = Eigen::Matrix3d::Identity() - 2.0 * tt;
  }
  elasticity_ = std::make_unique<ImplicitElasticity>(kl_points_, n, std::move(links));
}

// The elastic stage of the Lagrangian implicit step: backward Euler of the control points alone
// (shell/implicit_elasticity.h) from x^ = x^n + dt v^n / (1 + c dt) + dt^2 g, with the damping
// taken implicitly on the incoming velocity as dampGridMomentum does. Pins hold their targets,
// fixed components their reference values, clamps slave their points to the interior
// neighbours. The solution's velocities (x* - x^n) / dt are what the grid receives; its forces
// -dPsi/dx(x*) are what pins and clamps balance.
void HybridShellDynamics::solveElasticity(double dt) {
  const int n = numVertices();
  if (!elasticity_) buildElasticity();
  std::vector<Vec3> x_hat(n), x(n), free = free_axes_;
  // Backward Euler, or BDF2 (a0 x^{n+1} + a1 x^n + a2 x^{n-1} = dt v^{n+1}, the same for v and
  // a, bdf2.h) for the points that have a history: both minimise sum m_p |x_p - x^_p|^2 /
  // (2 h_p^2) + Psi(x) with h_p = dt / a0 and x^ = -(a1 x^n + a2 x^{n-1}) / a0
  // - dt (a1 v^n + a2 v^{n-1}) / a0^2 + h^2 g; the solve takes h_p through the mass m a0^2.
  // Damping as 1 / (1 + c h) on the velocity part. Newton starts from the inertial motion without
  // gravity: from x^ itself a stiff membrane would start stretched by h^2 g against its pins, a
  // residual a hundred times larger.
  const bool bdf2 = settings_.integration == TimeIntegration::kLagrangianBdf2;
  if (bdf2 && static_cast<int>(bdf2_.valid.size()) != n) {
    bdf2_.x.assign(n, Vec3::Zero());
    bdf2_.v.assign(n, Vec3::Zero());
    bdf2_.valid.assign(n, 0);
  }
  const Bdf2Coefficients second = bdf2Coefficients(dt, bdf2_.dt);
  step_start_x_ = control_.x;
  step_start_v_ = control_.v;
  second_order_.assign(n, 0);
  std::vector<double> inertia(n);
  for (int p = 0; p < n; ++p) {
    second_order_[p] = bdf2 && bdf2_.valid[p] && bdf2_.dt > 0.0;
    const Bdf2Coefficients c = second_order_[p] ? second : Bdf2Coefficients{};
    const double h = dt / c.a0;
    const double keep = 1.0 / (1.0 + settings_.damping * h);
    const Vec3 xp = second_order_[p] ? bdf2_.x[p] : Vec3::Zero();
    const Vec3 vp = second_order_[p] ? bdf2_.v[p] : Vec3::Zero();
    x[p] = -(c.a1 * control_.x[p] + c.a2 * xp) / c.a0 -
           keep * dt / (c.a0 * c.a0) * (c.a1 * control_.v[p] + c.a2 * vp);
    x_hat[p] = x[p] + h * h * gravity_;
    inertia[p] = control_.mass[p] * c.a0 * c.a0;
  }
  for (int p = 0; p < n; ++p)
    for (int a = 0; a < 3; ++a)
      if (free_axes_[p][a] == 0.0) x[p][a] = reference_[p][a];
  pins_.forEachPinned([&](int p) {
    x[p] = pins_.target(p);
    free[p].setZero();
  });
  clamps_.placePositions(x);
  ImplicitElasticitySettings es;
  es.tolerance = lagrangianTolerance(dt);
  es.max_iterations = settings_.elastic_max_iterations;
  es.reuse_factorization = settings_.reuse_factorization;
  es.history = settings_.elastic_history;
  es.obstacles.stiffness = grid_colliders_.empty() ? 0.0 : settings_.obstacle_stiffness;
  es.obstacles.point_stiffness = settings_.obstacle_point_stiffness;
  es.obstacles.offset = settings_.obstacle_offset;
  es.obstacles.friction_velocity = settings_.obstacle_friction_velocity;
  es.obstacles.start = &control_.x;
  // Twice the rest sag, and a lift of 1 cm/s for a cloth laid inside the band.
  const double beta = settings_.obstacle_stiffness + settings_.obstacle_point_stiffness;
  es.obstacles.rise = (beta > 0.0 ? 2.0 * gravity_.norm() * dt * dt / beta : 0.0) + 1e-2 * dt;
  // Each obstacle where it will be at the step's end: a point x then is where x - dt v(x) is now.
  // The solve uses only obstacles nearer than the offset: those a cell's list holds.
  const mpm::ColliderCandidates candidates(grid_colliders_, dt, settings_.obstacle_offset, dx_);
  es.obstacles.nearest = [this, dt, &candidates](const Vec3& x) {
    ObstacleQuery nearest;
    for (int k : candidates.near(x)) {
      const mpm::GridCollider& c = grid_colliders_[k];
      const Vec3 v = c.velocity.at(x);
      const SurfaceProjection q = c.surface->project(x - dt * v);
      if (nearest.obstacle < 0 || q.gap < nearest.distance)
        nearest = {static_cast<int>(k), q.gap, q.normal, v, c.friction};
    }
    return nearest;
  };
  last_elastic_ = elasticity_->solve(
      x, x_hat, inertia, dt, free, lamina_,
      [this](std::vector<Vec3>& y) { clamps_.placePositions(y); }, es);
  lagrangian_velocity_.resize(n);
  elastic_force_.resize(n);
  for (int p = 0; p < n; ++p) {
    lagrangian_velocity_[p] = (x[p] - control_.x[p]) / dt;
    elastic_force_[p] = -elasticity_->elasticGradient()[p] - elasticity_->obstacleGradient()[p];
  }
  for (const ObstaclePush& push : elasticity_->obstaclePushes())
    collider_impulse_[push.obstacle].add(push.point, dt * push.force);
  control_.v = lagrangian_velocity_;
}

bool HybridShellDynamics::updateGrid(double dt) {
  return updateGrid(dt, settings_.integration);
}

bool HybridShellDynamics::updateGrid(double dt, TimeIntegration integration) {
  if (integration == TimeIntegration::kLagrangianImplicit ||
      integration == TimeIntegration::kLagrangianBdf2) {
    StageTimer t(times_.grid_update);
    solveGridMomentum(dt, true);
    return last_solve_.converged() && last_elastic_.converged;
  }
  if (integration == TimeIntegration::kBackwardEuler) {
    StageTimer t(times_.grid_update);
    solveGridMomentum(dt);
    return last_solve_.converged();
  }
  {
    StageTimer t(times_.shell_forces);
    computeGridForces();
  }
  StageTimer t(times_.grid_update);
  updateGridMomentum(dt);
  return true;
}

void HybridShellDynamics::reapplyColliders() {
  mpm::applyGridColliders(grid_, grid_colliders_, &collider_impulse_);
}

void HybridShellDynamics::transferFromGrid(double dt) {
  StageTimer t(times_.transfer_to_particles);
  transferToParticles(dt);
  updatePositionsAndTrialState(dt);
}

void HybridShellDynamics::endStep(double dt) {
  {
    StageTimer t(times_.plasticity);
    updatePlasticity();
  }
  if (settings_.integration == TimeIntegration::kLagrangianBdf2) updateBdf2History(dt);
  time_ += dt;
  ++times_.steps;
}

// The grid moved each control point by its displacement velocity u = (x^{n+1} - x^n) / dt (the
// elastic stage's u* plus the grid's change u - u*). BDF2's state velocity is that of the elastic
// stage, (a0 x* + a1 x^n + a2 x^{n-1}) / dt, plus the grid's change as an impulse. Where the grid
// changed u by more than a quarter of u* (contact with an obstacle, another layer or body) the
// point restarts from backward Euler: BDF2 extrapolates the velocity from before the impact and
// would bounce it off; so does a point an obstacle's projection placed. Pinned points have no
// history either (their path is prescribed), and after an elastic solve short of its tolerance
// none has: BDF2 would carry the iterate's error on (in 2 of 3 runs of cloth_vs_bullet the
// wrinkling cloth then stretched by 23-40 %).
void HybridShellDynamics::updateBdf2History(double dt) {
  const Bdf2Coefficients second = bdf2Coefficients(dt, bdf2_.dt);
  for (int p = 0; p < numVertices(); ++p) {
    const Vec3 change = control_.v[p] - lagrangian_velocity_[p];
    // An obstacle's projection moves a point without a velocity: BDF2 would read it as one.
    const Vec3 placed = control_.x[p] - (step_start_x_[p] + dt * control_.v[p]);
    const bool smooth = last_elastic_.converged && !pins_.isPinned(p) &&
                        change.norm() <= 0.25 * lagrangian_velocity_[p].norm() &&
                        placed.norm() <= 1e-3 * dt * control_.v[p].norm() + 1e-12;
    if (second_order_[p] && smooth) {
      const Vec3 x_elastic = step_start_x_[p] + dt * lagrangian_velocity_[p];
      control_.v[p] =
          (second.a0 * x_elastic + second.a1 * step_start_x_[p] + second.a2 * bdf2_.x[p]) / dt +
          change;
    }
    bdf2_.x[p] = step_start_x_[p];
    bdf2_.v[p] = step_start_v_[p];
    bdf2_.valid[p] = smooth;
  }
  bdf2_.dt = dt;
}

// Han (5.37)-(5.38): APIC transfer of control and contact particles onto one grid. Pinned
// control points are prescribed, not grid degrees of freedom (a Dirichlet condition): they give
// the grid neither mass nor force, and act on the cloth through the shell energy alone. Handed
// to the grid, their zero velocity would smear a clamp over a kernel width (a cantilever read
// 4-10 % stiff) and hold their neighbours back. The solid's particles (type (i)) are the third
// set: where their supports overlap the cloth's, the nodes carry both, and that shared velocity
// is the two-way coupling.
void HybridShellDynamics::transferToGrid() {
  StageTimer t(times_.transfer_to_grid);
  transfer_mass_ = control_.mass;
  for (const ClampedEdges::Clamp& c : clamps_.clamps()) {
    transfer_mass_[c.interior] +=
        ClampedEdges::carriedMass(control_.mass[c.boundary], control_.mass[c.ghost]);
    transfer_mass_[c.boundary] = transfer_mass_[c.ghost] = 0.0;
  }
  pins_.forEachPinned([&](int p) { transfer_mass_[p] = 0.0; });
  std::swap(control_.mass, transfer_mass_);  // the transfer reads the particles' mass field
  mpm::particleToGrid({&control_, &contact_.p, &solid_}, grid_, settings_.kernel_degree,
                      &supports_);
  std::swap(control_.mass, transfer_mass_);
  if (layers_) layers_->find(grid_, supports_[1], contact_.p.x, near_layer_);
  // The fibres' weight gradients serve their forces and their velocity gradient, which a step
  // with no fibre in contact does without (solveGridMomentum).
  if (!(lagrangian() && contactFree()))
    mpm::tabulateMassSupportedGradients(grid_, contact_.p.x, settings_.kernel_degree, supports_[1],
                                        fibre_weight_gradients_);
  if (lagrangian() && settings_.flip_blend > 0.0) transferred_velocity_ = grid_.velocity;
}

// Han (5.46)-(5.49) at x* = x_i (symplectic Euler): the forces at the step's start; the solid's
// -sum_p V_p^0 tau(F_p) grad w_ip (3.9) adds to them.
void HybridShellDynamics::computeGridForces() {
  scatterShellForces(control_.x, contact_.fibre);
  if (solid_.size() > 0)
    mpm::scatterElasticStress(grid_, solid_, *solid_material_, settings_.kernel_degree,
                              &supports_[2]);
}

// The Kirchhoff-Love forces on the control points (5.32) and the contact forces through the
// surface tangents reach the grid with the control points' weights (5.48); the fibre part of the
// contact force with the weight gradients (5.49), dotted with the step-start fibre a^n because
// the trial fibre is (I + dt sum_i v_i (x) grad w_ip) a^n (5.44).
void HybridShellDynamics::scatterShellForces(const std::vector<Vec3>& x_control,
                                             const std::vector<Vec3>& fibres,
                                             bool with_elasticity) {
  const int nc = numVertices();
  std::fill(grid_.force.begin(), grid_.force.end(), Vec3::Zero());
  if (with_elasticity) {
    kirchhoffLoveEnergy(kl_points_, lamina_, x_control, &kl_gradient_);
    for (int p = 0; p < nc; ++p) control_force_[p] = -kl_gradient_[p];  // (5.32)
  } else {
    std::fill(control_force_.begin(), control_force_.end(), Vec3::Zero());
  }
  tbb::enumerable_thread_specific<std::vector<Vec3>> local(
      [nc] { return std::vector<Vec3>(nc, Vec3::Zero()); });
  tbb::parallel_for(0, contact_.size(), [&](int p) {
    Vec3 a1, a2;
    contact_.stencil.tangents(p, x_control, a1, a2);
    const ContactEnergy e = contactEnergy(a1, a2, fibres[p], contact_material_);
    const double V = contact_.p.volume0[p];
    std::vector<Vec3>& f = local.local();
    for (auto t = contact_.stencil.begin(p); t != contact_.stencil.end(p); ++t)
      f[t->point] -= V * (t->du * e.d_a1 + t->dv * e.d_a2);
    contact_.fibre_force[p] = -V * e.d_a3;
  });
  for (const auto& f : local)
    for (int p = 0; p < nc; ++p) control_force_[p] += f[p];
  grid_force_ = control_force_;
  // Clamped points and ghosts move with their interior neighbour N: their forces, and the part of
  // their weight the grid does not already apply to the mass N carries for them, act on N.
  const Vec3 g = with_elasticity ? gravity_ : Vec3::Zero();
  for (const ClampedEdges::Clamp& c : clamps_.clamps()) {
    const double mb = control_.mass[c.boundary], mg = control_.mass[c.ghost];
    grid_force_[c.interior] +=
        clamps_.foldedForce(c, grid_force_[c.boundary] + mb * g, grid_force_[c.ghost] + mg * g) -
        ClampedEdges::carriedMass(mb, mg) * g;
    grid_force_[c.boundary].setZero();
    grid_force_[c.ghost].setZero();
  }
  // Pinned points are held by their pins instead (transferToGrid).
  pins_.forEachPinned([&](int p) { grid_force_[p].setZero(); });
  mpm::scatterPointForces(grid_, control_.x, grid_force_, settings_.kernel_degree, &supports_[0]);
  // The fibres move with S v (carriedVelocity), so their force f reaches the grid as the
  // transpose, P(f / m): the pair stays the gradient of one contact energy.
  std::swap(grid_.force, shell_node_force_);
  grid_.force.assign(grid_.size(), Vec3::Zero());
  mpm::scatterFibreForces(grid_, contact_.fibre, contact_.fibre_force, supports_[1],
                          fibre_weight_gradients_);
  for (int i = 0; i < grid_.size(); ++i)
    grid_.force[i] = grid_.mass[i] > 0.0 ? Vec3(grid_.force[i] / grid_.mass[i]) : Vec3::Zero();
  mpm::projectThroughParticles(grid_, massCarriers(), settings_.kernel_degree, grid_.force,
                               projected_);
  for (int i = 0; i < grid_.size(); ++i) grid_.force[i] = shell_node_force_[i] + projected_[i];
}

std::vector<mpm::MassCarriers> HybridShellDynamics::massCarriers() const {
  return {{&control_.x, &transfer_mass_, &supports_[0]},
          {&contact_.p.x, &contact_.p.mass, &supports_[1]},
          {&solid_.x, &solid_.mass, &supports_[2]}};
}

// The contact particles carry no mass by default, so a node in a contact particle's support may
// carry almost none: one that a control point's kernel barely reaches. The fibre force through
// the contact particle's full weight gradient then gives it dt f / m without bound as m -> 0
// (the twisted tube and the walker's hem diverged within one step, 5e4 m/s at a node of 6e-13
// times the largest mass). The fibres (5.44) therefore move with what the mass-carrying
// particles can hold of the grid velocity, S v = P(v) / m: the grid velocity at the nodes that
// carry mass, averaged by the particles' APIC transfers (affine fields pass unchanged), as MUSL
// remaps particle momentum for small-mass nodes.
void HybridShellDynamics::carriedVelocity(const std::vector<Vec3>& node_velocity,
                                          std::vector<Vec3>& carried) {
  mpm::projectThroughParticles(grid_, massCarriers(), settings_.kernel_degree, node_velocity,
                               projected_);
  carried.resize(grid_.size());
  for (int i = 0; i < grid_.size(); ++i)
    carried[i] = grid_.mass[i] > 0.0 ? Vec3(projected_[i] / grid_.mass[i]) : Vec3::Zero();
}

// Han (3.9) with x* = x_i + dt v_i: control points at x_p + dt sum_i w_ip v_i (5.45) (pins at
// their targets, fixed components at their reference), contact fibres at their trial value
// (5.44) projected onto the Coulomb cone (5.28)-(5.30). The return mapping stays inside the
// solve: lagging it gives a symmetric linearisation but cohesion artifacts (Han section 5.7),
// which is why the solve is Newton-GMRES. Denting (5.5.5) is lagged: it changes the stiffness,
// not the contact.
void HybridShellDynamics::computeTrialGridForces(const std::vector<Vec3>& node_velocity, double dt,
                                                 bool with_elasticity) {
  const int deg = settings_.kernel_degree;
  mpm::interpolateNodeField(grid_, node_velocity, control_.x, deg, supports_[0], &trial_shift_,
                            nullptr);
  trial_control_.resize(numVertices());
  for (int p = 0; p < numVertices(); ++p) {
    if (pins_.isPinned(p)) {
      trial_control_[p] = pins_.target(p);
      continue;
    }
    trial_control_[p] = control_.x[p] + dt * trial_shift_[p];
    for (int a = 0; a < 3; ++a)
      if (free_axes_[p][a] == 0.0) trial_control_[p][a] = reference_[p][a];
  }
  clamps_.placePositions(trial_control_);
  carriedVelocity(node_velocity, fibre_velocity_);
  mpm::interpolateMassSupportedGradient(grid_, fibre_velocity_, supports_[1],
                                        fibre_weight_gradients_, fibre_gradient_);
  trial_fibre_.resize(contact_.size());
  tbb::parallel_for(0, contact_.size(), [&](int p) {
    const Vec3& a = contact_.fibre[p];
    Vec3 a1, a2;
    contact_.stencil.tangents(p, trial_control_, a1, a2);
    trial_fibre_[p] =
        fibreInContact(p)
            ? projectContactFibre(a1, a2, a + dt * fibre_gradient_[p] * a, contact_material_)
            : Vec3(a1.cross(a2).normalized());
  });
  scatterShellForces(trial_control_, trial_fibre_, with_elasticity);
  scatterTrialSolidStress(node_velocity, dt);
}

// Han (3.9) at x* = x_i + dt v_i: f_i = -sum_p V_p^0 P(F*_p) (F^n_p)^T grad w_ip with the trial
// F* = (I + dt grad v_p) F^n (3.17), the weights at the step start. Not tau(F*): the chain rule
// through x* leaves F^n, not F*, beside P. A trial that inverts a particle (det F* <= 0, which a
// long Newton step can propose) has no Hencky stress; its NaN stress makes the residual
// non-finite, and the solver backtracks (solver/newton_krylov.h).
void HybridShellDynamics::scatterTrialSolidStress(const std::vector<Vec3>& node_velocity,
                                                  double dt) {
  if (solid_.size() == 0) return;
  const int deg = settings_.kernel_degree;
  mpm::interpolateNodeField(grid_, node_velocity, solid_.x, deg, supports_[2], nullptr,
                            &solid_gradient_);
  solid_stress_.resize(solid_.size());
  tbb::parallel_for(0, solid_.size(), [&](int p) {
    const Eigen::Matrix3d& Fn = solid_.F[p];
    const Eigen::Matrix3d F = (Eigen::Matrix3d::Identity() + dt * solid_gradient_[p]) * Fn;
    solid_stress_[p] = F.allFinite() && F.determinant() > 0.0
                           ? Eigen::Matrix3d(solid_.volume0[p] *
                                             solid_material_->firstPiolaStress(F) * Fn.transpose())
                           : Eigen::Matrix3d::Constant(std::numeric_limits<double>::quiet_NaN());
  });
  mpm::scatterStressForces(grid_, solid_.x, solid_stress_, deg, &supports_[2]);
}

// Damping, then Han (5.40) with gravity, then the obstacles' boundary conditions (section 3.4).
void HybridShellDynamics::updateGridMomentum(double dt) {
  dampGridMomentum(dt);
  mpm::updateGridVelocity(grid_, gravity_, dt);
  mpm::applyGridColliders(grid_, grid_colliders_, &collider_impulse_);
}

// Viscous damping acts on the incoming momentum m_i v_i^n, taken implicitly so that it never
// reverses a velocity; applied after the forces it would also eat a fraction c dt of each step's
// weight and a held cloth's supports would carry less than its weight.
void HybridShellDynamics::dampGridMomentum(double dt) {
  if (settings_.damping <= 0.0) return;
  const double keep = 1.0 / (1.0 + settings_.damping * dt);
  for (int i = 0; i < grid_.size(); ++i) {
    grid_.velocity[i] *= keep;
    grid_.momentum[i] *= keep;
  }
}

// Backward Euler, Han (3.7)-(3.9) with x* = x^{n+1}: the velocities of the nodes that carry mass
// solve r_i(v) = m_i (v_i - v~_i) - dt f_i(x + dt v) = 0 with v~_i = v_i^n + dt g, by
// Jacobian-free Newton-GMRES preconditioned with the masses. Massless nodes (touched only by
// massless contact particles or pins) stay at rest as in the explicit update. The obstacles'
// conditions follow the solve, as in the explicit step. A solve that stops short of its
// tolerance keeps its last iterate (lastImplicitSolve() says so; the caller's checks decide).
void HybridShellDynamics::solveGridMomentum(double dt, bool contact_only) {
  if (contact_only && contactFree()) {
    // No fibre carries contact (each is its surface normal, whose contact energy and force
    // vanish) and no solid: r(v) = m (v - v~) is zero at the transferred velocities, which the
    // solve would return unchanged after three evaluations of the fibres (two for its warm
    // start). The grid keeps its velocities, the fibres move with the surface (F = I), and the
    // next solve starts cold, as it would from the zero change this one leaves.
    std::fill(control_force_.begin(), control_force_.end(), Vec3::Zero());
    std::fill(contact_.fibre_force.begin(), contact_.fibre_force.end(), Vec3::Zero());
    fibre_gradient_.assign(contact_.size(), Eigen::Matrix3d::Zero());
    last_contact_nodes_.clear();
    last_contact_change_.clear();
    last_solve_ = NewtonKrylovResult();
    last_solve_.status = NewtonKrylovStatus::kConverged;
    mpm::applyGridColliders(grid_, grid_colliders_, &collider_impulse_);
    return;
  }
  if (!contact_only) dampGridMomentum(dt);
  const Vec3 g = contact_only ? Vec3::Zero() : gravity_;
  std::vector<int> node;
  for (int i = 0; i < grid_.size(); ++i)
    if (grid_.mass[i] > 0.0) node.push_back(i);
  const int n = static_cast<int>(node.size());
  Eigen::VectorXd v(3 * n), v_free(3 * n), mass(3 * n);
  double total_mass = 0.0;
  for (int k = 0; k < n; ++k) {
    v_free.segment<3>(3 * k) = grid_.velocity[node[k]] + dt * g;
    mass.segment<3>(3 * k).setConstant(grid_.mass[node[k]]);
    total_mass += grid_.mass[node[k]];
  }
  v = v_free;
  std::vector<Vec3> node_velocity(grid_.size(), Vec3::Zero());
  Eigen::VectorXd evaluated;  // where the trial state was last evaluated
  auto residual = [&](const Eigen::VectorXd& u, Eigen::VectorXd& r) {
    evaluated = u;
    for (int k = 0; k < n; ++k) node_velocity[node[k]] = u.segment<3>(3 * k);
    computeTrialGridForces(node_velocity, dt, !contact_only);
    r.resize(3 * n);
    for (int k = 0; k < n; ++k)
      r.segment<3>(3 * k) =
          mass.segment<3>(3 * k).cwiseProduct(u.segment<3>(3 * k) - v_free.segment<3>(3 * k)) -
          dt * grid_.force[node[k]];
  };
  if (contact_only && !last_contact_change_.empty()) {
    // Warm start: the last solution's change at the nodes active again, less its rigid part
    // (the mass-weighted least-squares a + w x (x - c)). The contact forces are internal, so each
    // Newton-Krylov update from a start of zero momentum keeps both momenta (docs/VALIDATION.md);
    // an old change at nodes that moved would not. Taken only where it lowers the residual:
    // during fast motion the old change can be the wrong one (two evaluations).
    std::vector<Vec3> change(n, Vec3::Zero());
    for (int k = 0; k < n; ++k) {
      const int j = last_contact_nodes_.find(grid_.coordinate(node[k]));
      if (j >= 0) change[k] = last_contact_change_[j];
    }
    const RigidVelocity rigid = fitRigidVelocity(n, [&](int k, double& m, Vec3& x, Vec3& u) {
      m = grid_.mass[node[k]];
      x = grid_.position(node[k]);
      u = change[k];
    });
    Eigen::VectorXd warm = v_free, r_free, r_warm;
    for (int k = 0; k < n; ++k)
      warm.segment<3>(3 * k) += change[k] - rigid.at(grid_.position(node[k]));
    residual(v_free, r_free);
    residual(warm, r_warm);
    const auto norm = [&](const Eigen::VectorXd& r) { return r.cwiseQuotient(mass).dot(r); };
    if (norm(r_warm) < norm(r_free)) v = warm;
  }
  NewtonKrylovSettings ns;
  ns.tolerance = (contact_only ? lagrangianTolerance(dt) : settings_.implicit_tolerance) *
                 std::sqrt(total_mass);
  ns.max_newton_iterations = settings_.max_newton_iterations;
  ns.max_krylov_iterations = settings_.max_krylov_iterations;
  ns.krylov_restart = settings_.max_krylov_iterations;
  ns.krylov_tolerance = settings_.krylov_tolerance;
  last_solve_ = solveNewtonKrylov(residual, mass, v, ns);
  // The trial state (control forces, fibres, their carried velocity and its gradient) must be
  // that of the accepted velocities: the pins' support forces balance those forces, and G2P
  // reuses the fibres' gradient. A solve's last evaluation is usually there already (its line
  // search accepted it); after a rejected trial it is evaluated once more.
  if (evaluated.size() != v.size() || evaluated != v) {
    Eigen::VectorXd r;
    residual(v, r);
  }
  for (int i = 0; i < grid_.size(); ++i) {
    grid_.velocity[i] = node_velocity[i];
    grid_.momentum[i] = grid_.mass[i] * node_velocity[i];
  }
  if (contact_only) {
    last_contact_nodes_.clear();
    last_contact_change_.resize(n);
    for (int k = 0; k < n; ++k)
      last_contact_change_[last_contact_nodes_.activate(grid_.coordinate(node[k]))] =
          v.segment<3>(3 * k) - v_free.segment<3>(3 * k);
  }
  mpm::applyGridColliders(grid_, grid_colliders_, &collider_impulse_);
}

// Han (5.50)-(5.53): velocities and affine velocities from the grid; control points move with
// the grid. F of each shell particle becomes I + dt grad v (5.43)-(5.44), the map of this step;
// the solid's F accumulates, F <- (I + dt grad v) F (3.17).
void HybridShellDynamics::transferToParticles(double dt) {
  // The fibres' map I + dt grad(S v) (carriedVelocity), taken before the transfers move the
  // particles off the positions their supports were recorded at. The Lagrangian step's contact
  // solve left it at its solution (solveGridMomentum).
  if (!lagrangian()) {
    carriedVelocity(grid_.velocity, fibre_velocity_);
    mpm::interpolateMassSupportedGradient(grid_, fibre_velocity_, supports_[1],
                                          fibre_weight_gradients_, fibre_gradient_);
  }
  std::fill(control_.F.begin(), control_.F.end(), Eigen::Matrix3d::Identity());
  if (lagrangian() && settings_.flip_blend > 0.0)
    mpm::interpolateNodeField(grid_, transferred_velocity_, control_.x, settings_.kernel_degree,
                              supports_[0], &transferred_at_particles_, nullptr);
  mpm::gridToParticle(grid_, control_, settings_.kernel_degree, settings_.rpic_damping, dt,
                      &supports_[0]);
  if (lagrangian() && settings_.flip_blend > 0.0) {
    // Han (4.12): the grid's velocity, plus xi times what the transfer averaged away of the
    // elastic velocity (v* + dv_grid = v_grid + (v* - v_transferred)).
    // Where the grid stage changed a node of a point's support (contact between layers, with an
    // obstacle or another body), the point takes the grid's velocity alone (PIC): the node's
    // velocity is what resolves that contact, and the elastic motion's detail handed back on
    // top would carry the point on into it (with the blend everywhere, the twisted tube crossed
    // itself from 0.08 s instead of 0.88 turns). Elsewhere the blend keeps that sub-cell detail,
    // which PIC would average away as damping. There the grid's velocity is the transferred one,
    // so v = (1 - xi) v_grid + xi v*, and C is the grid's: where xi = 1 the control points carry
    // the motion themselves and C is only the next transfer's affine fit of it (kept from before
    // instead, C conserves APIC's angular momentum but goes stale: the cloth dropped on the
    // sphere then stretched by 3.9-4.4 % instead of 3.0-3.2 %).
    // "Changed": by more than round-off (1e-8 m/s; a lone layer's nodes differ by ~1e-20).
    const int k = supports_[0].per_particle;
    pic_nodes_.resize(grid_.size());
    tbb::parallel_for(0, grid_.size(), [&](int i) {
      pic_nodes_[i] = (grid_.velocity[i] - transferred_velocity_[i]).squaredNorm() > 1e-16;
    });
    for (int p = 0; p < numVertices(); ++p) {
      double xi = settings_.flip_blend;
      for (const int* i = supports_[0].of(p); i != supports_[0].of(p) + k; ++i)
        if (pic_nodes_[*i]) {
          xi = 0.0;
          break;
        }
      const Vec3 x_start = control_.x[p] - dt * control_.v[p];
      control_.v[p] += xi * (lagrangian_velocity_[p] - transferred_at_particles_[p]);
      control_.x[p] = x_start + dt * control_.v[p];
    }
  }
  // Massless contact particles need no velocity: (5.54) places them and the fibres take S v.
  if (settings_.contact_mass_fraction > 0.0)
    mpm::gridToParticle(grid_, contact_.p, settings_.kernel_degree, settings_.rpic_damping, dt,
                        &supports_[1]);
  mpm::gridToParticle(grid_, solid_, settings_.kernel_degree, settings_.rpic_damping, dt,
                      &supports_[2]);
  tbb::parallel_for(0, contact_.size(), [&](int p) {
    contact_.p.F[p] = Eigen::Matrix3d::Identity() + dt * fibre_gradient_[p];
  });
}

// Pins, obstacles for the control points, (5.54) for the contact particles and the trial
// fibres (5.44).
void HybridShellDynamics::updatePositionsAndTrialState(double dt) {
  const bool surface_collisions = surface_collisions_ && !grid_colliders_.empty();
  // The colliders within two control spacings of a block of 4^3 cells, for the control points'
  // collisions and clearances below: each point asks those alone (on the demo's mannequin every
  // point asked all 18, a tenth of the explicit step).
  const mpm::ColliderCandidates near(grid_colliders_, 0.0, 2.0 * std::max(control_spacing_, dx_),
                                     4.0 * dx_);
  if (surface_collisions) {
    surface_start_.resize(numVertices());
    for (int p = 0; p < numVertices(); ++p) surface_start_[p] = control_.x[p] - dt * control_.v[p];
  }
  for (int p = 0; p < numVertices(); ++p) {
    if (pins_.isPinned(p)) {
      // Back to the pin's motion (G2P gave it the grid's velocity); the support supplies
      // m a - f - m g with f the shell's force on the point at the start of the step.
      const Vec3 x_start = control_.x[p] - dt * control_.v[p];
      control_.v[p] = (pins_.target(p) - x_start) / dt;
      control_.x[p] = pins_.target(p);
      pin_force_[p] =
          control_.mass[p] * ((control_.v[p] - step_start_velocity_[p]) / dt - gravity_) -
          control_force_[p] - (lagrangian() ? elastic_force_[p] : Vec3::Zero());
      continue;
    }
    pin_force_[p].setZero();
    if (clamps_.isSlaved(p)) continue;  // placed below, from their interior neighbours
    for (int a = 0; a < 3; ++a)
      if (free_axes_[p][a] == 0.0) {  // held on axis a: v_a and its affine part C_a. vanish
        control_.x[p][a] = reference_[p][a];
        control_.v[p][a] = 0.0;
        control_.C[p].row(a).setZero();
      }
    // The grid conditions act on nodes inside an obstacle only: a control point on the surface
    // also draws on the free nodes above it, so it ends the step slightly inside and slid by
    // the part of gravity those nodes did not resist. Resolve its contact as a collision
    // impulse: the same Coulomb projection as the nodes get (grid_collider.h) on its relative
    // velocity, the step redone with that velocity, then any remaining depth removed. (Removing
    // at most a tenth of a cell per step instead let a sheet falling onto the moving mannequin
    // sink deeper and diverge 13 times as often.) Its
    // APIC affine velocity goes too: it holds the free nodes' slide and would hand it back to
    // the grid at the next transfer, so a patch below the friction onset would creep.
    const Vec3 x_start = control_.x[p] - dt * control_.v[p];
    const std::vector<int>* listed = &near.near(control_.x[p]);
    for (std::size_t c = 0; c < surfaces_.size(); ++c) {
      if (!std::binary_search(listed->begin(), listed->end(), static_cast<int>(c))) continue;
      const SurfaceProjection pr = surfaces_[c]->project(control_.x[p]);
      if (pr.gap >= 0.0) continue;
      const mpm::GridCollider& gc = grid_colliders_[c];
      const Vec3 vc = gc.velocity.at(control_.x[p]);
      const Vec3 v_rel = control_.v[p] - vc;
      if (v_rel.dot(pr.normal) < 0.0) {
        const Vec3 before = control_.v[p];
        control_.v[p] =
            vc + mpm::collideRelativeVelocity(v_rel, pr.normal, gc.boundary, gc.friction);
        collider_impulse_[c].add(control_.x[p], control_.mass[p] * (control_.v[p] - before));
        control_.C[p].setZero();
        control_.x[p] = x_start + dt * control_.v[p];
      }
      const double gap = surfaces_[c]->project(control_.x[p]).gap;
      if (gap < 0.0) control_.x[p] -= gap * pr.normal;
      listed = &near.near(control_.x[p]);  // it moved: the colliders near it now
    }
  }
  placeClamped(dt);
  if (surface_collisions) {
    // The limit surface out of the colliders too (mpm/surface_collisions.h), by moving the
    // points whose motion is free; clamped points then follow their interior neighbours again.
    movable_.resize(numVertices());
    clearance_.resize(numVertices());
    tbb::parallel_for(0, numVertices(), [&](int p) {
      movable_[p] = !pins_.isPinned(p) && !clamps_.isSlaved(p) && free_axes_[p] == Vec3::Ones();
      clearance_[p] = mpm::clearanceOf(control_.x[p], grid_colliders_, &near.near(control_.x[p]),
                                       near.beyond());
    });
    const mpm::SurfaceCollisionResult pushed =
        surface_collisions_->apply(control_.x, control_.v, surface_start_, control_.mass, movable_,
                                   clearance_, grid_colliders_, dt, collider_impulse_);
    for (int p = 0; p < numVertices(); ++p)
      if (surface_collisions_->moved(p)) control_.C[p].setZero();
    if (pushed.iterations > 0) placeClamped(dt);
  }
  tbb::parallel_for(0, contact_.size(), [&](int p) {
    contact_.p.x[p] = contact_.stencil.position(p, control_.x);  // (5.54)
    contact_.fibre[p] = contact_.p.F[p] * contact_.fibre[p];     // (5.44)
  });
}

// Clamped points and ghosts follow their interior neighbours; the clamp's force on each clamped
// point comes from their residuals m a - f - m g (ClampedEdges::reaction).
void HybridShellDynamics::placeClamped(double dt) {
  clamps_.placePositions(control_.x);
  clamps_.placeVelocities(control_.v);
  const auto residual = [&](int p) {
    return Vec3(control_.mass[p] * ((control_.v[p] - step_start_velocity_[p]) / dt - gravity_) -
                control_force_[p] - (lagrangian() ? elastic_force_[p] : Vec3::Zero()));
  };
  for (const ClampedEdges::Clamp& c : clamps_.clamps()) {
    const Vec3& rb = clamp_residual_[c.boundary] = residual(c.boundary);
    const Vec3& rg = clamp_residual_[c.ghost] = residual(c.ghost);
    pin_force_[c.boundary] = clamps_.reaction(c, rb, rg);
    // A pinned N supplies its own residual less the clamp's share -(J_B^T r_B + J_G^T r_G),
    // which the clamp's force already counts.
    if (pins_.isPinned(c.interior)) pin_force_[c.interior] += clamps_.foldedForce(c, rb, rg);
  }
}

// Section 5.5.5: denting return mapping at the quadrature points, Coulomb return mapping
// (5.29)-(5.30) of the fibres.
void HybridShellDynamics::updatePlasticity() {
  updateKirchhoffLovePlasticity(kl_points_, lamina_, control_.x);
  tbb::parallel_for(0, contact_.size(), [&](int p) {
    Vec3 a1, a2;
    contact_.stencil.tangents(p, control_.x, a1, a2);
    contact_.fibre[p] = fibreInContact(p)
                            ? projectContactFibre(a1, a2, contact_.fibre[p], contact_material_)
                            : Vec3(a1.cross(a2).normalized());
  });
}

double HybridShellDynamics::cflTimeStep(double longest) const {
  return mpm::motionTimeStep({motion()}, grid_colliders_, (settings_.kernel_degree + 1) * dx_,
                             settings_.cfl * dx_, longest);
}

mpm::MotionGroup HybridShellDynamics::motion() const {
  // The control points carry the shell's contact particles (and the solid its own); the shell
  // meets itself on its field (layers, the fibres' contact), so its own approach counts.
  mpm::MotionGroup g;
  g.self = true;
  for (const auto* set : {&control_, &solid_}) {
    g.x.insert(g.x.end(), set->x.begin(), set->x.end());
    g.v.insert(g.v.end(), set->v.begin(), set->v.end());
  }
  // Where the fibres act between layers only, two control points of one layer meet through the
  // shell's elasticity alone: only their closing in needs a short step (the solid's particles
  // count as before).
  if (layers_ && settings_.cfl_between_layers_only)
    g.one_layer = [this](int p, int q, double distance) {
      const int nc = control_.size();
      return p < nc && q < nc &&
             layers_->facesOnOneLayer(control_face_[p], control_face_[q], distance);
    };
  return g;
}

bool HybridShellDynamics::contactFree() const {
  return solid_.size() == 0 && !near_layer_.empty() &&
         std::none_of(near_layer_.begin(), near_layer_.end(), [](char near) { return near; });
}

double HybridShellDynamics::lagrangianTolerance(double dt) const {
  return std::max(settings_.lagrangian_tolerance,
                  settings_.lagrangian_gravity_fraction * gravity_.norm() * dt);
}

double HybridShellDynamics::explicitTimeStep() const {
  const double h = std::min(control_spacing_, dx_);
  const double membrane = young_ * thickness_ / (1.0 - poisson_ * poisson_);
  const double bending = membrane * thickness_ * thickness_ / 12.0;
  // Fastest membrane wave over a control spacing, fastest flexural wave at wavenumber pi / h,
  // and the fibre contact stiffness over a cell.
  const double dt_membrane = h / std::sqrt(membrane / areal_density_);
  const double dt_bending = 2.0 * h * h / (M_PI * M_PI * std::sqrt(bending / areal_density_));
  const double k = std::max(contact_material_.normal_stiffness, contact_material_.shear_stiffness);
  const double dt_contact = dx_ / std::sqrt(k * thickness_ / areal_density_);
  // The solid's fastest (dilatational) wave over a cell, as for a plain MPM continuum.
  const double dt_solid =
      solid_.size() > 0 ? dx_ / solid_wave_speed_ : std::numeric_limits<double>::infinity();
  return cflTimeStep(settings_.safety * std::min({dt_membrane, dt_bending, dt_contact, dt_solid}));
}

double HybridShellDynamics::stableTimeStep() const {
  if (settings_.integration != TimeIntegration::kSymplecticEuler)
    return cflTimeStep(settings_.max_time_step);
  return explicitTimeStep();
}

void HybridShellDynamics::setPositions(const std::vector<Vec3>& x) {
  if (static_cast<int>(x.size()) != numVertices())
    throw InputError("hybrid shell: " + std::to_string(x.size()) + " positions for " +
                     std::to_string(numVertices()) + " control points");
  control_.x = x;
  clamps_.placePositions(control_.x);
  std::fill(bdf2_.valid.begin(), bdf2_.valid.end(), 0);
  // A placed surface starts out of contact: its fibres are reset to the new normals (kept,
  // a fibre of the old orientation would read a turned garment as sheared through itself).
  for (int p = 0; p < contact_.size(); ++p) {
    Vec3 a1, a2;
    contact_.stencil.tangents(p, control_.x, a1, a2);
    contact_.p.x[p] = contact_.stencil.position(p, control_.x);
    contact_.fibre[p] = a1.cross(a2).normalized();
  }
}

void HybridShellDynamics::setVelocities(const std::vector<Vec3>& v) {
  if (static_cast<int>(v.size()) != numVertices())
    throw InputError("hybrid shell: " + std::to_string(v.size()) + " velocities for " +
                     std::to_string(numVertices()) + " control points");
  control_.v = v;
  clamps_.placeVelocities(control_.v);
  for (auto& C : control_.C) C.setZero();
  std::fill(bdf2_.valid.begin(), bdf2_.valid.end(), 0);  // a new start: backward Euler first
  // Contact particles take the surface's velocity; their affine part restarts at zero.
  for (int p = 0; p < contact_.size(); ++p) {
    contact_.p.v[p] = contact_.stencil.position(p, control_.v);
    contact_.p.C[p].setZero();
  }
}

void HybridShellDynamics::fieldNormals(std::vector<Vec3>& normals) const {
  normals.assign(grid_.size(), Vec3::Zero());
  std::vector<Vec3> n(contact_.size());
  for (int p = 0; p < contact_.size(); ++p) {
    Vec3 a1, a2;
    contact_.stencil.tangents(p, control_.x, a1, a2);
    n[p] = a1.cross(a2).normalized();
  }
  mpm::sumOverSupports(grid_, contact_.p.x, n, supports_[1], settings_.kernel_degree, normals);
}

bool HybridShellDynamics::finite() const {
  for (const auto* set : {&control_, &solid_})
    for (int p = 0; p < set->size(); ++p)
      if (!set->x[p].allFinite() || !set->v[p].allFinite()) return false;
  return true;
}

double HybridShellDynamics::kineticEnergy() const {
  double e = 0.0;
  for (const auto* set : {&control_, &contact_.p, &solid_})
    for (int p = 0; p < set->size(); ++p) e += 0.5 * set->mass[p] * set->v[p].squaredNorm();
  return e;
}

void HybridShellDynamics::setGravity(const Vec3& gravity) {
  if (!gravity.allFinite()) throw InputError("hybrid shell: gravity must be finite");
  gravity_ = gravity;
}

void HybridShellDynamics::setDamping(double damping) {
  if (!(damping >= 0.0 && std::isfinite(damping)))
    throw InputError("hybrid shell: damping must be >= 0 and finite");
  settings_.damping = damping;
}

void HybridShellDynamics::setColliders(const RigidSurfaces& colliders,
                                       const std::vector<SurfaceVelocity>& velocities,
                                       const std::vector<double>& frictions) {
  std::vector<mpm::GridCollider> grid_colliders = mpm::makeGridColliders(
      colliders, velocities, frictions, settings_.boundary, settings_.friction, "hybrid shell");
  surfaces_ = colliders;
  grid_colliders_ = std::move(grid_colliders);
}

// A clamp's points move with their interior neighbour N for the garment's life: a pin on one
// would fight the slaving. (N itself may be pinned; the clamp then follows the pin.)
void HybridShellDynamics::checkNotClamped(int vertex) const {
  pins_.check(vertex);
  if (clamps_.isSlaved(vertex))
    throw InputError("hybrid shell: control point " + std::to_string(vertex) +
                     (vertex < clamps_.numMeshVertices() ? " is clamped" : " is a clamp's ghost") +
                     " (bc.clamped): it cannot be pinned, unpinned or fixed");
}

void HybridShellDynamics::pin(int vertex) {
  checkNotClamped(vertex);
  pins_.pinInPlace(vertex, control_.x);
}

void HybridShellDynamics::pin(int vertex, const Vec3& target) {
  checkNotClamped(vertex);
  pins_.pin(vertex, target);
}

void HybridShellDynamics::unpin(int vertex) {
  checkNotClamped(vertex);
  pins_.unpin(vertex);
  pin_force_[vertex].setZero();
}

std::vector<Vec3> HybridShellDynamics::holdingForces(const std::vector<int>& vertices,
                                                     const std::vector<Vec3>& accelerations) const {
  pins_.checkHoldingRequest(vertices, accelerations);
  std::vector<Vec3> r;
  for (int v : vertices) r.push_back(pin_force_[v]);
  return r;
}

// The clamp's constraint forces act on B, G and (through the slaving) N: r_B, r_G and
// -(J_B^T r_B + J_G^T r_G). Their moment at the control points is the one a rigid rotation of
// the cloth would work against, since the limit surface is an affine combination of them.
HoldingWrench HybridShellDynamics::clampWrench(const Vec3& origin) const {
  HoldingWrench w;
  for (const ClampedEdges::Clamp& c : clamps_.clamps()) {
    const Vec3& rb = clamp_residual_[c.boundary];
    const Vec3& rg = clamp_residual_[c.ghost];
    const std::pair<int, Vec3> forces[] = {
        {c.boundary, rb}, {c.ghost, rg}, {c.interior, -clamps_.foldedForce(c, rb, rg)}};
    for (const auto& [p, f] : forces) {
      w.force += f;
      w.torque += (control_.x[p] - origin).cross(f);
    }
  }
  return w;
}

std::unique_ptr<DynamicsSnapshot> HybridShellDynamics::snapshot() const {
  auto s = std::make_unique<HybridSnapshot>();
  s->control = control_;
  s->contact = contact_.p;
  s->fibre = contact_.fibre;
  for (const auto& q : kl_points_) s->plastic.push_back(q.plasticDeformation());
  s->pin_force = pin_force_;
  s->clamp_residual = clamp_residual_;
  s->solid = solid_;
  s->solid_material = solid_material_;
  s->solid_wave_speed = solid_wave_speed_;
  s->time = time_;
  s->bdf2_x = bdf2_.x;
  s->bdf2_v = bdf2_.v;
  s->bdf2_valid = bdf2_.valid;
  s->bdf2_dt = bdf2_.dt;
  return s;
}

void HybridShellDynamics::restore(const DynamicsSnapshot& snapshot) {
  const auto& s = dynamic_cast<const HybridSnapshot&>(snapshot);
  // The elastic solve's factor and L-BFGS pairs may come from a rolled-back step.
  if (elasticity_) elasticity_->invalidate();
  control_ = s.control;
  contact_.p = s.contact;
  contact_.fibre = s.fibre;
  for (std::size_t q = 0; q < kl_points_.size(); ++q)
    kl_points_[q].setPlasticDeformation(s.plastic[q]);
  pin_force_ = s.pin_force;
  clamp_residual_ = s.clamp_residual;
  solid_ = s.solid;
  solid_material_ = s.solid_material;
  solid_wave_speed_ = s.solid_wave_speed;
  time_ = s.time;
  bdf2_.x = s.bdf2_x;
  bdf2_.v = s.bdf2_v;
  bdf2_.valid = s.bdf2_valid;
  bdf2_.dt = s.bdf2_dt;
}

void HybridShellDynamics::writeState(StateWriter& out) const {
  out.text("hybrid shell");
  writeParticles(out, control_, false);
  writeParticles(out, contact_.p, false);
  out.vectors(contact_.fibre);
  std::vector<Eigen::Matrix3d> plastic;
  for (const auto& q : kl_points_) plastic.push_back(q.plasticDeformation());
  out.matrices(plastic);
  out.vectors(pin_force_);
  out.vectors(clamp_residual_);
  out.vectors(step_start_velocity_);
  out.u64(solid_.size());
  if (solid_.size() > 0) {
    out.real(solid_material_->youngsModulus());
    out.real(solid_material_->poissonRatio());
    out.real(solid_wave_speed_);
    writeParticles(out, solid_, true);
  }
  pins_.write(out);
  out.real(time_);
}

void HybridShellDynamics::dropSolverCaches() {
  if (elasticity_) elasticity_->invalidate();
  last_contact_nodes_.clear();
  last_contact_change_.clear();
}

void HybridShellDynamics::readState(StateReader& in) {
  in.expectText("hybrid shell", "dynamics backend");
  const std::size_t nc = control_.x.size(), np = contact_.p.x.size();
  const mpm::Particles control = readParticles(in, control_, nc, false, "control point");
  const mpm::Particles contact = readParticles(in, contact_.p, np, false, "contact particle");
  std::vector<Vec3> fibre = in.vectors("contact fibres", np);
  const std::vector<Eigen::Matrix3d> plastic =
      in.matrices("Kirchhoff-Love plastic deformations", kl_points_.size());
  std::vector<Vec3> pin_force = in.vectors("pin forces", nc);
  std::vector<Vec3> clamp_residual = in.vectors("clamp residuals", nc);
  std::vector<Vec3> step_start_velocity = in.vectors("step start velocities", nc);
  const std::uint64_t solid_count = in.u64("solid particle count");
  mpm::Particles solid;
  std::optional<mpm::HenckySolid> solid_material;
  double solid_wave_speed = 0.0;
  if (solid_count > 0) {
    const double young = in.real("solid Young's modulus");
    const double poisson = in.real("solid Poisson ratio");
    solid_material.emplace(young, poisson);
    solid_wave_speed = in.real("solid wave speed");
    solid = readParticles(in, solid, solid_count, true, "solid particle");
  }
  PinSet pins = pins_;
  pins.read(in);
  const double time = in.real("hybrid shell time");
  control_ = control;
  contact_.p = contact;
  contact_.fibre = std::move(fibre);
  for (std::size_t q = 0; q < kl_points_.size(); ++q)
    kl_points_[q].setPlasticDeformation(plastic[q]);
  pin_force_ = std::move(pin_force);
  clamp_residual_ = std::move(clamp_residual);
  step_start_velocity_ = std::move(step_start_velocity);
  solid_ = std::move(solid);
  solid_material_ = std::move(solid_material);
  solid_wave_speed_ = solid_wave_speed;
  pins_ = std::move(pins);
  time_ = time;
  // State files hold one time level: the first step after a load is backward Euler.
  std::fill(bdf2_.valid.begin(), bdf2_.valid.end(), 0);
}

void HybridShellDynamics::addSolid(mpm::Particles particles, const mpm::HenckySolid& material) {
  if (solid_.size() > 0)
    throw InputError("hybrid shell: it already carries a solid (one solid per shell)");
  // The Lagrangian step gives the grid no gravity (the shell's elastic stage took it) and no
  // stress but contact: a solid's particles would float.
  if (lagrangian())
    throw InputError(
        "hybrid shell: the Lagrangian implicit integration carries no solid; use "
        "symplectic_euler or backward_euler");
  const std::size_t n = particles.x.size();
  if (n == 0) throw InputError("hybrid shell: the solid has no particles");
  if (particles.v.size() != n || particles.C.size() != n || particles.F.size() != n ||
      particles.mass.size() != n || particles.volume0.size() != n)
    throw InputError("hybrid shell: solid particle arrays of different lengths (" +
                     std::to_string(n) + " positions, " + std::to_string(particles.v.size()) +
                     " velocities, " + std::to_string(particles.C.size()) + " C, " +
                     std::to_string(particles.F.size()) + " F, " +
                     std::to_string(particles.mass.size()) + " masses, " +
                     std::to_string(particles.volume0.size()) + " volumes)");
  double wave_speed = 0.0;
  for (int p = 0; p < particles.size(); ++p) {
    const std::string which = "hybrid shell: solid particle " + std::to_string(p);
    const double m = particles.mass[p], V = particles.volume0[p];
    if (!(m > 0.0 && std::isfinite(m)))
      throw InputError(which + " has mass " + std::to_string(m) + " (must be positive, finite)");
    if (!(V > 0.0 && std::isfinite(V)))
      throw InputError(which + " has volume " + std::to_string(V) + " (must be positive, finite)");
    if (!particles.x[p].allFinite() || !particles.v[p].allFinite() || !particles.C[p].allFinite() ||
        !particles.F[p].allFinite())
      throw InputError(which + " has a non-finite position, velocity, C or F");
    if (!(particles.F[p].determinant() > 0.0)) throw InputError(which + " starts with det F <= 0");
    wave_speed = std::max(wave_speed, material.dilatationalWaveSpeed(m / V));
  }
  solid_ = std::move(particles);
  solid_material_ = material;
  solid_wave_speed_ = wave_speed;
}

std::vector<Vec3> HybridShellDynamics::surfacePoints() const {
  return evaluate(display_stencils_, control_.x);
}

DisplaySurface HybridShellDynamics::displaySurface() const {
  return {surfacePoints(), display_triangles_};
}

double HybridShellDynamics::totalMass() const {
  double m = 0.0;
  for (const auto* set : {&control_, &contact_.p, &solid_})
    for (double mp : set->mass) m += mp;
  return m;
}

Vec3 HybridShellDynamics::linearMomentum() const {
  Vec3 P = Vec3::Zero();
  for (const auto* set : {&control_, &contact_.p, &solid_})
    for (int p = 0; p < set->size(); ++p) P += set->mass[p] * set->v[p];
  return P;
}

Vec3 HybridShellDynamics::angularMomentum() const {
  // APIC carries angular momentum in C as well: m D eps : C^T with D = dx^2 (d + 1) / 12 I the
  // kernel's inertia (Jiang et al. 2015).
  const double D =
      1.0 / (settings_.kernel_degree == 2 ? mpm::ParticleStencil<2>::inverseInertia(dx_)
                                          : mpm::ParticleStencil<3>::inverseInertia(dx_));
  Vec3 L = Vec3::Zero();
  for (const auto* set : {&control_, &contact_.p, &solid_})
    for (int p = 0; p < set->size(); ++p) {
      const Eigen::Matrix3d& C = set->C[p];
      L += set->mass[p] * (set->x[p].cross(set->v[p]) +
                           D * Vec3(C(2, 1) - C(1, 2), C(0, 2) - C(2, 0), C(1, 0) - C(0, 1)));
    }
  return L;
}

double HybridShellDynamics::elasticEnergy() const {
  return kirchhoffLoveEnergy(kl_points_, lamina_, control_.x);
}

// Each point asks only the colliders that may contain it (ColliderCandidates with reach 0, blocks
// of 4^3 cells): the node's status asked every collider for every displayed point, under the
// world's lock (2000 points and 18 colliders on the demo's mannequin).
double HybridShellDynamics::deepestPenetration() const {
  const mpm::ColliderCandidates inside(grid_colliders_, 0.0, 0.0, 4.0 * dx_);
  return chs::deepestPenetration(
             surfacePoints(), surfaces_,
             [&inside](const Vec3& x) -> const std::vector<int>& { return inside.near(x); })
      .depth;
}

}  // namespace chs
