#pragma once
#include <functional>
#include <vector>

#include <Eigen/Core>

#include "cloth_hair_sim/core/shell/hencky_lamina.h"
#include "cloth_hair_sim/core/shell/kirchhoff_love_point.h"
#include "cloth_hair_sim/core/subdiv/surface_stencil.h"

namespace chs {

// Through-thickness rule for the Kirchhoff-Love energy (5.9).
//  - kGauss: 2-point Gauss, xi3 = +-tau / (2 sqrt 3). Integrates xi3^2 exactly (tau^3 / 12), so
//    the small-strain bending energy (quadratic in xi3) is exact: bending stiffness D.
//  - kHanQuarter: Han's xi3 = +-tau/4 (5.4), the midpoint rule on each half. It integrates xi3^2
//    as tau^3 / 16 and so gives 3/4 of the classical bending stiffness.
enum class ThicknessRule { kGauss, kHanQuarter };

struct KirchhoffLoveQuadrature {
  // n x n Gauss-Legendre points on each face's [0,1]^2. On a regular (bicubic) face the
  // small-strain integrands reach degree 6 per direction, so 4 x 4 is exact. 2 x 2 (degree 3)
  // under-integrates but keeps only the 6 rigid zero modes (1 x 1 has spurious ones); against
  // 4 x 4 its 10 softest deformation modes are within 0.1 % (regular sheet) to 0.9 % (near
  // extraordinary vertices), shorter waves two or three faces long soften by up to 4 %
  // (test_shell_kirchhoff_love_modes). It costs 4/9 of 3 x 3: a step of the 90 x 90 sheet takes
  // 12 % less time; the hybrid validation cases move by at most a few tenths of a per cent
  // (docs/VALIDATION.md).
  int in_plane_order = 2;
  ThicknessRule thickness_rule = ThicknessRule::kGauss;
};

// The subdivision basis at (u, v) in [0,1]^2 of a control-mesh face, filled by the caller (e.g.
// from OpenSubdiv's Bfr surfaces).
using FaceStencilFunction = std::function<SurfaceStencil(int face, double u, double v)>;

// Gauss-Legendre nodes and weights on [0, 1] (n >= 1).
void gaussLegendreUnit(int n, std::vector<double>& nodes, std::vector<double>& weights);

// All quadrature points of a shell of the given thickness: per face, in-plane points times
// through-thickness points, with the reference state from reference_positions. Throws InputError
// for a non-positive thickness, order < 1, or a bad stencil/reference (see KirchhoffLovePoint).
std::vector<KirchhoffLovePoint> buildKirchhoffLovePoints(
    int num_faces, const FaceStencilFunction& stencil_at,
    const std::vector<Eigen::Vector3d>& reference_positions, double thickness,
    const KirchhoffLoveQuadrature& rule = {});

// Psi^KL = sum_q V_q^0 psi(F_q^{KL,E,tr}) (5.31). With a gradient, it is resized to x.size() and
// set to dPsi/dx_p (the generalized Kirchhoff-Love force (5.32) is its negative).
double kirchhoffLoveEnergy(const std::vector<KirchhoffLovePoint>& points,
                           const HenckyLamina& material, const std::vector<Eigen::Vector3d>& x,
                           std::vector<Eigen::Vector3d>* gradient = nullptr);

// End-of-step denting update of every point (5.5.5); returns how many yielded.
int updateKirchhoffLovePlasticity(std::vector<KirchhoffLovePoint>& points,
                                  const HenckyLamina& material,
                                  const std::vector<Eigen::Vector3d>& x);

}  // namespace chs
