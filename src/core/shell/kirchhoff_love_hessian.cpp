#include "cloth_hair_sim/core/shell/kirchhoff_love_hessian.h"

#include <array>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

namespace chs {

std::vector<FibreRange> fibreRanges(const std::vector<KirchhoffLovePoint>& points) {
  std::vector<FibreRange> fibres;
  const int n = static_cast<int>(points.size());
  for (int first = 0; first < n;) {
    int last = first + 1;
    while (last < n && points[last].sharesFibreWith(points[first])) ++last;
    fibres.push_back({first, last});
    first = last;
  }
  return fibres;
}

double fibreEnergy(const std::vector<KirchhoffLovePoint>& points, const FibreRange& fibre,
                   const HenckyLamina& material, const StencilSums& s, StencilSums* gradient) {
  const MidSurfaceFrame frame = MidSurfaceFrame::fromSums(s);
  double e = 0.0;
  if (!gradient) {
    for (int q = fibre.first; q < fibre.last; ++q) e += points[q].energy(material, frame);
    return e;
  }
  // As kirchhoffLoveEnergy: g_alpha = a_alpha + xi3 a_{3,alpha}, g_3 = a_3.
  Eigen::Matrix3d dpsi_da = Eigen::Matrix3d::Zero(), dpsi_dg;
  Eigen::Matrix<double, 3, 2> dpsi_da3d = Eigen::Matrix<double, 3, 2>::Zero();
  for (int q = fibre.first; q < fibre.last; ++q) {
    e += points[q].energy(material, frame, &dpsi_dg);
    dpsi_da += dpsi_dg;
    dpsi_da3d += points[q].xi3() * dpsi_dg.leftCols<2>();
  }
  *gradient = frame.sumAdjoint(dpsi_da, dpsi_da3d);
  return e;
}

namespace {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using SumJacobian = Eigen::Matrix<double, 3, 15>;  // d(3-vector) / ds

// [c]_x, c x y = [c]_x y.
Mat3 crossMatrix(const Vec3& c) {
  Mat3 m;
  m << 0.0, -c.z(), c.y(), c.z(), 0.0, -c.x(), -c.y(), c.x(), 0.0;
  return m;
}

// The Hessian in n of c . a_3, a_3 = n / J:
//   -(c a_3^T + a_3 c^T + (c . a_3)(I - 3 a_3 a_3^T)) / J^2.
// With c = n_{,alpha} it is also d a_{3,alpha} / dn, a_{3,alpha} = (I - a_3 a_3^T) n_{,alpha} / J
// (A.1).
Mat3 unitNormalHessian(const Vec3& c, const Vec3& a3, double J) {
  const Mat3 ca = c * a3.transpose();
  return -(ca + ca.transpose() + c.dot(a3) * (Mat3::Identity() - 3.0 * a3 * a3.transpose())) /
         (J * J);
}

// The Hessian in n of v . a_{3,alpha} at fixed n_{,alpha} = m: the third derivative of a_3.
Mat3 normalDerivativeHessian(const Vec3& v, const Vec3& m, const Vec3& a3, double J) {
  const double vn = v.dot(a3), mn = m.dot(a3);
  const Mat3 aa = a3 * a3.transpose(), vm = v * m.transpose();
  const Mat3 w = (vn * m + mn * v) * a3.transpose();
  return (-v.dot(m) * (Mat3::Identity() - 3.0 * aa) +
          vn * mn * (3.0 * Mat3::Identity() - 15.0 * aa) - vm - vm.transpose() +
          3.0 * (w + w.transpose())) /
         (J * J * J);
}

// Adds the Hessian of c . (s_x x s_y) in the sums: block (x, y) -[c]_x, block (y, x) [c]_x.
void addCrossHessian(FibreHessian& H, const Vec3& c, int x, int y) {
  const Mat3 m = crossMatrix(c);
  H.block<3, 3>(3 * x, 3 * y) -= m;
  H.block<3, 3>(3 * y, 3 * x) += m;
}

// Adds X^T Y, symmetric by construction, to the upper triangle of H as nine-long dot products:
// Eigen would pack the 15 x 9 x 15 product for its GEMM kernel, several times slower at this size.
using Rows = Eigen::Matrix<double, 9, 15>;
void addUpperProduct(FibreHessian& H, const Rows& X, const Rows& Y) {
  for (int j = 0; j < 15; ++j)
    for (int i = 0; i <= j; ++i) H(i, j) += X.col(i).dot(Y.col(j));
}

template <int N>
Eigen::Matrix<double, N, N> positivePart(const Eigen::Matrix<double, N, N>& A) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, N, N>> eig(A);
  return eig.eigenvectors() * eig.eigenvalues().cwiseMax(0.0).asDiagonal() *
         eig.eigenvectors().transpose();
}

// Psi = sum_q V_q psi(C_q), C_q = L_q^T L_q, L_q = [g_1 g_2 g_3] M_q (the lamina vectors l_beta
// of F^{KL,E,tr}, (5.34)-(5.35)). Its Hessian in s has a material part and a curvature part:
//   sum_q V_q dL^T (S (x) I + dc/dL^T psi_cc dc/dL) dL + sum_i w_i . d^2 g_i / ds^2,
// c = (C_11, C_22, C_12), w_i = dPsi/dg_i summed over the fibre (the gradient's adjoints). The
// g_i depend on s through n = a_1 x a_2 and m_alpha = n_{,alpha} (A.1), both bilinear in s: with
// F(n, m_1, m_2) = u . a_3 + v_alpha . a_{3,alpha} (u, v_alpha the adjoints of a_3, a_{3,alpha};
// F is linear in m), the curvature part is dchi^T F_chichi dchi + dF/dchi . d^2 chi / ds^2,
// chi = (n, m_1, m_2).
// With gauss_newton: the material part alone, the lamina's stress S and tangent psi_cc clamped to
// positive semidefinite, so positive semidefinite by construction (a sum of B^T D B, D >= 0).
FibreHessian fibreHessianIn(const std::vector<KirchhoffLovePoint>& points, const FibreRange& fibre,
                            const HenckyLamina& material, const StencilSums& s, bool gauss_newton) {
  const MidSurfaceFrame frame = MidSurfaceFrame::fromSums(s);
  const double J = frame.area_ratio;
  const Vec3& a3 = frame.a3;
  const Mat3 P_J = (Mat3::Identity() - a3 * a3.transpose()) / J;  // d a_3 / dn
  // Jacobians of n and m_alpha = a_{1,alpha} x a_2 + a_1 x a_{2,alpha}.
  SumJacobian dn = SumJacobian::Zero();
  dn.block<3, 3>(0, 0) = -crossMatrix(s[1]);
  dn.block<3, 3>(0, 3) = crossMatrix(s[0]);
  std::array<SumJacobian, 2> dm;
  for (int alpha = 0; alpha < 2; ++alpha) {
    dm[alpha].setZero();
    dm[alpha].block<3, 3>(0, 0) = -crossMatrix(s[3 + alpha]);
    dm[alpha].block<3, 3>(0, 3) = crossMatrix(s[2 + alpha]);
    dm[alpha].block<3, 3>(0, 3 * (2 + alpha)) = -crossMatrix(s[1]);
    dm[alpha].block<3, 3>(0, 3 * (3 + alpha)) = crossMatrix(s[0]);
  }
  const SumJacobian da3 = P_J.lazyProduct(dn);
  std::array<Mat3, 2> dd_dn;  // d a_{3,alpha} / dn
  std::array<SumJacobian, 2> dd;
  for (int alpha = 0; alpha < 2; ++alpha) {
    dd_dn[alpha] = unitNormalHessian(frame.normal_d[alpha], a3, J);
    dd[alpha] = dd_dn[alpha].lazyProduct(dn) + P_J.lazyProduct(dm[alpha]);
  }

  FibreHessian H = FibreHessian::Zero();
  Vec3 u = Vec3::Zero();                                 // dPsi/da_3
  std::array<Vec3, 2> v = {Vec3::Zero(), Vec3::Zero()};  // dPsi/da_{3,alpha}
  Rows X, Y;
  for (int q = fibre.first; q < fibre.last; ++q) {
    const KirchhoffLovePoint& p = points[q];
    const double xi3 = p.xi3(), V = p.referenceVolume();
    const Eigen::Matrix<double, 3, 2>& M = p.elasticLaminaMap();
    const Eigen::Matrix<double, 3, 2> L = frame.laminaBasis(xi3) * M;
    Mat3 psi_cc;
    const HenckyLamina::LaminaResponse r = material.laminaResponse(L.transpose() * L, &psi_cc);
    Eigen::Matrix2d S = r.second_piola;
    if (gauss_newton) {
      S = positivePart<2>(S);
      psi_cc = positivePart<3>(psi_cc);
    }
    const Mat3 w = V * (L * S) * M.transpose();  // dPsi_q/dg_i, as energy()
    u += w.col(2);
    v[0] += xi3 * w.col(0);
    v[1] += xi3 * w.col(1);
    // X: dl_1, dl_2 (g_alpha = a_alpha + xi3 a_{3,alpha}, g_3 = a_3) and dc; Y: V S (x) I dL and
    // V psi_cc dc, so that X^T Y is this point's material part.
    for (int beta = 0; beta < 2; ++beta) {
      auto dl = X.middleRows<3>(3 * beta);
      dl = xi3 * (M(0, beta) * dd[0] + M(1, beta) * dd[1]) + M(2, beta) * da3;
      dl.block<3, 3>(0, 0).diagonal().array() += M(0, beta);
      dl.block<3, 3>(0, 3).diagonal().array() += M(1, beta);
    }
    const auto dl1 = X.topRows<3>(), dl2 = X.middleRows<3>(3);
    X.row(6) = 2.0 * L.col(0).transpose().lazyProduct(dl1);
    X.row(7) = 2.0 * L.col(1).transpose().lazyProduct(dl2);
    X.row(8) = L.col(0).transpose().lazyProduct(dl2) + L.col(1).transpose().lazyProduct(dl1);
    Y.topRows<3>() = V * (S(0, 0) * dl1 + S(0, 1) * dl2);
    Y.middleRows<3>(3) = V * (S(1, 0) * dl1 + S(1, 1) * dl2);
    Y.bottomRows<3>() = (V * psi_cc).lazyProduct(X.bottomRows<3>());
    addUpperProduct(H, X, Y);
  }
  if (gauss_newton) {
    H.triangularView<Eigen::StrictlyLower>() = H.transpose();
    return H;
  }

  // Curvature part, dchi^T F_chichi dchi as X^T Y: F_nn, and F_{n m_alpha} = the Hessian of
  // v_alpha . a_3 in n (F_mm = 0).
  Mat3 F_nn = unitNormalHessian(u, a3, J);
  for (int alpha = 0; alpha < 2; ++alpha)
    F_nn += normalDerivativeHessian(v[alpha], frame.normal_d[alpha], a3, J);
  X << dn, dm[0], dm[1];
  Y.topRows<3>() = F_nn.lazyProduct(dn);
  for (int alpha = 0; alpha < 2; ++alpha) {
    const Mat3 F_nm = unitNormalHessian(v[alpha], a3, J);
    Y.topRows<3>() += F_nm.lazyProduct(dm[alpha]);
    Y.middleRows<3>(3 + 3 * alpha) = F_nm.lazyProduct(dn);
  }
  addUpperProduct(H, X, Y);
  H.triangularView<Eigen::StrictlyLower>() = H.transpose();
  // dF/dchi . d^2 chi / ds^2: dF/dn = P u / J + sum_alpha (d a_{3,alpha}/dn) v_alpha,
  // dF/dm_alpha = P v_alpha / J.
  Vec3 adj_n = P_J * u;
  for (int alpha = 0; alpha < 2; ++alpha) {
    adj_n += dd_dn[alpha] * v[alpha];
    const Vec3 adj_m = P_J * v[alpha];  // m_alpha = s_{2+alpha} x s_1 + s_0 x s_{3+alpha}
    addCrossHessian(H, adj_m, 2 + alpha, 1);
    addCrossHessian(H, adj_m, 0, 3 + alpha);
  }
  addCrossHessian(H, adj_n, 0, 1);  // n = s_0 x s_1
  return H;
}

}  // namespace

FibreHessian fibreHessian(const std::vector<KirchhoffLovePoint>& points, const FibreRange& fibre,
                          const HenckyLamina& material, const StencilSums& s) {
  return fibreHessianIn(points, fibre, material, s, false);
}

FibreHessian projectedFibreHessian(const std::vector<KirchhoffLovePoint>& points,
                                   const FibreRange& fibre, const HenckyLamina& material,
                                   const StencilSums& s) {
  const FibreHessian H = fibreHessian(points, fibre, material, s);
  // Most fibres are already positive semidefinite (three zero modes: the sums' rigid rotation);
  // the inertia of a pivoted LDL^T tells. Pivots below -1e-6 of the largest count as negative:
  // the zero modes' rounding and barely indefinite fibres stay as they are.
  const Eigen::LDLT<FibreHessian> ldlt(H);
  const auto& d = ldlt.vectorD();
  if (ldlt.info() == Eigen::Success && d.minCoeff() >= -1e-6 * d.cwiseAbs().maxCoeff()) return H;
  return fibreHessianIn(points, fibre, material, s, true);
}

}  // namespace chs
