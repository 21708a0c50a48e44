#include "cloth_hair_sim/core/rod/strand_newton_solver.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/rod/parallel_transport.h"
#include "cloth_hair_sim/core/solver/banded_cholesky.h"

namespace chs::rod {
namespace {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

// A full true-Newton step this small, times sqrt(tolerance), ends the solve (below): with a
// convergence constant up to 1 / kQuadratic^2 the error left is still within the tolerance.
constexpr double kQuadratic = 0.1;

Mat3 crossMatrix(const Vec3& a) {
  Mat3 m;
  m << 0.0, -a.z(), a.y(), a.z(), 0.0, -a.x(), -a.y(), a.x(), 0.0;
  return m;
}

}  // namespace

StrandNewtonResult solveStrand(DiscreteElasticRod& rod, const StrandLoads& loads,
                               const StrandNewtonSettings& settings, double* tip_angle) {
  const int n = rod.numDofs(), nv = rod.numVertices();
  const bool dynamic = loads.dt > 0.0;
  if (dynamic && loads.inertial_target.size() != n)
    throw InputError("strand solve: inertial target of " +
                     std::to_string(loads.inertial_target.size()) + " values for " +
                     std::to_string(n) + " unknowns");
  if (!loads.vertex_forces.empty() && static_cast<int>(loads.vertex_forces.size()) != nv)
    throw InputError("strand solve: " + std::to_string(loads.vertex_forces.size()) +
                     " vertex forces for " + std::to_string(nv) + " vertices");
  if (!loads.held.empty() && static_cast<int>(loads.held.size()) != n)
    throw InputError("strand solve: held flags for " + std::to_string(loads.held.size()) + " of " +
                     std::to_string(n) + " unknowns");
  const auto held = [&](int k) { return !loads.held.empty() && loads.held[k]; };

  Eigen::VectorXd mass(n);
  for (int i = 0; i < nv; ++i)
    mass.segment<3>(DiscreteElasticRod::vertexDof(i)).setConstant(rod.vertexMass(i));
  for (int j = 0; j < rod.numEdges(); ++j)
    mass[DiscreteElasticRod::angleDof(j)] = rod.angleInertia(j);
  const double inv_dt2 = dynamic ? 1.0 / (loads.dt * loads.dt) : 0.0;
  const double mean_segment = rod.length() / rod.numEdges();

  // The tip moment's angle: the last edge's turn about the axis since entry.
  const Vec3 axis = loads.tip_moment_axis.normalized();
  const int tip = DiscreteElasticRod::vertexDof(nv - 1),
            before_tip = DiscreteElasticRod::vertexDof(nv - 2);
  const auto planar = [&](const Eigen::VectorXd& q) {
    const Vec3 e = q.segment<3>(tip) - q.segment<3>(before_tip);
    return Vec3(e - e.dot(axis) * axis);
  };
  Eigen::VectorXd q = rod.configuration();
  // Tracked from accepted iterate to accepted iterate, so that it counts whole turns; a trial
  // that turns the tip by more than a quarter turn at once is refused (the line search halves
  // it), so the increment's sign is never ambiguous.
  double phi_now = tip_angle ? *tip_angle : 0.0;
  Vec3 tip_now = planar(q);
  const auto tipAngle = [&](const Eigen::VectorXd& x) {
    return phi_now + signedAngle(tip_now, planar(x), axis);
  };

  const auto potential = [&](const Eigen::VectorXd& x) {
    constexpr double kInf = std::numeric_limits<double>::infinity();
    if (!rod.setConfiguration(x)) return kInf;
    double phi = rod.elasticEnergy();
    if (dynamic) phi += 0.5 * inv_dt2 * (x - loads.inertial_target).cwiseAbs2().dot(mass);
    for (int i = 0; i < nv; ++i) {
      Vec3 f = rod.vertexMass(i) * loads.gravity;
      if (!loads.vertex_forces.empty()) f += loads.vertex_forces[i];
      phi -= f.dot(x.segment<3>(DiscreteElasticRod::vertexDof(i)));
    }
    if (loads.obstacles) phi += loads.obstacles->energy(x);
    if (loads.tip_moment != 0.0) {
      const double turn = tipAngle(x) - phi_now;
      if (std::abs(turn) > 0.5 * M_PI) return kInf;
      phi -= loads.tip_moment * (phi_now + turn);
    }
    return phi;
  };

  StrandNewtonResult result;
  double value = potential(q);
  if (!std::isfinite(value)) return result;
  rod.commit();
  Eigen::VectorXd g(n);
  // The unknowns are in band order (solver/banded_cholesky.h).
  SymmetricBandMatrix hessian;
  BandedCholesky cholesky;
  // The Newton matrix: the true Hessian where it is positive definite (quadratic convergence
  // near a stable equilibrium), else its Gauss-Newton form (positive: a descent direction). The
  // first iteration, from the step's start far from the solve's end, takes the Gauss-Newton form
  // at once: the true one failed there for 38 % of a head of hair's strand-steps, each failure
  // costing a second assembly and factorisation (the worst strand of the head took 13
  // iterations instead of 6).
  // The gradient of Phi's terms besides the elasticity, at q, and the obstacles' Hessian.
  const auto addLoadGradient = [&](Eigen::VectorXd& grad, SymmetricBandMatrix* h) {
    if (loads.obstacles) loads.obstacles->addDerivatives(q, grad, h);
    for (int k = 0; k < n && dynamic; ++k)
      grad[k] += inv_dt2 * mass[k] * (q[k] - loads.inertial_target[k]);
    for (int i = 0; i < nv; ++i) {
      Vec3 f = rod.vertexMass(i) * loads.gravity;
      if (!loads.vertex_forces.empty()) f += loads.vertex_forces[i];
      grad.segment<3>(DiscreteElasticRod::vertexDof(i)) -= f;
    }
    if (loads.tip_moment != 0.0) {
      const Vec3 e = q.segment<3>(tip) - q.segment<3>(before_tip);
      const Vec3 dphi = axis.cross(e) / planar(q).squaredNorm();
      grad.segment<3>(tip) -= loads.tip_moment * dphi;
      grad.segment<3>(before_tip) += loads.tip_moment * dphi;
    }
  };
  const auto newtonStep = [&](bool gauss_newton, Eigen::VectorXd& dq) {
    g.setZero();
    hessian.reset(n, rod.hessianBandwidth());
    rod.addElasticDerivatives(&g, &hessian, gauss_newton);
    addLoadGradient(g, &hessian);
    for (int k = 0; k < n && dynamic; ++k) hessian.lower(k, k) += inv_dt2 * mass[k];
    if (loads.tip_moment != 0.0) {
      // phi = atan2 in the plane normal to the axis: d phi / de = a x e / |e_p|^2, and its
      // Hessian [a]x / |e_p|^2 - 2 (a x e) e_p^T / |e_p|^4 (symmetric).
      const Vec3 e = q.segment<3>(tip) - q.segment<3>(before_tip), ep = planar(q);
      const double r2 = ep.squaredNorm();
      Mat3 h = -loads.tip_moment *
               (crossMatrix(axis) / r2 - 2.0 * axis.cross(e) * ep.transpose() / (r2 * r2));
      h = 0.5 * (h + h.transpose());
      if (gauss_newton) {  // its negative eigenvalues zeroed
        Eigen::SelfAdjointEigenSolver<Mat3> es(h);
        h = es.eigenvectors() * es.eigenvalues().cwiseMax(0.0).asDiagonal() *
            es.eigenvectors().transpose();
      }

      hessian.addBlock(tip, tip, h);
      hessian.addBlock(before_tip, before_tip, h);
      hessian.addBlock(tip, before_tip, -h);
    }
    // Held unknowns: identity rows, zero gradient.
    for (int k = 0; k < n; ++k)
      if (held(k)) {
        g[k] = 0.0;
        hessian.hold(k);
      }
    if (cholesky.factorize(hessian)) {
      dq = -cholesky.solve(g);
      return true;
    }
    if (!gauss_newton) return false;
    // Semi-definite blocks can still sum to a singular matrix (a free strand's rigid motions in
    // a static solve): shift until the factorisation succeeds.
    const double diag_max = hessian.maxDiagonal();
    for (double shift = 1e-12 * diag_max; shift <= diag_max; shift *= 10.0)
      if (cholesky.factorize(hessian, shift)) {
        dq = -cholesky.solve(g);
        return true;
      }
    return false;  // nothing to descend along
  };

  // A Newton step moves the vertices along the tangent of the rotations it linearises, and a
  // stiff strand's stretching then takes back most of it: Newton's quadratic convergence starts
  // only once the edges turn by less than about r / l per step. Each trial is therefore first
  // tried with its edges turned (a retraction from the first vertex outwards: each edge along
  // the trial's direction, with the length the step changes it to at first order, l + e.de / l,
  // so that only the stretch of the turn itself, second order, is taken out) and as it is, and
  // the lower potential of the two taken. A step that turns no edge by more than a tenth of
  // r / l is in that quadratic range, where the two differ by far less than the step: tried as
  // it is alone. The retraction once kept the iterate's lengths, which took the step's own
  // change of length out as well: the true Newton step was halved by the line search every
  // other iteration, and a strand whose step ended a tenth of a segment or more from where it
  // started took 10-15 iterations (1000 hairs on the walking head: 6.26 per strand-step, 591 of
  // 165 000 at the cap of 30; with the first-order length 3.56, none).
  const double thickness = std::min(rod.material().radius_1, rod.material().semiAxis2());
  const double small_turn = 0.1 * thickness / mean_segment;
  std::vector<double> lengths(rod.numEdges());
  const auto retract = [&](const Eigen::VectorXd& x) {
    Eigen::VectorXd r = x;
    for (int j = 0; j < rod.numEdges(); ++j) {
      if (rod.edgeEnd(j) == 0) continue;  // a ring's closing edge
      const int a = DiscreteElasticRod::vertexDof(j),
                b = DiscreteElasticRod::vertexDof(rod.edgeEnd(j));
      const Vec3 e = x.segment<3>(b) - x.segment<3>(a);
      if (held(b) || e.norm() == 0.0 || lengths[j] == 0.0) continue;
      const Vec3 now = q.segment<3>(b) - q.segment<3>(a);
      double length = lengths[j] + now.dot(e - now) / lengths[j];
      if (!(length > 0.0)) length = lengths[j];  // a step that would fold the edge back
      r.segment<3>(b) = r.segment<3>(a) + length * e.normalized();
    }
    return r;
  };

  Eigen::VectorXd dq;
  for (result.iterations = 0; result.iterations < settings.max_iterations; ++result.iterations) {
    for (int j = 0; j < rod.numEdges(); ++j)
      lengths[j] = (q.segment<3>(DiscreteElasticRod::vertexDof(rod.edgeEnd(j))) -
                    q.segment<3>(DiscreteElasticRod::vertexDof(j)))
                       .norm();
    const bool exact = result.iterations > 0 && newtonStep(false, dq);
    if (!exact && !newtonStep(true, dq)) break;
    double step = 0.0;
    for (int i = 0; i < nv; ++i)
      step = std::max(step, dq.segment<3>(DiscreteElasticRod::vertexDof(i)).norm() / mean_segment);
    for (int j = 0; j < rod.numEdges(); ++j)
      step = std::max(step, std::abs(dq[DiscreteElasticRod::angleDof(j)]));
    result.step = step;
    // Armijo backtracking; the slack of a few ulps of Phi lets the last, tiny steps through
    // where Phi no longer resolves the decrease.
    const double slope = g.dot(dq), slack = 1e-14 * std::abs(value);
    bool accepted = false, full_step = false;
    for (double alpha = 1.0; alpha > 1e-10 && !accepted; alpha *= 0.5) {
      const Eigen::VectorXd plain = q + alpha * dq;
      const bool retracting = alpha * step > small_turn;
      const Eigen::VectorXd turned = retracting ? retract(plain) : plain;
      const double v_plain = potential(plain), v_turned = retracting ? potential(turned) : v_plain;
      const bool take_turned = v_turned < v_plain;
      const double v = take_turned ? v_turned : v_plain;
      if (v <= value + 1e-4 * alpha * slope + slack) {
        q = take_turned ? turned : plain;
        // The rod holds the configuration evaluated last (its frames transported from the same
        // committed one): set again only if that was the other.
        if (retracting && !take_turned) rod.setConfiguration(q);
        value = v;
        accepted = true;
        full_step = alpha == 1.0 && !take_turned;
        rod.commit();
        phi_now = tipAngle(q);
        tip_now = planar(q);
      }
    }
    if (!accepted) {
      rod.setConfiguration(q);
      break;
    }
    // Converged: a step within the tolerance, or a full step of the true Newton iteration within
    // sqrt(tolerance) times kQuadratic: quadratic convergence leaves an error of the order of that
    // step squared, and the iteration that would confirm it is not taken.
    const double quadratic = kQuadratic * std::sqrt(settings.tolerance);
    if (step <= settings.tolerance || (exact && full_step && step <= quadratic)) {
      result.converged = true;
      ++result.iterations;
      break;
    }
  }
  if (tip_angle) *tip_angle = phi_now;
  if (!loads.held.empty()) {
    Eigen::VectorXd full = Eigen::VectorXd::Zero(n);
    rod.addElasticDerivatives(&full, nullptr, false);
    addLoadGradient(full, nullptr);
    result.held_reaction = Eigen::VectorXd::Zero(n);
    for (int k = 0; k < n; ++k)
      if (held(k)) result.held_reaction[k] = full[k];
  }
  return result;
}

}  // namespace chs::rod
