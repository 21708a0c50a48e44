#pragma once
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "cloth_hair_sim/core/shell/hencky_lamina.h"
#include "cloth_hair_sim/core/shell/midsurface_frame.h"
#include "cloth_hair_sim/core/subdiv/surface_stencil.h"

namespace chs {

// One Kirchhoff-Love quadrature point, Han's type (iv) (5.5): a point at height xi3 in the fibre
// through the mid-surface point (u, v) of a control-mesh face. It carries the reference
// contravariant basis g-bar^i, the volume V_q^0 and the plastic state F^{KL,P}, and contributes
// V_q^0 psi(F^{KL,E,tr}) to the Kirchhoff-Love energy (5.31).
class KirchhoffLovePoint {
 public:
  // weight = parametric area weight x thickness weight (xi3 measures length, so the thickness
  // weights sum to the thickness). The points of one fibre (same face and (u, v), different
  // xi3) should share one stencil object: sums over points then evaluate the mid-surface once
  // per fibre (see sharesFibreWith). Throws InputError for a null or malformed stencil, a
  // degenerate reference surface or a height beyond the reference radius of curvature.
  KirchhoffLovePoint(std::shared_ptr<const SurfaceStencil> stencil, int face,
                     const Eigen::Vector2d& parameter, double xi3, double weight,
                     const std::vector<Eigen::Vector3d>& reference_positions);

  const SurfaceStencil& stencil() const { return *stencil_; }
  // Whether both points lie on one fibre through the same stencil object.
  bool sharesFibreWith(const KirchhoffLovePoint& other) const { return stencil_ == other.stencil_; }
  int face() const { return face_; }
  const Eigen::Vector2d& parameter() const { return parameter_; }
  double xi3() const { return xi3_; }
  // V_q^0 = |det d r-bar / d xi| x weight.
  double referenceVolume() const { return volume_; }
  // Rows g-bar^1, g-bar^2, g-bar^3 = a-bar_3 (the inverse of [g-bar_1 g-bar_2 g-bar_3]).
  const Eigen::Matrix3d& referenceContravariantBasis() const { return contravariant_; }
  // Orthonormal reference lamina/fibre frame: columns e_1 = a-bar_1/|a-bar_1|, e_2, e_3 = a-bar_3.
  const Eigen::Matrix3d& laminaFrame() const { return frame_; }
  const Eigen::Matrix3d& plasticDeformation() const { return plastic_; }
  // M with F^{KL,E,tr} e_alpha = [g_1 g_2 g_3] M e_alpha (3 x 2): g-bar^i (F^{KL,P})^{-1} e_alpha.
  const Eigen::Matrix<double, 3, 2>& elasticLaminaMap() const { return elastic_lamina_map_; }
  // Restores a plastic state saved from plasticDeformation() (rolling back a step).
  void setPlasticDeformation(const Eigen::Matrix3d& plastic);

  // F^KL = g_i (x) g-bar^i (5.34) of the current control positions x.
  Eigen::Matrix3d deformationGradient(const std::vector<Eigen::Vector3d>& x) const;
  // F^{KL,E,tr} = F^KL (F^{KL,P})^{-1} (5.35).
  Eigen::Matrix3d trialElasticDeformation(const std::vector<Eigen::Vector3d>& x) const;

  // V_q^0 psi(F^{KL,E,tr}).
  double energy(const HenckyLamina& material, const std::vector<Eigen::Vector3d>& x) const;
  // The energy and its gradient dPsi_q/dx_{stencil.points[k]} written to dpsi_dx[k] (resized to
  // the stencil); the generalized force (5.32)-(5.36) on those control points is -dpsi_dx[k].
  double energyAndGradient(const HenckyLamina& material, const std::vector<Eigen::Vector3d>& x,
                           std::vector<Eigen::Vector3d>& dpsi_dx) const;
  // V_q^0 psi at this height of the current mid-surface frame of this point's stencil, and with
  // dpsi_dg the derivative dPsi_q/dg_i (columns) for MidSurfaceFrame's pull-backs. Sums over the
  // points of one fibre share the frame.
  double energy(const HenckyLamina& material, const MidSurfaceFrame& current,
                Eigen::Matrix3d* dpsi_dg = nullptr) const;

  // End-of-step plasticity (Han 5.5.5): von Mises denting return of F^{KL,E,tr}, then
  // F^{KL,P} = (F^{KL,E})^{-1} F^KL so that F^{KL,E} F^{KL,P} = F^KL (5.15). Returns whether the
  // point yielded.
  bool updatePlasticity(const HenckyLamina& material, const std::vector<Eigen::Vector3d>& x);

 private:
  void updateElasticLaminaMap();

  std::shared_ptr<const SurfaceStencil> stencil_;
  int face_;
  Eigen::Vector2d parameter_;
  double xi3_, volume_;
  Eigen::Matrix3d contravariant_, frame_;
  Eigen::Matrix3d plastic_ = Eigen::Matrix3d::Identity();
  Eigen::Matrix3d plastic_inverse_ = Eigen::Matrix3d::Identity();
  // g-bar^i (F^{KL,P})^{-1} e_alpha: the lamina vectors of F^{KL,E,tr} are [g_1 g_2 g_3] times
  // this (F^{KL,E,tr} e_alpha, (5.34)-(5.35)), a product that only changes with the plastic state.
  Eigen::Matrix<double, 3, 2> elastic_lamina_map_;
};

}  // namespace chs
