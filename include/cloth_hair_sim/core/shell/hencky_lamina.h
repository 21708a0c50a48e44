#pragma once
#include <limits>

#include <Eigen/Core>

namespace chs {

// Isotropic lamina model quadratic in the Hencky strain of the lamina, Han (5.11):
//   psi = mu eps_ab eps_ab + lambda/2 (eps_dd)^2,  eps = 1/2 log(C_hat),
// with C_hat the 2x2 lamina block of C = F^T F in an orthonormal reference lamina/fibre frame
// (e_1, e_2 tangent to the reference mid-surface, e_3 its unit normal). Han writes the frame as
// a-bar_i; we orthonormalise it so that "isotropic in the lamina" has its usual meaning.
//
// Lame parameters: the Kirchhoff-Love kinematics have no transverse normal strain, so the lamina
// is in plane stress and the 2D energy must use the plane-stress Lame parameters
//   mu = E / (2 (1 + nu)),  lambda = E nu / (1 - nu^2)   (= 2 mu lambda_3D / (lambda_3D + 2 mu)).
// Then cylindrical bending (eps_11 = xi3 kappa, eps_22 = 0) integrates to (mu + lambda/2) kappa^2
// tau^3 / 12 = D kappa^2 / 2 with the plate stiffness D = E tau^3 / (12 (1 - nu^2)), and uniaxial
// stress gives Young's modulus E. The 3D lambda would overestimate D by (1-nu)^2/(1-2nu)
// (1.225 at nu = 0.3).
//
// Denting (Han 5.3.2): von Mises yield on the Kirchhoff stress, f_vM = |dev tau|_F <= c_vM
// (5.13); c_vM is Han's threshold on the Frobenius norm of the deviator (uniaxial yield stress
// sqrt(3/2) c_vM). An infinite c_vM (the default) is purely elastic; c_vM <= 0 is rejected.
class HenckyLamina {
 public:
  HenckyLamina(double youngs_modulus, double poisson_ratio,
               double yield_stress = std::numeric_limits<double>::infinity());

  double youngsModulus() const { return E_; }
  double poissonRatio() const { return nu_; }
  double mu() const { return mu_; }
  double lambda() const { return lambda_; }
  double yieldStress() const { return c_vm_; }
  bool isElastic() const { return c_vm_ == std::numeric_limits<double>::infinity(); }
  // D = E tau^3 / (12 (1 - nu^2)) for a shell of thickness tau.
  double bendingStiffness(double thickness) const;

  // All functions below take the lamina-frame deformation F (3x3, world components) and the
  // reference lamina/fibre frame (columns e_1, e_2, e_3, orthonormal, e_3 the reference normal).
  double energyDensity(const Eigen::Matrix3d& F, const Eigen::Matrix3d& frame) const;
  // First Piola-Kirchhoff stress dpsi/dF = F S with S = C_hat^{-1} (2 mu eps^R + lambda tr eps^R)
  // on the lamina block: exact for any F. For Kirchhoff-Love F (F e_3 the unit normal of the
  // deformed lamina) it equals tau F^{-T}.
  Eigen::Matrix3d firstPiolaStress(const Eigen::Matrix3d& F, const Eigen::Matrix3d& frame) const;
  // The lamina's response to its stretch tensor C_hat = E^T F^T F E (2x2, E = frame's first two
  // columns): psi and the second Piola-Kirchhoff stress S = 2 dpsi/dC_hat = C_hat^{-1} (2 mu
  // eps^R + lambda tr eps^R), so that P = F E S E^T. One closed-form spectral decomposition
  // gives both (the Kirchhoff-Love forces need both at every quadrature point). With hessian, also
  // the material tangent for an implicit step: the second derivatives of psi in the independent
  // components c = (C_11, C_22, C_12) of C_hat (C_21 = C_12), so that dpsi/dc = (S_11 / 2,
  // S_22 / 2, S_12).
  struct LaminaResponse {
    double energy_density;
    Eigen::Matrix2d second_piola;
  };
  LaminaResponse laminaResponse(const Eigen::Matrix2d& C_hat,
                                Eigen::Matrix3d* hessian = nullptr) const;
  // Kirchhoff stress (5.12)/(A.2): tau = tau_ab q_a (x) q_b, tau_ab = 2 mu eps^L_ab + lambda
  // eps^L_gg delta_ab, from the QR decomposition F e_j = r_ij q_i and eps^L = 1/2 log(r r^T).
  Eigen::Matrix3d kirchhoffStress(const Eigen::Matrix3d& F, const Eigen::Matrix3d& frame) const;

  // Principal Kirchhoff stresses from the principal log stretches of the lamina, (5.16)-(5.17).
  Eigen::Vector2d principalStress(const Eigen::Vector2d& log_stretch) const;
  // Its inverse, (5.19).
  Eigen::Vector2d principalLogStretch(const Eigen::Vector2d& principal_stress) const;
  // f_vM of a plane stress state (tau_1, tau_2, 0), (5.14).
  static double vonMises(const Eigen::Vector2d& principal_stress);

  // Associative return of a trial principal stress onto the ellipse f_vM = c_vM in the
  // (tau_1, tau_2) plane (Han 5.3.2.1, A.7). The plastic log strain increment is parallel to the
  // yield normal, so the stress returns along A n with the constant plane-stress elasticity
  // A = [[2mu+lambda, lambda], [lambda, 2mu+lambda]]: tau = (I + kappa A grad(f^2))^{-1} tau_tr.
  // A and the ellipse share their axes (1,1) and (1,-1), so kappa solves a scalar equation.
  // Han replaces the ellipse by a diamond (A.7); we project onto the exact ellipse.
  // Trial states inside (or an elastic material) are returned unchanged.
  Eigen::Vector2d projectPrincipalStress(const Eigen::Vector2d& trial_stress) const;

  struct DentingReturn {
    Eigen::Matrix3d elastic_deformation;  // F^{KL,E} after the return, (5.20)/(A.37)
    Eigen::Vector2d trial_stress;         // principal tau^tr, (5.16)-(5.17)
    Eigen::Vector2d stress;               // projected principal tau
    bool yielded = false;
  };
  // Von Mises denting return mapping (5.13)-(5.20) of a trial elastic deformation: QR in the
  // reference frame, SVD r_hat = U Sigma V^T, project the principal stresses, rebuild r_hat with
  // the same U and V. The caller sets F^{KL,P} = (F^{KL,E})^{-1} F^{KL} to keep (5.15).
  DentingReturn returnMapping(const Eigen::Matrix3d& F_elastic_trial,
                              const Eigen::Matrix3d& frame) const;

 private:
  double E_, nu_, mu_, lambda_, c_vm_;
};

}  // namespace chs
