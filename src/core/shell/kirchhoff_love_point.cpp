#include "cloth_hair_sim/core/shell/kirchhoff_love_point.h"

#include <cmath>
#include <string>
#include <utility>

#include <Eigen/Geometry>
#include <Eigen/LU>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/shell/midsurface_frame.h"

namespace chs {
namespace {

std::string where(int face, const Eigen::Vector2d& uv) {
  return "face " + std::to_string(face) + " at (u, v) = (" + std::to_string(uv(0)) + ", " +
         std::to_string(uv(1)) + ")";
}

void checkStencil(const SurfaceStencil& s, int face, const Eigen::Vector2d& uv, std::size_t n) {
  const std::size_t k = s.points.size();
  if (k == 0 || s.w.size() != k || s.du.size() != k || s.dv.size() != k || s.duu.size() != k ||
      s.duv.size() != k || s.dvv.size() != k)
    throw InputError("KirchhoffLovePoint: stencil of " + where(face, uv) +
                     " has empty or mismatched weight arrays");
  for (int p : s.points)
    if (p < 0 || static_cast<std::size_t>(p) >= n)
      throw InputError("KirchhoffLovePoint: stencil of " + where(face, uv) +
                       " names control point " + std::to_string(p) + " of " + std::to_string(n));
}

}  // namespace

KirchhoffLovePoint::KirchhoffLovePoint(SurfaceStencil stencil, int face,
                                       const Eigen::Vector2d& parameter, double xi3, double weight,
                                       const std::vector<Eigen::Vector3d>& reference_positions)
    : stencil_(std::move(stencil)), face_(face), parameter_(parameter), xi3_(xi3) {
  checkStencil(stencil_, face, parameter, reference_positions.size());
  if (!std::isfinite(weight) || weight <= 0.0 || !std::isfinite(xi3))
    throw InputError("KirchhoffLovePoint: quadrature weight must be positive at " +
                     where(face, parameter));
  const MidSurfaceFrame ref = MidSurfaceFrame::evaluate(stencil_, reference_positions);
  if (!(ref.area_ratio > 1e-12 * ref.a[0].norm() * ref.a[1].norm()))
    throw InputError("KirchhoffLovePoint: degenerate reference surface (a_1 x a_2 = 0) at " +
                     where(face, parameter));
  const Eigen::Matrix3d g_bar = ref.laminaBasis(xi3);
  const double det = g_bar.determinant();
  // det <= 0: the fibre height xi3 exceeds the radius of curvature and the shell folds over.
  if (!(det > 0.0))
    throw InputError("KirchhoffLovePoint: lamina at xi3 = " + std::to_string(xi3) +
                     " folds over (thickness beyond the radius of curvature) at " +
                     where(face, parameter));
  contravariant_ = g_bar.inverse();
  volume_ = det * weight;
  frame_.col(0) = ref.a[0].normalized();
  frame_.col(2) = ref.a3;
  frame_.col(1) = ref.a3.cross(frame_.col(0));
}

Eigen::Matrix3d KirchhoffLovePoint::deformationGradient(
    const std::vector<Eigen::Vector3d>& x) const {
  return MidSurfaceFrame::evaluate(stencil_, x).laminaBasis(xi3_) * contravariant_;
}

Eigen::Matrix3d KirchhoffLovePoint::trialElasticDeformation(
    const std::vector<Eigen::Vector3d>& x) const {
  return deformationGradient(x) * plastic_inverse_;
}

double KirchhoffLovePoint::energy(const HenckyLamina& material,
                                  const std::vector<Eigen::Vector3d>& x) const {
  return volume_ * material.energyDensity(trialElasticDeformation(x), frame_);
}

double KirchhoffLovePoint::energyAndGradient(const HenckyLamina& material,
                                             const std::vector<Eigen::Vector3d>& x,
                                             std::vector<Eigen::Vector3d>& dpsi_dx) const {
  const MidSurfaceFrame cur = MidSurfaceFrame::evaluate(stencil_, x);
  const Eigen::Matrix3d F_elastic = cur.laminaBasis(xi3_) * contravariant_ * plastic_inverse_;
  // dPsi/dF^KL = V P(F^{KL,E,tr}) F^{KL,P,-T} (5.36); F^KL = G g-bar^i gives dPsi/dG = .
  // g-bar^{-T}.
  const Eigen::Matrix3d dpsi_dg = volume_ * material.firstPiolaStress(F_elastic, frame_) *
                                  plastic_inverse_.transpose() * contravariant_.transpose();
  cur.pullBack(stencil_, xi3_, dpsi_dg, dpsi_dx);
  return volume_ * material.energyDensity(F_elastic, frame_);
}

bool KirchhoffLovePoint::updatePlasticity(const HenckyLamina& material,
                                          const std::vector<Eigen::Vector3d>& x) {
  if (material.isElastic()) return false;
  const Eigen::Matrix3d F = deformationGradient(x);
  const HenckyLamina::DentingReturn ret = material.returnMapping(F * plastic_inverse_, frame_);
  if (!ret.yielded) return false;
  plastic_ = ret.elastic_deformation.inverse() * F;
  plastic_inverse_ = plastic_.inverse();
  return true;
}

}  // namespace chs
