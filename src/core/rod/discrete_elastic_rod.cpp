#include "cloth_hair_sim/core/rod/discrete_elastic_rod.h"

#include <cmath>
#include <string>

#include <Eigen/Geometry>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/rod/curvature.h"
#include "cloth_hair_sim/core/rod/parallel_transport.h"

namespace chs::rod {
namespace {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

constexpr double kMinSegment = 1e-9;  // [m]: shorter is a duplicate vertex
// 1 + te . tf below this is a segment folded back onto its neighbour (turned by > 179.9 deg):
// the curvature binormal 2 tan(phi / 2) has no finite value there.
constexpr double kMinChi = 1e-6;

}  // namespace

DiscreteElasticRod::DiscreteElasticRod(const std::vector<Vec3>& rest, const RodMaterial& material,
                                       const Vec3& first_director, bool closed)
    : material_(material), closed_(closed), x_(rest) {
  checkRodMaterial(material, "strand material");
  if (rest.size() < (closed ? 3u : 2u))
    throw InputError(std::string(closed ? "ring" : "strand") + ": needs at least " +
                     (closed ? "three" : "two") + " vertices, got " + std::to_string(rest.size()));
  for (std::size_t i = 0; i < rest.size(); ++i)
    if (!rest[i].allFinite())
      throw InputError("strand: vertex " + std::to_string(i) + " is not finite");
  const int ne = numEdges();
  for (int j = 0; j < ne; ++j)
    if ((rest[edgeEnd(j)] - rest[j]).norm() < kMinSegment)
      throw InputError("strand: segment " + std::to_string(j) + " has zero length (vertices " +
                       std::to_string(j) + " and " + std::to_string(edgeEnd(j)) + " coincide)");
  for (int i = firstBendingVertex(); i < endBendingVertex(); ++i) {
    const int p = previousEdge(i);
    const Vec3 a = (rest[i] - rest[p]).normalized(), b = (rest[edgeEnd(i)] - rest[i]).normalized();
    if (1.0 + a.dot(b) < kMinChi)
      throw InputError("strand: segment " + std::to_string(i) + " folds back onto segment " +
                       std::to_string(p));
  }
  if (!first_director.allFinite()) throw InputError("strand: first director must be finite");

  stretch_ = material.stretchingStiffness();
  bend_1_ = material.bendingStiffness1();
  bend_2_ = material.bendingStiffness2();
  twist_stiffness_ = material.twistingStiffness();

  rest_length_.resize(ne);
  for (int j = 0; j < ne; ++j) rest_length_[j] = (rest[edgeEnd(j)] - rest[j]).norm();
  const int nv = numVertices();
  voronoi_.assign(nv, 0.0);
  vertex_mass_.assign(nv, 0.0);
  angle_inertia_.resize(ne);
  for (int j = 0; j < ne; ++j) {
    vertex_mass_[j] += 0.5 * material.linearDensity() * rest_length_[j];
    vertex_mass_[edgeEnd(j)] += 0.5 * material.linearDensity() * rest_length_[j];
    angle_inertia_[j] = material.polarInertiaPerLength() * rest_length_[j];
  }
  for (int i = firstBendingVertex(); i < endBendingVertex(); ++i)
    voronoi_[i] = 0.5 * (rest_length_[previousEdge(i)] + rest_length_[i]);

  // Rest frames: the first director transported along the centreline.
  theta_.assign(ne, 0.0);
  t_.resize(ne);
  d1_.resize(ne);
  for (int j = 0; j < ne; ++j) t_[j] = (rest[edgeEnd(j)] - rest[j]).normalized();
  Vec3 d = first_director - first_director.dot(t_[0]) * t_[0];
  d1_[0] = d.norm() > 1e-12 * std::max(1.0, first_director.norm()) ? Vec3(d.normalized())
                                                                   : anyNormal(t_[0]);
  for (int j = 1; j < ne; ++j)
    d1_[j] = parallelTransport(d1_[j - 1], t_[j - 1], t_[j]).normalized();
  base_t_ = t_;
  base_d1_ = d1_;
  base_ref_twist_.assign(nv, 0.0);
  updateFrames();
  rest_kappa_.assign(nv, Eigen::Vector2d::Zero());
  rest_twist_.assign(nv, 0.0);
  for (int i = firstBendingVertex(); i < endBendingVertex(); ++i) {
    rest_kappa_[i] = curvature(i);
    rest_twist_[i] = twist(i);
  }
  commit();
}

double DiscreteElasticRod::length() const {
  double l = 0.0;
  for (double r : rest_length_) l += r;
  return l;
}

void DiscreteElasticRod::updateFrames() {
  const int ne = numEdges();
  admissible_ = true;
  d2_.resize(ne);
  m1_.resize(ne);
  m2_.resize(ne);
  ref_twist_.assign(numVertices(), 0.0);
  for (int j = 0; j < ne; ++j) {
    const Vec3 e = x_[edgeEnd(j)] - x_[j];
    const double l = e.norm();
    if (!(l > 1e-3 * rest_length_[j])) admissible_ = false;
    t_[j] = l > 0.0 ? Vec3(e / l) : base_t_[j];
    if (1.0 + base_t_[j].dot(t_[j]) < kMinChi) admissible_ = false;  // no transport
    Vec3 d1 = parallelTransport(base_d1_[j], base_t_[j], t_[j]);
    d1 = (d1 - d1.dot(t_[j]) * t_[j]).normalized();  // keeps the frame orthonormal over steps
    d1_[j] = d1;
    d2_[j] = t_[j].cross(d1);
    const double c = std::cos(theta_[j]), s = std::sin(theta_[j]);
    m1_[j] = c * d1_[j] + s * d2_[j];
    m2_[j] = -s * d1_[j] + c * d2_[j];
  }
  for (int i = firstBendingVertex(); i < endBendingVertex(); ++i) {
    const int p = previousEdge(i);
    if (1.0 + t_[p].dot(t_[i]) < kMinChi) admissible_ = false;
    // Bergou 2010 section 4.2: the reference twist changes by the angle between d1_i and
    // d1_{i-1} transported to t_i and turned by the old reference twist, that is by the angle
    // from the transported d1_{i-1} to d1_i less the old twist, wrapped into [-pi, pi] (no
    // rotation of the transported director needed).
    const double turn =
        signedAngle(parallelTransport(d1_[p], t_[p], t_[i]), d1_[i], t_[i]) - base_ref_twist_[i];
    ref_twist_[i] = base_ref_twist_[i] + turn - 2.0 * M_PI * std::round(turn / (2.0 * M_PI));
  }
}

Eigen::Vector2d DiscreteElasticRod::curvature(int i) const {
  const int p = previousEdge(i);
  const Vec3 kb = 2.0 * t_[p].cross(t_[i]) / (1.0 + t_[p].dot(t_[i]));
  return {0.5 * kb.dot(m2_[p] + m2_[i]), -0.5 * kb.dot(m1_[p] + m1_[i])};
}

double DiscreteElasticRod::twist(int i) const {
  return theta_[i] - theta_[previousEdge(i)] + ref_twist_[i];
}

Eigen::VectorXd DiscreteElasticRod::configuration() const {
  Eigen::VectorXd q(numDofs());
  for (int i = 0; i < numVertices(); ++i) q.segment<3>(vertexDof(i)) = x_[i];
  for (int j = 0; j < numEdges(); ++j) q[angleDof(j)] = theta_[j];
  return q;
}

bool DiscreteElasticRod::setConfiguration(const Eigen::VectorXd& q) {
  if (q.size() != numDofs())
    throw InputError("strand: configuration of " + std::to_string(q.size()) + " values for " +
                     std::to_string(numDofs()) + " unknowns");
  for (int i = 0; i < numVertices(); ++i) x_[i] = q.segment<3>(vertexDof(i));
  for (int j = 0; j < numEdges(); ++j) theta_[j] = q[angleDof(j)];
  updateFrames();
  return admissible_ && q.allFinite();
}

void DiscreteElasticRod::commit() {
  base_t_ = t_;
  base_d1_ = d1_;
  base_ref_twist_ = ref_twist_;
}

double DiscreteElasticRod::elasticEnergy() const {
  double energy = 0.0;
  for (int j = 0; j < numEdges(); ++j) {
    const double strain = (x_[edgeEnd(j)] - x_[j]).norm() / rest_length_[j] - 1.0;
    energy += 0.5 * stretch_ * strain * strain * rest_length_[j];
  }
  for (int i = firstBendingVertex(); i < endBendingVertex(); ++i) {
    const Eigen::Vector2d dk = curvature(i) - rest_kappa_[i];
    const double dm = twist(i) - rest_twist_[i];
    energy += 0.5 *
              (bend_1_ * dk[0] * dk[0] + bend_2_ * dk[1] * dk[1] + twist_stiffness_ * dm * dm) /
              voronoi_[i];
  }
  return energy;
}

void DiscreteElasticRod::addElasticDerivatives(Eigen::VectorXd* gradient,
                                               SymmetricBandMatrix* hessian,
                                               bool gauss_newton) const {
  const bool want_h = hessian != nullptr;
  // Stretching: E = EA / 2 (|e| / L - 1)^2 L on edge j, unknowns x_j, x_{j+1}.
  for (int j = 0; j < numEdges(); ++j) {
    const Vec3 e = x_[edgeEnd(j)] - x_[j];
    const double l = e.norm(), L = rest_length_[j];
    const Vec3 t = e / l;
    const Vec3 g = stretch_ * (l / L - 1.0) * t;
    const int a = vertexDof(j), b = vertexDof(edgeEnd(j));
    if (gradient) {
      gradient->segment<3>(a) -= g;
      gradient->segment<3>(b) += g;
    }
    if (!want_h) continue;
    // Along the edge EA / L; across it the tension EA (1 / L - 1 / l), dropped when compressed
    // (negative) in the Gauss-Newton form.
    double across = stretch_ * (1.0 / L - 1.0 / l);
    if (gauss_newton) across = std::max(across, 0.0);
    const Mat3 h =
        stretch_ / L * t * t.transpose() + across * (Mat3::Identity() - t * t.transpose());
    hessian->addBlock(a, a, h);
    hessian->addBlock(b, b, h);
    hessian->addBlock(a, b, -h);
    hessian->addBlock(b, a, -h);
  }
  // Bending and twisting at vertex i, in the local variables (e, theta_e, f, theta_f) of
  // curvature.h; those map to the unknowns (x_{i-1}, theta_{i-1}, x_i, theta_i, x_{i+1}) by
  // e = x_i - x_{i-1}, f = x_{i+1} - x_i (contiguous in q for an open rod, q.segment(4 (i - 1),
  // 11); a ring's vertex 0 wraps round): local variable a is +unknown plus[a] - unknown
  // minus[a] (no minus for the angles).
  for (int i = firstBendingVertex(); i < endBendingVertex(); ++i) {
    const int p = previousEdge(i), next = edgeEnd(i);
    int plus[8], minus[8];
    for (int k = 0; k < 3; ++k) {
      plus[k] = minus[4 + k] = vertexDof(i) + k;
      minus[k] = vertexDof(p) + k;
      plus[4 + k] = vertexDof(next) + k;
    }
    plus[3] = angleDof(p);
    plus[7] = angleDof(i);
    minus[3] = minus[7] = -1;
    const Vec3 e = x_[i] - x_[p], f = x_[next] - x_[i];
    const EdgePairFrames frames{m1_[p], m2_[p], m1_[i], m2_[i]};
    const CurvatureDerivatives k = curvatureDerivatives(e, f, frames);
    // (The Gauss-Newton form needs no second derivatives of the strains.)
    const bool strain_hessians = want_h && !gauss_newton;
    const TwistDerivatives tw = twistDerivatives(e, f, k.kb, strain_hessians);
    const double l = voronoi_[i];
    const Eigen::Vector2d dk = k.kappa - rest_kappa_[i];
    const double dm = twist(i) - rest_twist_[i];
    const double b1 = bend_1_ / l, b2 = bend_2_ / l, gj = twist_stiffness_ / l;
    const Vector8d g =
        b1 * dk[0] * k.gradient[0] + b2 * dk[1] * k.gradient[1] + gj * dm * tw.gradient;
    if (gradient)
      for (int a = 0; a < 8; ++a) {
        (*gradient)[plus[a]] += g[a];
        if (minus[a] >= 0) (*gradient)[minus[a]] -= g[a];
      }
    if (!want_h) continue;
    // The energy's Hessian sum_c B_c (grad c grad c^T + (c - c_rest) hess c) over the strains c
    // (two curvatures, the twist); the Gauss-Newton form keeps the first, positive part.
    Matrix8d h = b1 * k.gradient[0] * k.gradient[0].transpose() +
                 b2 * k.gradient[1] * k.gradient[1].transpose() +
                 gj * tw.gradient * tw.gradient.transpose();
    if (strain_hessians)
      h += curvatureHessian(e, f, frames, Eigen::Vector2d(b1 * dk[0], b2 * dk[1])) +
           gj * dm * tw.hessian;
    if (next == i + 1 && p == i - 1) {
      // The 11 unknowns are contiguous: H = J^T h J as a dense block, first T = h J (J's
      // columns: x_{i-1} -e, theta_{i-1}, x_i e - f, theta_i, x_{i+1} f), then J^T T.
      Eigen::Matrix<double, 8, 11> T;
      T.leftCols<3>() = -h.leftCols<3>();
      T.col(3) = h.col(3);
      T.middleCols<3>(4) = h.leftCols<3>() - h.middleCols<3>(4);
      T.col(7) = h.col(7);
      T.rightCols<3>() = h.middleCols<3>(4);
      Eigen::Matrix<double, 11, 11> H;
      H.topRows<3>() = -T.topRows<3>();
      H.row(3) = T.row(3);
      H.middleRows<3>(4) = T.topRows<3>() - T.middleRows<3>(4);
      H.row(7) = T.row(7);
      H.bottomRows<3>() = T.middleRows<3>(4);
      hessian->addDiagonalBlock(vertexDof(p), H);
      continue;
    }
    // A ring's vertex 0: H = J^T h J entry by entry (J's entries are +-1).
    for (int a = 0; a < 8; ++a)
      for (int b = 0; b < 8; ++b) {
        const double v = h(a, b);
        hessian->add(plus[a], plus[b], v);
        if (minus[b] >= 0) hessian->add(plus[a], minus[b], -v);
        if (minus[a] < 0) continue;
        hessian->add(minus[a], plus[b], -v);
        if (minus[b] >= 0) hessian->add(minus[a], minus[b], v);
      }
  }
}

void DiscreteElasticRod::setNaturalShape(const std::vector<Eigen::Vector2d>& curvature,
                                         const std::vector<double>& twist) {
  if (static_cast<int>(curvature.size()) != numVertices() ||
      static_cast<int>(twist.size()) != numVertices())
    throw InputError("strand: natural shape of " + std::to_string(curvature.size()) +
                     " curvatures and " + std::to_string(twist.size()) + " twists for " +
                     std::to_string(numVertices()) + " vertices");
  for (int i = 0; i < numVertices(); ++i)
    if (!curvature[i].allFinite() || !std::isfinite(twist[i]))
      throw InputError("strand: natural curvature or twist of vertex " + std::to_string(i) +
                       " is not finite");
  for (int i = firstBendingVertex(); i < endBendingVertex(); ++i) {
    rest_kappa_[i] = curvature[i];
    rest_twist_[i] = twist[i];
  }
}

void DiscreteElasticRod::writeState(StateWriter& out) const {
  out.vectors(x_);
  out.reals(theta_);
  out.vectors(base_t_);
  out.vectors(base_d1_);
  out.reals(base_ref_twist_);
  std::vector<double> kappa;
  for (const auto& k : rest_kappa_) kappa.insert(kappa.end(), {k[0], k[1]});
  out.reals(kappa);
  out.reals(rest_twist_);
}

void DiscreteElasticRod::readState(StateReader& in) {
  const std::size_t nv = x_.size(), ne = theta_.size();
  std::vector<Eigen::Vector3d> x = in.vectors("strand positions", nv);
  std::vector<double> theta = in.reals("strand angles", ne);
  base_t_ = in.vectors("strand reference tangents", base_t_.size());
  base_d1_ = in.vectors("strand reference directors", base_d1_.size());
  base_ref_twist_ = in.reals("strand reference twists", base_ref_twist_.size());
  const std::vector<double> kappa = in.reals("strand natural curvatures", 2 * rest_kappa_.size());
  for (std::size_t i = 0; i < rest_kappa_.size(); ++i)
    rest_kappa_[i] = Eigen::Vector2d(kappa[2 * i], kappa[2 * i + 1]);
  rest_twist_ = in.reals("strand natural twists", rest_twist_.size());
  x_ = std::move(x);
  theta_ = std::move(theta);
  updateFrames();
}

}  // namespace chs::rod
