#include "cloth_hair_sim/core/shell/midsurface_frame.h"

#include <Eigen/Geometry>

namespace chs {
namespace {

// dPsi/d of the five stencil sums: dPsi/dx_k is their combination with the stencil's du, dv,
// duu, duv, dvv weights.
using StencilAdjoint = StencilSums;

// Adjoints accumulated from a_3 and a_{3,alpha} back to a_alpha, a_{alpha,beta}, given dPsi/da_i
// (columns of dpsi_da) and dPsi/da_{3,alpha} (columns of dpsi_da3d).
StencilAdjoint stencilAdjoint(const MidSurfaceFrame& f, const Eigen::Matrix3d& dpsi_da,
                              const Eigen::Matrix<double, 3, 2>& dpsi_da3d) {
  const Eigen::Vector3d& a3 = f.a3;
  Eigen::Vector3d adj_a1 = dpsi_da.col(0), adj_a2 = dpsi_da.col(1), adj_a3 = dpsi_da.col(2);
  double adj_J = 0.0;
  std::array<Eigen::Vector3d, 2> adj_m;  // of n_{,alpha}
  const double J = f.area_ratio;
  for (int alpha = 0; alpha < 2; ++alpha) {
    // a_{3,alpha} = a~ - a_3 (a_3 . a~), a~ = n_{,alpha} / J.
    const Eigen::Vector3d adj_a3d = dpsi_da3d.col(alpha);
    const Eigen::Vector3d a_tilde = f.normal_d[alpha] / J;
    const Eigen::Vector3d adj_a_tilde = adj_a3d - a3 * a3.dot(adj_a3d);
    adj_a3 -= a3.dot(a_tilde) * adj_a3d + a3.dot(adj_a3d) * a_tilde;
    adj_m[alpha] = adj_a_tilde / J;
    adj_J -= a_tilde.dot(adj_a_tilde) / J;
  }
  // a_3 = n / J, J = |n|.
  adj_J -= a3.dot(adj_a3) / J;
  const Eigen::Vector3d adj_n = adj_a3 / J + adj_J * a3;
  // n = a_1 x a_2; n_{,alpha} = a_{1,alpha} x a_2 + a_1 x a_{2,alpha}.
  StencilAdjoint adj;
  adj[0] = adj_a1 + f.a[1].cross(adj_n);
  adj[1] = adj_a2 + adj_n.cross(f.a[0]);
  adj[2].setZero();
  adj[3].setZero();
  adj[4].setZero();
  for (int alpha = 0; alpha < 2; ++alpha) {
    const Eigen::Vector3d& a1_alpha = f.a_uv[alpha];
    const Eigen::Vector3d& a2_alpha = f.a_uv[alpha + 1];
    adj[2 + alpha] += f.a[1].cross(adj_m[alpha]);
    adj[1] += adj_m[alpha].cross(a1_alpha);
    adj[0] += a2_alpha.cross(adj_m[alpha]);
    adj[3 + alpha] += adj_m[alpha].cross(f.a[0]);
  }
  return adj;
}

Eigen::Vector3d stencilGradient(const SurfaceStencil& s, int k, const StencilAdjoint& adj) {
  return s.du[k] * adj[0] + s.dv[k] * adj[1] + s.duu[k] * adj[2] + s.duv[k] * adj[3] +
         s.dvv[k] * adj[4];
}

}  // namespace

StencilSums MidSurfaceFrame::sums(const SurfaceStencil& stencil,
                                  const std::vector<Eigen::Vector3d>& x) {
  // One pass over the stencil for all five sums.
  StencilSums s;
  for (auto& v : s) v.setZero();
  for (int k = 0; k < stencil.size(); ++k) {
    const Eigen::Vector3d& xk = x[stencil.points[k]];
    s[0] += stencil.du[k] * xk;
    s[1] += stencil.dv[k] * xk;
    s[2] += stencil.duu[k] * xk;
    s[3] += stencil.duv[k] * xk;
    s[4] += stencil.dvv[k] * xk;
  }
  return s;
}

MidSurfaceFrame MidSurfaceFrame::evaluate(const SurfaceStencil& stencil,
                                          const std::vector<Eigen::Vector3d>& x) {
  return fromSums(sums(stencil, x));
}

MidSurfaceFrame MidSurfaceFrame::fromSums(const StencilSums& s) {
  MidSurfaceFrame f;
  const Eigen::Vector3d &a1 = s[0], &a2 = s[1];
  f.a = {a1, a2};
  f.a_uv = {s[2], s[3], s[4]};
  f.normal = a1.cross(a2);
  f.area_ratio = f.normal.norm();
  f.a3 = f.normal / f.area_ratio;
  for (int alpha = 0; alpha < 2; ++alpha) {
    // d(a_1 x a_2)/d xi_alpha = a_{1,alpha} x a_2 + a_1 x a_{2,alpha}, Han (A.1).
    f.normal_d[alpha] = f.a_uv[alpha].cross(a2) + a1.cross(f.a_uv[alpha + 1]);
    const Eigen::Vector3d a_tilde = f.normal_d[alpha] / f.area_ratio;
    f.a3_d[alpha] = a_tilde - f.a3 * f.a3.dot(a_tilde);  // projection keeps a_3 unit
  }
  return f;
}

Eigen::Matrix3d MidSurfaceFrame::laminaBasis(double xi3) const {
  Eigen::Matrix3d g;
  g.col(0) = a[0] + xi3 * a3_d[0];
  g.col(1) = a[1] + xi3 * a3_d[1];
  g.col(2) = a3;
  return g;
}

void MidSurfaceFrame::pullBack(const SurfaceStencil& stencil, double xi3,
                               const Eigen::Matrix3d& dpsi_dg,
                               std::vector<Eigen::Vector3d>& dpsi_dx) const {
  const StencilAdjoint adj = stencilAdjoint(*this, dpsi_dg, xi3 * dpsi_dg.leftCols<2>());
  dpsi_dx.resize(stencil.size());
  for (int k = 0; k < stencil.size(); ++k) dpsi_dx[k] = stencilGradient(stencil, k, adj);
}

void MidSurfaceFrame::addPullBack(const SurfaceStencil& stencil, const Eigen::Matrix3d& dpsi_da,
                                  const Eigen::Matrix<double, 3, 2>& dpsi_da3d,
                                  std::vector<Eigen::Vector3d>& gradient) const {
  const StencilAdjoint adj = stencilAdjoint(*this, dpsi_da, dpsi_da3d);
  for (int k = 0; k < stencil.size(); ++k)
    gradient[stencil.points[k]] += stencilGradient(stencil, k, adj);
}

StencilSums MidSurfaceFrame::sumAdjoint(const Eigen::Matrix3d& dpsi_da,
                                        const Eigen::Matrix<double, 3, 2>& dpsi_da3d) const {
  return stencilAdjoint(*this, dpsi_da, dpsi_da3d);
}

}  // namespace chs
