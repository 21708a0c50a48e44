#include "cloth_hair_sim/core/shell/kirchhoff_love_point.h"

#include <cmath>
#include <string>
#include <utility>

#include <Eigen/Geometry>
#include <Eigen/LU>

#include "cloth_hair_sim/core/common/input_error.h"

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

KirchhoffLovePoint::KirchhoffLovePoint(std::shared_ptr<const SurfaceStencil> stencil, int face,
                                       const Eigen::Vector2d& parameter, double xi3, double weight,
                                       const std::vector<Eigen::Vector3d>& reference_positions)
    : stencil_(std::move(stencil)), face_(face), parameter_(parameter), xi3_(xi3) {
  if (!stencil_) throw InputError("KirchhoffLovePoint: no stencil at " + where(face, parameter));
  checkStencil(*stencil_, face, parameter, reference_positions.size());
  if (!std::isfinite(weight) || weight <= 0.0 || !std::isfinite(xi3))
    throw InputError("KirchhoffLovePoint: quadrature weight must be positive at " +
                     where(face, parameter));
  const MidSurfaceFrame ref = MidSurfaceFrame::evaluate(*stencil_, reference_positions);
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
  updateElasticLaminaMap();
}

void KirchhoffLovePoint::setPlasticDeformation(const Eigen::Matrix3d& plastic) {
  plastic_ = plastic;
  plastic_inverse_ = plastic.inverse();
  updateElasticLaminaMap();
}

void KirchhoffLovePoint::updateElasticLaminaMap() {
  elastic_lamina_map_ = contravariant_ * plastic_inverse_ * frame_.leftCols<2>();
}

Eigen::Matrix3d KirchhoffLovePoint::deformationGradient(
    const std::vector<Eigen::Vector3d>& x) const {
  return MidSurfaceFrame::evaluate(*stencil_, x).laminaBasis(xi3_) * contravariant_;
}

Eigen::Matrix3d KirchhoffLovePoint::trialElasticDeformation(
    const std::vector<Eigen::Vector3d>& x) const {
  return deformationGradient(x) * plastic_inverse_;
}

double KirchhoffLovePoint::energy(const HenckyLamina& material,
                                  const std::vector<Eigen::Vector3d>& x) const {
  return energy(material, MidSurfaceFrame::evaluate(*stencil_, x));
}

double KirchhoffLovePoint::energy(const HenckyLamina& material, const MidSurfaceFrame& current,
                                  Eigen::Matrix3d* dpsi_dg) const {
  const Eigen::Matrix3d g = current.laminaBasis(xi3_);
  const Eigen::Matrix<double, 3, 2> lamina = g * elastic_lamina_map_;  // F^{KL,E,tr} e_alpha
  const HenckyLamina::LaminaResponse r = material.laminaResponse(lamina.transpose() * lamina);
  // dPsi/dF^KL = V P(F^{KL,E,tr}) F^{KL,P,-T} (5.36) with P = F^{KL,E,tr} E S E^T, and F^KL =
  // G g-bar^i, so dPsi/dG = V (lamina S) (elastic lamina map)^T.
  if (dpsi_dg) *dpsi_dg = volume_ * (lamina * r.second_piola) * elastic_lamina_map_.transpose();
  return volume_ * r.energy_density;
}

double KirchhoffLovePoint::energyAndGradient(const HenckyLamina& material,
                                             const std::vector<Eigen::Vector3d>& x,
                                             std::vector<Eigen::Vector3d>& dpsi_dx) const {
  const MidSurfaceFrame cur = MidSurfaceFrame::evaluate(*stencil_, x);
  Eigen::Matrix3d dpsi_dg;
  const double e = energy(material, cur, &dpsi_dg);
  cur.pullBack(*stencil_, xi3_, dpsi_dg, dpsi_dx);
  return e;
}

bool KirchhoffLovePoint::updatePlasticity(const HenckyLamina& material,
                                          const std::vector<Eigen::Vector3d>& x) {
  if (material.isElastic()) return false;
  const Eigen::Matrix3d F = deformationGradient(x);
  const HenckyLamina::DentingReturn ret = material.returnMapping(F * plastic_inverse_, frame_);
  if (!ret.yielded) return false;
  setPlasticDeformation(ret.elastic_deformation.inverse() * F);
  return true;
}

}  // namespace chs
