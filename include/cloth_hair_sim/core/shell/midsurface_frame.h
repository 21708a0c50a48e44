#pragma once
#include <array>
#include <vector>

#include <Eigen/Core>

#include "cloth_hair_sim/core/subdiv/surface_stencil.h"

namespace chs {

// Mid-surface geometry at one parameter point of a subdivision surface, Han (5.3) and (A.1):
// tangents a_alpha, second derivatives a_{alpha,beta}, unit normal a_3 = a_1 x a_2 / |a_1 x a_2|
// and its derivatives a_{3,alpha} = (I - a_3 a_3) (a_{1,alpha} x a_2 + a_1 x a_{2,alpha}) / |.|.
// The lamina basis at height xi3 is g_alpha = a_alpha + xi3 a_{3,alpha}, g_3 = a_3.
// The five stencil sums a_1, a_2, a_{1,1}, a_{1,2}, a_{2,2} (in this order) that a frame depends
// on, each linear in the control positions (sum_k du[k] x_k, ...); or adjoints dPsi/d of them.
using StencilSums = std::array<Eigen::Vector3d, 5>;

struct MidSurfaceFrame {
  std::array<Eigen::Vector3d, 2> a;         // a_1, a_2
  std::array<Eigen::Vector3d, 3> a_uv;      // a_{1,1}, a_{1,2} = a_{2,1}, a_{2,2}
  Eigen::Vector3d normal;                   // a_1 x a_2 (unnormalised)
  std::array<Eigen::Vector3d, 2> normal_d;  // (a_1 x a_2)_{,alpha}, Han (A.1)
  double area_ratio = 0.0;                  // |a_1 x a_2|
  Eigen::Vector3d a3;
  std::array<Eigen::Vector3d, 2> a3_d;  // a_{3,alpha}

  static MidSurfaceFrame evaluate(const SurfaceStencil& stencil,
                                  const std::vector<Eigen::Vector3d>& x);
  static StencilSums sums(const SurfaceStencil& stencil, const std::vector<Eigen::Vector3d>& x);
  static MidSurfaceFrame fromSums(const StencilSums& s);

  // Columns g_1, g_2, g_3 at height xi3.
  Eigen::Matrix3d laminaBasis(double xi3) const;

  // Reverse-mode chain rule through the normal: given dPsi/dg_i (columns of dpsi_dg) at height
  // xi3, writes dPsi/dx_k for each stencil position k into dpsi_dx (resized to the stencil).
  // Exact, including the second derivatives that enter through a_{3,alpha}.
  void pullBack(const SurfaceStencil& stencil, double xi3, const Eigen::Matrix3d& dpsi_dg,
                std::vector<Eigen::Vector3d>& dpsi_dx) const;

  // The same for lamina points at several heights of this fibre at once, summed (the chain rule
  // is linear in the adjoints): columns of dpsi_da are dPsi/da_1, dPsi/da_2, dPsi/da_3 (the sums
  // of dPsi/dg_i over the heights), columns of dpsi_da3d are dPsi/da_{3,alpha} (the sums of
  // xi3 dPsi/dg_alpha). Adds dPsi/dx_k to gradient[stencil.points[k]].
  void addPullBack(const SurfaceStencil& stencil, const Eigen::Matrix3d& dpsi_da,
                   const Eigen::Matrix<double, 3, 2>& dpsi_da3d,
                   std::vector<Eigen::Vector3d>& gradient) const;
  // The chain rule as far as the stencil sums: dPsi/d(a_1, a_2, a_{1,1}, a_{1,2}, a_{2,2}).
  StencilSums sumAdjoint(const Eigen::Matrix3d& dpsi_da,
                         const Eigen::Matrix<double, 3, 2>& dpsi_da3d) const;
};

}  // namespace chs
