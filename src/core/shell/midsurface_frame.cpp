#include "cloth_hair_sim/core/shell/midsurface_frame.h"

#include <Eigen/Geometry>

namespace chs {
namespace {

// d(a_1 x a_2)/d xi_alpha = a_{1,alpha} x a_2 + a_1 x a_{2,alpha}, Han (A.1).
Eigen::Vector3d normalDerivative(const MidSurfaceFrame& f, int alpha) {
  const Eigen::Vector3d& a1_alpha = f.a_uv[alpha];      // a_{1,1} or a_{1,2}
  const Eigen::Vector3d& a2_alpha = f.a_uv[alpha + 1];  // a_{2,1} or a_{2,2}
  return a1_alpha.cross(f.a[1]) + f.a[0].cross(a2_alpha);
}

}  // namespace

MidSurfaceFrame MidSurfaceFrame::evaluate(const SurfaceStencil& stencil,
                                          const std::vector<Eigen::Vector3d>& x) {
  MidSurfaceFrame f;
  f.a[0] = stencil.combine(stencil.du, x);
  f.a[1] = stencil.combine(stencil.dv, x);
  f.a_uv[0] = stencil.combine(stencil.duu, x);
  f.a_uv[1] = stencil.combine(stencil.duv, x);
  f.a_uv[2] = stencil.combine(stencil.dvv, x);
  f.normal = f.a[0].cross(f.a[1]);
  f.area_ratio = f.normal.norm();
  f.a3 = f.normal / f.area_ratio;
  for (int alpha = 0; alpha < 2; ++alpha) {
    const Eigen::Vector3d a_tilde = normalDerivative(f, alpha) / f.area_ratio;
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
  // Adjoints (dPsi/d of each intermediate), accumulated from g_i back to a_alpha, a_{alpha,beta}.
  std::array<Eigen::Vector3d, 2> adj_a = {dpsi_dg.col(0), dpsi_dg.col(1)};
  std::array<Eigen::Vector3d, 3> adj_a_uv;
  for (auto& v : adj_a_uv) v.setZero();
  Eigen::Vector3d adj_a3 = dpsi_dg.col(2);
  double adj_J = 0.0;
  std::array<Eigen::Vector3d, 2> adj_m;  // of n_{,alpha}
  const double J = area_ratio;
  for (int alpha = 0; alpha < 2; ++alpha) {
    // a_{3,alpha} = a~ - a_3 (a_3 . a~), a~ = n_{,alpha} / J.
    const Eigen::Vector3d adj_a3d = xi3 * dpsi_dg.col(alpha);
    const Eigen::Vector3d m = normalDerivative(*this, alpha);
    const Eigen::Vector3d a_tilde = m / J;
    const Eigen::Vector3d adj_a_tilde = adj_a3d - a3 * a3.dot(adj_a3d);
    adj_a3 -= a3.dot(a_tilde) * adj_a3d + a3.dot(adj_a3d) * a_tilde;
    adj_m[alpha] = adj_a_tilde / J;
    adj_J -= a_tilde.dot(adj_a_tilde) / J;
  }
  // a_3 = n / J, J = |n|.
  adj_J -= a3.dot(adj_a3) / J;
  const Eigen::Vector3d adj_n = adj_a3 / J + adj_J * a3;
  // n = a_1 x a_2; n_{,alpha} = a_{1,alpha} x a_2 + a_1 x a_{2,alpha}.
  adj_a[0] += a[1].cross(adj_n);
  adj_a[1] += adj_n.cross(a[0]);
  for (int alpha = 0; alpha < 2; ++alpha) {
    const Eigen::Vector3d& a1_alpha = a_uv[alpha];
    const Eigen::Vector3d& a2_alpha = a_uv[alpha + 1];
    adj_a_uv[alpha] += a[1].cross(adj_m[alpha]);
    adj_a[1] += adj_m[alpha].cross(a1_alpha);
    adj_a[0] += a2_alpha.cross(adj_m[alpha]);
    adj_a_uv[alpha + 1] += adj_m[alpha].cross(a[0]);
  }
  dpsi_dx.resize(stencil.size());
  for (int k = 0; k < stencil.size(); ++k)
    dpsi_dx[k] = stencil.du[k] * adj_a[0] + stencil.dv[k] * adj_a[1] +
                 stencil.duu[k] * adj_a_uv[0] + stencil.duv[k] * adj_a_uv[1] +
                 stencil.dvv[k] * adj_a_uv[2];
}

}  // namespace chs
