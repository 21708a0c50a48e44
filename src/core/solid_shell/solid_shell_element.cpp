#include "cloth_hair_sim/core/solid_shell/solid_shell_element.h"

#include <cmath>

#include <Eigen/Geometry>

namespace chs {

namespace {

constexpr double kNodeXi[4] = {-1, 1, 1, -1}, kNodeEta[4] = {-1, -1, 1, 1};

struct Shape {
  double N[4], dxi[4], deta[4];
};

Shape shape(double xi, double eta) {
  Shape s;
  for (int i = 0; i < 4; ++i) {
    s.N[i] = 0.25 * (1 + kNodeXi[i] * xi) * (1 + kNodeEta[i] * eta);
    s.dxi[i] = 0.25 * kNodeXi[i] * (1 + kNodeEta[i] * eta);
    s.deta[i] = 0.25 * kNodeEta[i] * (1 + kNodeXi[i] * xi);
  }
  return s;
}

using Form = Eigen::Matrix<double, 8, 8>;
int pos(int i) {
  return 2 * i;
}  // slot of x_o of node i
int dir(int i) {
  return 2 * i + 1;
}  // slot of x_n of node i

// Adds the term c (v_a . v_b) to the quadratic form v^T M v / 2 (a == b included).
void add(Form& M, int a, int b, double c) {
  M(a, b) += c;
  M(b, a) += c;
}

// Natural strains of eq. (3) at (xi, eta) as forms in the nodal vectors (the reference value is
// subtracted later): membrane (xixi, etaeta, xieta), bending (same), shear (zxi, zeta).
struct NaturalForms {
  Form m[3], b[3], s[2];
};

NaturalForms naturalForms(double xi, double eta) {
  const Shape sh = shape(xi, eta);
  NaturalForms f;
  for (auto* group : {f.m, f.b}) group[0].setZero(), group[1].setZero(), group[2].setZero();
  f.s[0].setZero();
  f.s[1].setZero();
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) {
      const double xx = sh.dxi[i] * sh.dxi[j], yy = sh.deta[i] * sh.deta[j];
      const double xy = sh.dxi[i] * sh.deta[j];
      // eps_xixi = x_o,xi . x_o,xi / 2, eps_etaeta, gamma_xieta = x_o,xi . x_o,eta
      add(f.m[0], pos(i), pos(j), 0.5 * xx);
      add(f.m[1], pos(i), pos(j), 0.5 * yy);
      add(f.m[2], pos(i), pos(j), xy);
      // bending: x_o,xi . x_n,xi; x_o,eta . x_n,eta; x_o,xi . x_n,eta + x_o,eta . x_n,xi
      add(f.b[0], pos(i), dir(j), xx);
      add(f.b[1], pos(i), dir(j), yy);
      add(f.b[2], pos(i), dir(j), xy + sh.deta[i] * sh.dxi[j]);
      // transverse shear: x_n . x_o,xi and x_n . x_o,eta
      add(f.s[0], dir(i), pos(j), sh.N[i] * sh.dxi[j]);
      add(f.s[1], dir(i), pos(j), sh.N[i] * sh.deta[j]);
    }
  return f;
}

}  // namespace

SolidShellElement::SolidShellElement(const std::array<int, 4>& nodes,
                                     const std::array<Eigen::Vector3d, 4>& X,
                                     const std::array<Eigen::Vector3d, 4>& Xn,
                                     const Eigen::Vector3d& material_x,
                                     const SolidShellRigidity& rigidity,
                                     ThicknessStrain thickness_strain, double mu)
    : nodes_(nodes), Xn_(Xn), C_(rigidity), thickness_strain_(thickness_strain), mu_(mu) {
  Eigen::Matrix<double, 8, 3>& V = reference_;
  for (int i = 0; i < 4; ++i) V.row(pos(i)) = X[i], V.row(dir(i)) = Xn[i];
  // ANS sampling points of eq. (4): gamma_zxi at (0, -1), (0, 1); gamma_zeta at (-1, 0), (1, 0).
  const NaturalForms sA = naturalForms(0, -1), sC = naturalForms(0, 1);
  const NaturalForms sD = naturalForms(-1, 0), sB = naturalForms(1, 0);
  const double g = 1.0 / std::sqrt(3.0);
  for (int q = 0; q < 4; ++q) {
    const double xi = kNodeXi[q] * g, eta = kNodeEta[q] * g;
    const Shape sh = shape(xi, eta);
    Eigen::Vector3d G1 = Eigen::Vector3d::Zero(), G2 = Eigen::Vector3d::Zero(),
                    Gn = Eigen::Vector3d::Zero();
    for (int i = 0; i < 4; ++i) {
      G1 += sh.dxi[i] * X[i];
      G2 += sh.deta[i] * X[i];
      Gn += sh.N[i] * Xn[i];
    }
    GaussPoint& gp = gauss_[q];
    gp.weight = G1.cross(G2).dot(Gn);  // J_o of eq. (8), Gauss weights 1
    const Eigen::Vector3d ez = G1.cross(G2).normalized();
    Eigen::Vector3d ex = material_x - material_x.dot(ez) * ez;
    if (!(gp.weight > 0.0) || !(ex.norm() > 1e-6 * material_x.norm())) {
      valid_ = false;
      return;
    }
    ex.normalize();
    const Eigen::Vector3d ey = ez.cross(ex);
    Eigen::Matrix2d J;  // J(i, a) = G_i . e_a
    J << G1.dot(ex), G1.dot(ey), G2.dot(ex), G2.dot(ey);
    const Eigen::Matrix2d A = J.inverse().transpose();  // A(i, a) = d xi_i / d x_a
    // Covariant natural strains to Cartesian Voigt strains (xx, yy, 2xy): the T of eq. (6).
    Eigen::Matrix3d T;
    T << A(0, 0) * A(0, 0), A(1, 0) * A(1, 0), A(0, 0) * A(1, 0),  //
        A(0, 1) * A(0, 1), A(1, 1) * A(1, 1), A(0, 1) * A(1, 1),   //
        2 * A(0, 0) * A(0, 1), 2 * A(1, 0) * A(1, 1), A(0, 0) * A(1, 1) + A(1, 0) * A(0, 1);
    const NaturalForms nat = naturalForms(xi, eta);
    // ANS transverse shear (4), then to Cartesian with T_t = A^T.
    const Form zxi = 0.5 * (1 - eta) * sA.s[0] + 0.5 * (1 + eta) * sC.s[0];
    const Form zeta = 0.5 * (1 - xi) * sD.s[1] + 0.5 * (1 + xi) * sB.s[1];
    for (int k = 0; k < 3; ++k) {
      gp.strain[k] = T(k, 0) * nat.m[0] + T(k, 1) * nat.m[1] + T(k, 2) * nat.m[2];
      gp.strain[3 + k] = T(k, 0) * nat.b[0] + T(k, 1) * nat.b[1] + T(k, 2) * nat.b[2];
    }
    for (int a = 0; a < 2; ++a) gp.strain[6 + a] = A(0, a) * zxi + A(1, a) * zeta;
    for (int k = 0; k < 8; ++k) gp.reference[k] = gp.strain[k] * V;
    for (int i = 0; i < 4; ++i) {
      gp.N[i] = sh.N[i];
      nodal_area_[i] += sh.N[i] * G1.cross(G2).norm();
    }
  }
}

Eigen::Vector3d SolidShellElement::edge(const SolidShellState& s, int p, int q) const {
  return (reference_.row(pos(q)) - reference_.row(pos(p))).transpose() + s[pos(q)] - s[pos(p)];
}

double SolidShellElement::thicknessStrain(const SolidShellState& s, int p, Eigen::Vector3d& grad,
                                          Eigen::Matrix3d& hess) const {
  const Eigen::Vector3d& un = s[dir(p)];
  const Eigen::Vector3d xn = Xn_[p] + un;
  if (thickness_strain_ == ThicknessStrain::kGreen) {
    grad = xn;
    hess.setIdentity();
    return Xn_[p].dot(un) + 0.5 * un.squaredNorm();
  }
  // Eq. (24): the upward normal of the deformed mid-surface at node p from its two neighbours
  // (taken counter-clockwise, so that it agrees with the reference director).
  const int q = (p + 1) % 4, r = (p + 3) % 4;
  const Eigen::Vector3d n = edge(s, p, q).cross(edge(s, p, r));
  const double len = xn.norm();
  const Eigen::Vector3d d = xn / len;
  const double sign = n.normalized().dot(d) > -mu_ ? 1.0 : -1.0;
  grad = sign * d;
  hess = sign * (Eigen::Matrix3d::Identity() - d * d.transpose()) / len;
  return sign * len / Xn_[p].norm() - 1.0;
}

double SolidShellElement::evaluate(const SolidShellState& state, SolidShellVector* force,
                                   SolidShellMatrix* tangent) const {
  // Strains in the displacement form of eq. (3), X^T U + U^T U / 2.
  Eigen::Matrix<double, 8, 3> U;
  for (int a = 0; a < 8; ++a) U.row(a) = state[a].transpose();
  // Nodal thickness strains of eq. (5) (trapezoidal-locking ANS) and their derivatives.
  double ez[4];
  Eigen::Vector3d dez[4];
  Eigen::Matrix3d hez[4];
  for (int p = 0; p < 4; ++p) ez[p] = thicknessStrain(state, p, dez[p], hez[p]);

  double energy = 0.0;
  if (force) force->setZero();
  if (tangent) tangent->setZero();
  Eigen::Matrix<double, 9, 9> C = Eigen::Matrix<double, 9, 9>::Zero();
  C.topLeftCorner<3, 3>() = C_.membrane;
  C.block<3, 3>(3, 3) = C_.bending;
  C.block<2, 2>(6, 6) = C_.shear;
  C(8, 8) = C_.thickness;
  for (const GaussPoint& gp : gauss_) {
    Eigen::Matrix<double, 9, 1> e;
    Eigen::Matrix<double, 9, 24> B;  // dE / dd
    for (int k = 0; k < 8; ++k) {
      const Eigen::Matrix<double, 8, 3> MU = gp.strain[k] * U;
      e[k] = (U.array() * (gp.reference[k] + 0.5 * MU).array()).sum();
      const Eigen::Matrix<double, 8, 3> MV = gp.reference[k] + MU;  // d e / d v = M v
      for (int a = 0; a < 8; ++a) B.block<1, 3>(k, 3 * a) = MV.row(a);
    }
    e[8] = 0.0;
    B.row(8).setZero();
    for (int p = 0; p < 4; ++p) {
      e[8] += gp.N[p] * ez[p];
      B.block<1, 3>(8, 3 * dir(p)) = gp.N[p] * dez[p].transpose();
    }
    const Eigen::Matrix<double, 9, 1> sigma = C * e;  // resultants
    energy += 0.5 * gp.weight * e.dot(sigma);
    if (force) *force += gp.weight * B.transpose() * sigma;
    if (!tangent) continue;
    *tangent += gp.weight * B.transpose() * C * B;
    Form geo = Form::Zero();
    for (int k = 0; k < 8; ++k) geo += sigma[k] * gp.strain[k];
    for (int a = 0; a < 8; ++a)
      for (int b = 0; b < 8; ++b)
        if (geo(a, b) != 0.0)
          tangent->block<3, 3>(3 * a, 3 * b).diagonal().array() += gp.weight * geo(a, b);
    for (int p = 0; p < 4; ++p)
      tangent->block<3, 3>(3 * dir(p), 3 * dir(p)) += gp.weight * sigma[8] * gp.N[p] * hez[p];
  }
  return energy;
}

double SolidShellElement::bendingStrainNorm(const SolidShellState& state) const {
  Eigen::Matrix<double, 8, 3> U;
  for (int a = 0; a < 8; ++a) U.row(a) = state[a].transpose();
  double sum = 0.0;
  for (const GaussPoint& gp : gauss_) {
    Eigen::Vector3d kappa;
    for (int k = 0; k < 3; ++k)
      kappa[k] = (U.array() * (gp.reference[3 + k] + 0.5 * gp.strain[3 + k] * U).array()).sum();
    sum += kappa.norm();
  }
  return sum / 4.0;
}

int SolidShellElement::reversedDirectors(const SolidShellState& s) const {
  int count = 0;
  for (int p = 0; p < 4; ++p) {
    const int q = (p + 1) % 4, r = (p + 3) % 4;
    const Eigen::Vector3d n = edge(s, p, q).cross(edge(s, p, r));
    if (n.dot(Xn_[p] + s[dir(p)]) < 0.0) ++count;
  }
  return count;
}

}  // namespace chs
