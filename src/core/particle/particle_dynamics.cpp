#include "cloth_hair_sim/core/particle/particle_dynamics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/particle/particle_contact.h"

namespace chs {

namespace {
using Vec3 = Eigen::Vector3d;

const DrapeProblem& validated(const DrapeProblem& problem, const ParticleDynamicsSettings& s) {
  problem.validate();
  if (!(problem.material.areal_density > 0.0))
    throw InputError("particle dynamics: the areal density must be positive (nodes need mass)");
  if (!std::isfinite(s.damping) || s.damping < 0.0)
    throw InputError("particle dynamics: damping must be >= 0");
  if (!(s.restitution >= 0.0 && s.restitution <= 1.0))
    throw InputError("particle dynamics: restitution must lie in [0, 1]");
  if (!(s.friction >= 0.0) || !std::isfinite(s.friction))
    throw InputError("particle dynamics: friction coefficient must be finite and >= 0");
  if (!std::isfinite(s.contact_tolerance) || s.contact_tolerance < 0.0)
    throw InputError("particle dynamics: contact tolerance must be >= 0");
  return problem;
}
}  // namespace

ParticleDynamics::ParticleDynamics(const DrapeProblem& problem,
                                   const ParticleDynamicsSettings& settings)
    : settings_(settings),
      network_(validated(problem, settings).mesh, problem.material, problem.bc.clamped,
               settings.network),
      loads_(problem, network_),
      surfaces_(problem.colliders),
      pins_({"particle dynamics", "vertex", "vertices"}, problem.mesh.vertices),
      quads_(problem.mesh.quads),
      x_(problem.mesh.vertices) {
  const int n = numVertices();
  contact_tolerance_ = settings.contact_tolerance > 0.0 ? settings.contact_tolerance
                                                        : 1e-6 * network_.referenceEdgeLength();
  v_.assign(n, Vec3::Zero());
  mask_.assign(n, Vec3::Ones());
  for (const auto& f : problem.bc.fixed_components) mask_[f.vertex][f.axis] = 0.0;
  for (int v : problem.bc.clamped) pins_.pinInPlace(v, x_);
  for (int v : problem.bc.pinned) pins_.pinInPlace(v, x_);
}

void ParticleDynamics::setColliders(const RigidSurfaces& colliders,
                                    const std::vector<SurfaceVelocity>& velocities,
                                    const std::vector<double>& frictions) {
  for (const auto& c : colliders)
    if (!c) throw InputError("particle dynamics: null collider");
  if (!velocities.empty() && velocities.size() != colliders.size())
    throw InputError("particle dynamics: " + std::to_string(velocities.size()) +
                     " collider velocities for " + std::to_string(colliders.size()) + " colliders");
  for (const auto& u : velocities)
    if (!u.linear.allFinite() || !u.angular.allFinite() || !u.origin.allFinite())
      throw InputError("particle dynamics: collider velocity is not finite");
  if (!frictions.empty() && frictions.size() != colliders.size())
    throw InputError("particle dynamics: " + std::to_string(frictions.size()) +
                     " friction coefficients for " + std::to_string(colliders.size()) +
                     " colliders");
  for (double mu : frictions)
    if (!(mu >= 0.0) || !std::isfinite(mu))
      throw InputError("particle dynamics: friction coefficient must be finite and >= 0");
  surfaces_ = colliders;
  surface_velocities_ = velocities;
  surface_friction_ = frictions;
}

void ParticleDynamics::setPositions(const std::vector<Vec3>& x) {
  if (x.size() != x_.size()) throw InputError("particle dynamics: position count mismatch");
  x_ = x;
}

void ParticleDynamics::setVelocities(const std::vector<Vec3>& v) {
  if (v.size() != v_.size()) throw InputError("particle dynamics: velocity count mismatch");
  v_ = v;
}

void ParticleDynamics::pin(int vertex) {
  pins_.pinInPlace(vertex, x_);
}

void ParticleDynamics::pin(int vertex, const Vec3& target) {
  pins_.pin(vertex, target);
}

void ParticleDynamics::unpin(int vertex) {
  pins_.unpin(vertex);
}

void ParticleDynamics::acceleration(const std::vector<Vec3>& x, const std::vector<Vec3>& v,
                                    std::vector<Vec3>& a, std::vector<ContactReaction>* reactions,
                                    std::vector<double>* pushed) const {
  std::fill(a.begin(), a.end(), Vec3::Zero());
  if (pushed) pushed->assign(a.size(), 0.0);
  network_.addForces(x, a);
  loads_.addForces(x, 1.0, 1.0, a);
  const auto& m = loads_.masses();
  for (int i = 0; i < numVertices(); ++i) {
    a[i] -= settings_.damping * m[i] * v[i];
    Vec3 normal;
    const int s = touchingSurface(surfaces_, x[i], contact_tolerance_, &normal);
    if (s >= 0) {
      const Vec3 r = cancelInwardComponent(normal, a[i]);
      if (reactions && r.squaredNorm() > 0.0) reactions->push_back({i, s, r});
      if (pushed && !pins_.isPinned(i)) (*pushed)[i] = r.norm() / m[i];
    }
    a[i] = pins_.isPinned(i) ? Vec3::Zero() : Vec3(a[i].cwiseProduct(mask_[i]) / m[i]);
  }
}

void ParticleDynamics::step(double dt) {
  if (!(dt > 0.0) || !std::isfinite(dt))
    throw InputError("particle dynamics: time step must be positive");
  const int n = numVertices();
  // A pinned vertex travels to its target at constant velocity during the step.
  std::vector<Vec3> pin_velocity(n, Vec3::Zero());
  pins_.forEachPinned([&](int i) { pin_velocity[i] = (pins_.target(i) - x_[i]) / dt; });
  auto velocity = [&](const std::vector<Vec3>& v, int i) {
    return pins_.isPinned(i) ? pin_velocity[i] : Vec3(v[i].cwiseProduct(mask_[i]));
  };

  // Classical RK4 on (x, v), seed 000 eq. (50).
  std::vector<Vec3> xs(n), vs(n), a1(n), a2(n), a3(n), a4(n), v1(n), v2(n), v3(n), v4(n);
  std::vector<double> p1, p2, p3, p4;  // normal acceleration the obstacles cancel, per stage
  for (int i = 0; i < n; ++i) v1[i] = velocity(v_, i);
  acceleration(x_, v1, a1, nullptr, &p1);
  for (int i = 0; i < n; ++i) {
    xs[i] = x_[i] + 0.5 * dt * v1[i];
    vs[i] = v_[i] + 0.5 * dt * a1[i];
    v2[i] = velocity(vs, i);
  }
  acceleration(xs, v2, a2, nullptr, &p2);
  for (int i = 0; i < n; ++i) {
    xs[i] = x_[i] + 0.5 * dt * v2[i];
    vs[i] = v_[i] + 0.5 * dt * a2[i];
    v3[i] = velocity(vs, i);
  }
  acceleration(xs, v3, a3, nullptr, &p3);
  for (int i = 0; i < n; ++i) {
    xs[i] = x_[i] + dt * v3[i];
    vs[i] = v_[i] + dt * a3[i];
    v4[i] = velocity(vs, i);
  }
  acceleration(xs, v4, a4, nullptr, &p4);
  for (int i = 0; i < n; ++i) {
    x_[i] += dt / 6.0 * (v1[i] + 2.0 * v2[i] + 2.0 * v3[i] + v4[i]);
    v_[i] += dt / 6.0 * (a1[i] + 2.0 * a2[i] + 2.0 * a3[i] + a4[i]);
    if (pins_.isPinned(i)) {
      x_[i] = pins_.target(i);
      v_[i] = pin_velocity[i];
      continue;
    }
    v_[i] = v_[i].cwiseProduct(mask_[i]);
    // Impact: back onto the surface, inward normal velocity relative to the surface reversed by
    // the restitution.
    // Normal velocity the obstacles took away during the step: the cancelled pushes, then the
    // impact.
    double removed = dt / 6.0 * (p1[i] + 2.0 * p2[i] + 2.0 * p3[i] + p4[i]);
    const bool moved = projectOutOfSurfaces(surfaces_, x_[i]);
    Vec3 normal;
    const int s = touchingSurface(surfaces_, x_[i], contact_tolerance_, &normal);
    if (s < 0) continue;
    const Vec3 u = surface_velocities_.empty() ? Vec3::Zero() : surface_velocities_[s].at(x_[i]);
    const double vn = (v_[i] - u).dot(normal);
    if (moved && vn < 0.0) {
      v_[i] -= (1.0 + settings_.restitution) * vn * normal;
      removed -= (1.0 + settings_.restitution) * vn;
    }
    // Coulomb friction at the velocity level: the tangential slip relative to the obstacle
    // loses mu times the removed normal velocity, or stops. The position takes half the change
    // (the correction is spread over the step), so sticking nodes do not creep.
    const double mu = surface_friction_.empty() ? settings_.friction : surface_friction_[s];
    if (mu > 0.0 && removed > 0.0) {
      const Vec3 rel = v_[i] - u;
      const Vec3 slip = rel - rel.dot(normal) * normal;
      const double speed = slip.norm();
      const Vec3 dv =
          speed > 0.0 ? Vec3(-std::min(mu * removed, speed) / speed * slip) : Vec3::Zero();
      v_[i] += dv.cwiseProduct(mask_[i]);
      x_[i] += 0.5 * dt * dv.cwiseProduct(mask_[i]);
    }
  }
  time_ += dt;
}

double ParticleDynamics::kineticEnergy() const {
  double e = 0.0;
  for (int i = 0; i < numVertices(); ++i) e += 0.5 * masses()[i] * v_[i].squaredNorm();
  return e;
}

void ParticleDynamics::setGravity(const Vec3& gravity) {
  if (!gravity.allFinite()) throw InputError("particle dynamics: gravity must be finite");
  loads_.setGravity(gravity);
}

void ParticleDynamics::setDamping(double damping) {
  if (!std::isfinite(damping) || damping < 0.0)
    throw InputError("particle dynamics: damping must be >= 0");
  settings_.damping = damping;
}

Vec3 ParticleDynamics::centreOfMass() const {
  Vec3 c = Vec3::Zero();
  double m = 0.0;
  for (int i = 0; i < numVertices(); ++i) {
    c += masses()[i] * x_[i];
    m += masses()[i];
  }
  return c / m;
}

double ParticleDynamics::stableTimeStep() const {
  const auto bound = network_.stiffnessBound();
  double w2 = 0.0;
  for (int i = 0; i < numVertices(); ++i) w2 = std::max(w2, bound[i] / masses()[i]);
  // 2 / omega_max keeps omega dt inside RK4's stability interval (|omega dt| < 2.8) for the
  // undamped network at its reference stiffness; half of it leaves a margin for the stiffening
  // of contact and large stretch, which the bound does not see.
  return w2 > 0.0 ? 0.5 * 2.0 / std::sqrt(w2) : std::numeric_limits<double>::infinity();
}

std::vector<Vec3> ParticleDynamics::appliedForces() const {
  std::vector<Vec3> f(numVertices(), Vec3::Zero());
  network_.addForces(x_, f);
  loads_.addForces(x_, 1.0, 1.0, f);
  // Damping on the velocity the step integrates (a pinned vertex moves with its pin).
  for (int i = 0; i < numVertices(); ++i) f[i] -= settings_.damping * masses()[i] * v_[i];
  return f;
}

std::vector<ContactReaction> ParticleDynamics::contactReactions() const {
  std::vector<Vec3> a(numVertices());
  std::vector<ContactReaction> reactions;
  acceleration(x_, v_, a, &reactions);
  return reactions;
}

namespace {
struct ParticleSnapshot : DynamicsSnapshot {
  std::vector<Eigen::Vector3d> x, v;
  double time = 0.0;
};
}  // namespace

std::vector<Eigen::Vector3d> ParticleDynamics::holdingForces(
    const std::vector<int>& vertices, const std::vector<Eigen::Vector3d>& accelerations) const {
  pins_.checkHoldingRequest(vertices, accelerations);
  // All applied forces are evaluated for a few held vertices: cheap next to a step (4 of them).
  const std::vector<Eigen::Vector3d> f = appliedForces();
  std::vector<Eigen::Vector3d> r(vertices.size());
  for (std::size_t k = 0; k < vertices.size(); ++k) {
    const int v = vertices[k];
    r[k] = -f[v];
    if (!accelerations.empty()) r[k] += masses()[v] * accelerations[k];
  }
  return r;
}

std::unique_ptr<DynamicsSnapshot> ParticleDynamics::snapshot() const {
  auto s = std::make_unique<ParticleSnapshot>();
  s->x = x_;
  s->v = v_;
  s->time = time_;
  return s;
}

void ParticleDynamics::restore(const DynamicsSnapshot& snapshot) {
  const auto& s = dynamic_cast<const ParticleSnapshot&>(snapshot);
  x_ = s.x;
  v_ = s.v;
  time_ = s.time;
}

void ParticleDynamics::writeState(StateWriter& out) const {
  out.text("particle network");
  out.vectors(x_);
  out.vectors(v_);
  out.real(time_);
  pins_.write(out);
}

void ParticleDynamics::readState(StateReader& in) {
  in.expectText("particle network", "dynamics backend");
  std::vector<Eigen::Vector3d> x = in.vectors("particle positions", x_.size());
  std::vector<Eigen::Vector3d> v = in.vectors("particle velocities", v_.size());
  const double time = in.real("particle time");
  PinSet pins = pins_;
  pins.read(in);
  x_ = std::move(x);
  v_ = std::move(v);
  time_ = time;
  pins_ = std::move(pins);
}

DisplaySurface ParticleDynamics::displaySurface() const {
  DisplaySurface d;
  d.vertices = x_;
  for (const auto& q : quads_) {
    d.triangles.push_back({q[0], q[1], q[2]});
    d.triangles.push_back({q[0], q[2], q[3]});
  }
  return d;
}

}  // namespace chs
