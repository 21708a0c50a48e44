#pragma once
#include <vector>

#include <Eigen/Core>

#include "cloth_hair_sim/core/shell/hencky_lamina.h"
#include "cloth_hair_sim/core/shell/kirchhoff_love_point.h"
#include "cloth_hair_sim/core/shell/midsurface_frame.h"

namespace chs {

// Second derivatives of the Kirchhoff-Love energy (5.31) for an implicit step. A fibre (the
// quadrature points through the thickness at one (u, v), sharing a stencil) depends on the control
// points only through its five stencil sums s = (a_1, a_2, a_{1,1}, a_{1,2}, a_{2,2})
// (MidSurfaceFrame), each linear in them, so its Hessian in the control points is J^T H_s J with
// H_s the 15 x 15 Hessian in the sums and J the stencil's weights.
//
// H_s is exact and in closed form: the Hencky lamina's tangent in C (HenckyLamina::laminaResponse)
// through the lamina vectors, and the normal's second derivatives through n = a_1 x a_2 and
// n_{,alpha} (A.1), computed once for the fibre's points. It replaced forward differences of the
// gradient in s (16 gradients per fibre, ~1e-7 accurate): half the time, and no step to choose.
using FibreHessian = Eigen::Matrix<double, 15, 15>;  // index 3 a + i: sum a, component i

struct FibreRange {
  int first = 0, last = 0;  // quadrature points [first, last) of one fibre
};

// The fibres of a point list built by buildKirchhoffLovePoints (consecutive points that share a
// stencil object).
std::vector<FibreRange> fibreRanges(const std::vector<KirchhoffLovePoint>& points);

// Energy of one fibre at the sums s, and its gradient dPsi/ds if asked.
double fibreEnergy(const std::vector<KirchhoffLovePoint>& points, const FibreRange& fibre,
                   const HenckyLamina& material, const StencilSums& s,
                   StencilSums* gradient = nullptr);

// The fibre's Hessian in its sums, d^2 Psi / ds^2 (indefinite where the lamina is compressed or
// the normal's curvature terms dominate).
FibreHessian fibreHessian(const std::vector<KirchhoffLovePoint>& points, const FibreRange& fibre,
                          const HenckyLamina& material, const StencilSums& s);

// fibreHessian where it is positive semidefinite; elsewhere (a compressed membrane, a bent
// lamina beyond its inflection: a Newton matrix with it need not give a descent direction) its
// Gauss-Newton form, the material part sum_q V dL^T (S+ (x) I + dc^T psi_cc+ dc) dL with the
// stress and the lamina tangent clamped to their positive parts and the curvature part (the
// normal's second derivatives weighted by the stresses) left out: positive semidefinite by
// construction, as the strands' solve does (rod/strand_newton_solver.cpp). It replaced clamping
// the negative eigenvalues of the 15 x 15 Hessian (as IPC and HOT project per element), whose
// eigensolves made the assembly of the cloth resting on a sphere 1.6-1.9 x as long for the same
// Newton iterations (docs/BENCHMARKS.md, 2026-12-07).
FibreHessian projectedFibreHessian(const std::vector<KirchhoffLovePoint>& points,
                                   const FibreRange& fibre, const HenckyLamina& material,
                                   const StencilSums& s);

}  // namespace chs
