#include "cloth_hair_sim/core/shell/kirchhoff_love_hessian.h"

#include <algorithm>
#include <cmath>

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

FibreHessian projectedFibreHessian(const std::vector<KirchhoffLovePoint>& points,
                                   const FibreRange& fibre, const HenckyLamina& material,
                                   const StencilSums& s) {
  StencilSums g0, g1;
  fibreEnergy(points, fibre, material, s, &g0);
  FibreHessian H;
  for (int a = 0; a < 5; ++a) {
    // Step relative to the sum's own size (a_alpha ~ the face size, a_{alpha,beta} may vanish on
    // a flat sheet: then the tangents' size sets the scale).
    const double h = 1e-7 * std::max({s[a].norm(), s[0].norm(), s[1].norm()});
    for (int i = 0; i < 3; ++i) {
      StencilSums t = s;
      t[a][i] += h;
      fibreEnergy(points, fibre, material, t, &g1);
      for (int b = 0; b < 5; ++b) H.block<3, 1>(3 * b, 3 * a + i) = (g1[b] - g0[b]) / h;
    }
  }
  H = 0.5 * (H + H.transpose()).eval();
  // Most fibres are already positive semidefinite (three zero modes: the sums' rigid rotation);
  // the inertia of a pivoted LDL^T tells, ~10 times cheaper than the eigen-decomposition that
  // the others need. Pivots below -1e-6 of the largest count as negative: the differences' noise
  // is smaller.
  const Eigen::LDLT<FibreHessian> ldlt(H);
  const auto& d = ldlt.vectorD();
  if (ldlt.info() == Eigen::Success && d.minCoeff() >= -1e-6 * d.cwiseAbs().maxCoeff()) return H;
  Eigen::SelfAdjointEigenSolver<FibreHessian> eig(H);
  const Eigen::Matrix<double, 15, 1> lambda = eig.eigenvalues().cwiseMax(0.0);
  return eig.eigenvectors() * lambda.asDiagonal() * eig.eigenvectors().transpose();
}

}  // namespace chs
