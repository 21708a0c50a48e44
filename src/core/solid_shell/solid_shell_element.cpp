#include "cloth_hair_sim/core/solid_shell/solid_shell_element.h"

#include <cmath>

#include <Eigen/Geometry>

namespace chs {

namespace {

constexpr double kNodeXi[4] = {-1, 1, 1, -1}, kNodeEta[4] = {-1, -1, 1, 1};

// Shape functions and their derivatives in the element's natural coordinates (xi, eta) or
// (s, t); a triangle leaves the fourth entries zero.
struct Shape {
  double N[4] = {0, 0, 0, 0}, dxi[4] = {0, 0, 0, 0}, deta[4] = {0, 0, 0, 0};
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

// Triangle of eq. (10): N_1 = r = 1 - s - t, N_2 = s, N_3 = t.
Shape triangleShape(double s, double t) {
  Shape sh;
  sh.N[0] = 1 - s - t;
  sh.N[1] = s;
  sh.N[2] = t;
  sh.dxi[0] = -1, sh.dxi[1] = 1;
  sh.deta[0] = -1, sh.deta[2] = 1;
  return sh;
}

NaturalForms naturalForms(const Shape& sh) {
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

NaturalForms naturalForms(double xi, double eta) {
  return naturalForms(shape(xi, eta));
}

// Eq. (12): the natural transverse shear along the edge from node a to node b at its midpoint,
// x_n (a + b) / 2 . (x_o,b - x_o,a), as a form.
Form edgeShear(int a, int b) {
  Form f = Form::Zero();
  for (int n : {a, b}) {
    add(f, dir(n), pos(b), 0.25);
    add(f, dir(n), pos(a), -0.25);
  }
  return f;
}

// The element's material frame at a mid-surface point with tangents G1, G2 (e_z their normal,
// e_x the material axis projected onto the surface) and what maps natural strains to it.
struct LocalFrame {
  Eigen::Vector3d ex, ey, ez;
  Eigen::Matrix2d A;  // A(i, a) = d xi_i / d x_a
  Eigen::Matrix3d T;  // covariant natural strains to Cartesian Voigt (xx, yy, 2xy): eq. (6)
  bool valid = false;
};

LocalFrame localFrame(const Eigen::Vector3d& G1, const Eigen::Vector3d& G2,
                      const Eigen::Vector3d& material_x) {
  LocalFrame f;
  f.ez = G1.cross(G2).normalized();
  f.ex = material_x - material_x.dot(f.ez) * f.ez;
  if (!(G1.cross(G2).norm() > 0.0) || !(f.ex.norm() > 1e-6 * material_x.norm())) return f;
  f.ex.normalize();
  f.ey = f.ez.cross(f.ex);
  Eigen::Matrix2d J;  // J(i, a) = G_i . e_a
  J << G1.dot(f.ex), G1.dot(f.ey), G2.dot(f.ex), G2.dot(f.ey);
  f.A = J.inverse().transpose();
  const Eigen::Matrix2d& A = f.A;
  f.T << A(0, 0) * A(0, 0), A(1, 0) * A(1, 0), A(0, 0) * A(1, 0),  //
      A(0, 1) * A(0, 1), A(1, 1) * A(1, 1), A(0, 1) * A(1, 1),     //
      2 * A(0, 0) * A(0, 1), 2 * A(1, 0) * A(1, 1), A(0, 0) * A(1, 1) + A(1, 0) * A(0, 1);
  f.valid = true;
  return f;
}

// Membrane and bending strains of eq. (6) in the local frame, then the two transverse shears.
std::array<Form, 8> cartesianStrains(const Eigen::Matrix3d& T, const NaturalForms& nat,
                                     const std::array<Form, 2>& shear) {
  std::array<Form, 8> e;
  for (int k = 0; k < 3; ++k) {
    e[k] = T(k, 0) * nat.m[0] + T(k, 1) * nat.m[1] + T(k, 2) * nat.m[2];
    e[3 + k] = T(k, 0) * nat.b[0] + T(k, 1) * nat.b[1] + T(k, 2) * nat.b[2];
  }
  e[6] = shear[0];
  e[7] = shear[1];
  return e;
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
    const LocalFrame lf = localFrame(G1, G2, material_x);
    // ANS transverse shear (4), then to Cartesian with T_t = A^T.
    const Form zxi = 0.5 * (1 - eta) * sA.s[0] + 0.5 * (1 + eta) * sC.s[0];
    const Form zeta = 0.5 * (1 - xi) * sD.s[1] + 0.5 * (1 + xi) * sB.s[1];
    std::array<Form, 2> shear;
    for (int a = 0; a < 2; ++a) shear[a] = lf.A(0, a) * zxi + lf.A(1, a) * zeta;
    if (!lf.valid || !setGaussPoint(gauss_[q], sh.N, G1, G2, Gn, 1.0,
                                    cartesianStrains(lf.T, naturalForms(sh), shear))) {
      valid_ = false;
      return;
    }
  }
}

// Seed 001 eqs. (10)-(15): the 3-node triangle, three-point rule at (s, t) = (1/6, 1/6),
// (2/3, 1/6), (1/6, 2/3) with weights 1/6.
SolidShellElement::SolidShellElement(const std::array<int, 3>& nodes,
                                     const std::array<Eigen::Vector3d, 3>& X,
                                     const std::array<Eigen::Vector3d, 3>& Xn,
                                     const Eigen::Vector3d& material_x,
                                     const SolidShellRigidity& rigidity,
                                     ThicknessStrain thickness_strain, double mu)
    : nodes_({nodes[0], nodes[1], nodes[2], -1}),
      Xn_({Xn[0], Xn[1], Xn[2], Eigen::Vector3d::Zero()}),
      C_(rigidity),
      thickness_strain_(thickness_strain),
      mu_(mu),
      corners_(3),
      num_gauss_(3) {
  Eigen::Matrix<double, 8, 3>& V = reference_;
  V.setZero();
  for (int i = 0; i < 3; ++i) V.row(pos(i)) = X[i], V.row(dir(i)) = Xn[i];
  // Reference edge vectors d_r X_o = X_1 - X_3, d_s X_o = X_2 - X_1, d_t X_o = X_3 - X_2 (the
  // differentiation operators of eq. (12)) and the natural shears along them at the edges'
  // midpoints.
  const std::array<Eigen::Vector3d, 3> edge = {X[0] - X[2], X[1] - X[0], X[2] - X[1]};
  const std::array<Form, 3> natural = {edgeShear(2, 0), edgeShear(0, 1), edgeShear(1, 2)};
  const Eigen::Vector3d G1 = X[1] - X[0], G2 = X[2] - X[0];  // x_o,s and x_o,t
  const LocalFrame lf = localFrame(G1, G2, material_x);
  if (!lf.valid) {
    valid_ = false;
    return;
  }
  // Eq. (13): each node's Cartesian shear from the two edges meeting there (r, s at node 1; s, t
  // at node 2; t, r at node 3), as forms.
  std::array<std::array<Form, 2>, 3> nodal;
  for (int i = 0; i < 3; ++i) {
    const int e1 = i, e2 = (i + 1) % 3;
    Eigen::Matrix2d M;
    M << edge[e1].dot(lf.ex), edge[e1].dot(lf.ey), edge[e2].dot(lf.ex), edge[e2].dot(lf.ey);
    const Eigen::Matrix2d Minv = M.inverse();
    for (int a = 0; a < 2; ++a) nodal[i][a] = Minv(a, 0) * natural[e1] + Minv(a, 1) * natural[e2];
  }
  const double points[3][2] = {{1.0 / 6, 1.0 / 6}, {2.0 / 3, 1.0 / 6}, {1.0 / 6, 2.0 / 3}};
  for (int q = 0; q < 3; ++q) {
    const Shape sh = triangleShape(points[q][0], points[q][1]);
    Eigen::Vector3d Gn = Eigen::Vector3d::Zero();
    for (int i = 0; i < 3; ++i) Gn += sh.N[i] * Xn[i];
    std::array<Form, 2> shear;  // eq. (14)
    for (int a = 0; a < 2; ++a)
      shear[a] = sh.N[0] * nodal[0][a] + sh.N[1] * nodal[1][a] + sh.N[2] * nodal[2][a];
    if (!setGaussPoint(gauss_[q], sh.N, G1, G2, Gn, 1.0 / 6,
                       cartesianStrains(lf.T, naturalForms(sh), shear))) {
      valid_ = false;
      return;
    }
  }
}

bool SolidShellElement::setGaussPoint(GaussPoint& gp, const double N[4], const Eigen::Vector3d& G1,
                                      const Eigen::Vector3d& G2, const Eigen::Vector3d& Gn,
                                      double rule_weight, const std::array<Form, 8>& strains) {
  gp.weight = rule_weight * G1.cross(G2).dot(Gn);  // J_o of eq. (8) times the rule's weight
  if (!(gp.weight > 0.0)) return false;
  gp.strain = strains;
  for (int k = 0; k < 8; ++k) gp.reference[k] = gp.strain[k] * reference_;
  for (int i = 0; i < 4; ++i) {
    gp.N[i] = N[i];
    nodal_area_[i] += rule_weight * N[i] * G1.cross(G2).norm();
  }
  return true;
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
  const int q = (p + 1) % corners_, r = (p + corners_ - 1) % corners_;
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
  for (int p = 0; p < corners_; ++p) ez[p] = thicknessStrain(state, p, dez[p], hez[p]);

  double energy = 0.0;
  if (force) force->setZero();
  if (tangent) tangent->setZero();
  Eigen::Matrix<double, 9, 9> C = Eigen::Matrix<double, 9, 9>::Zero();
  C.topLeftCorner<3, 3>() = C_.membrane;
  C.block<3, 3>(3, 3) = C_.bending;
  C.block<2, 2>(6, 6) = C_.shear;
  C(8, 8) = C_.thickness;
  for (int g = 0; g < num_gauss_; ++g) {
    const GaussPoint& gp = gauss_[g];
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
    for (int p = 0; p < corners_; ++p) {
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
    for (int p = 0; p < corners_; ++p)
      tangent->block<3, 3>(3 * dir(p), 3 * dir(p)) += gp.weight * sigma[8] * gp.N[p] * hez[p];
  }
  return energy;
}

double SolidShellElement::bendingStrainNorm(const SolidShellState& state) const {
  Eigen::Matrix<double, 8, 3> U;
  for (int a = 0; a < 8; ++a) U.row(a) = state[a].transpose();
  double sum = 0.0;
  for (int g = 0; g < num_gauss_; ++g) {
    const GaussPoint& gp = gauss_[g];
    Eigen::Vector3d kappa;
    for (int k = 0; k < 3; ++k)
      kappa[k] = (U.array() * (gp.reference[3 + k] + 0.5 * gp.strain[3 + k] * U).array()).sum();
    sum += kappa.norm();
  }
  return sum / num_gauss_;
}

int SolidShellElement::reversedDirectors(const SolidShellState& s) const {
  int count = 0;
  for (int p = 0; p < corners_; ++p) {
    const int q = (p + 1) % corners_, r = (p + corners_ - 1) % corners_;
    const Eigen::Vector3d n = edge(s, p, q).cross(edge(s, p, r));
    if (n.dot(Xn_[p] + s[dir(p)]) < 0.0) ++count;
  }
  return count;
}

}  // namespace chs
