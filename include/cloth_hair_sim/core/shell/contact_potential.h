#pragma once
#include <Eigen/Core>

namespace chs {

// The continuum frictional contact model of a shell's fibres (Han section 5.3.3-5.3.4): the
// fibre a3^E, carried by a contact particle (type iii) and stretched by the grid motion, is
// split into its part along the deformed mid-surface normal n = a1 x a2 / |a1 x a2|,
// s3 = a3^E . n, and its shear a3S^E = a3^E - s3 n. Compression (s3 < 1) and shear store energy;
// separation (s3 > 1) stores none.
struct ContactMaterial {
  double shear_stiffness = 0.0;   // gamma [Pa], Han (5.21)
  double normal_stiffness = 0.0;  // k^c [Pa], Han (5.22)
  double friction = 0.0;          // c_F, Coulomb coefficient of Han (5.27)

  // Throws InputError for negative or non-finite values, or gamma = 0 with c_F > 0 (the Coulomb
  // cone of (5.28) divides by gamma).
  void validate() const;
};

// Energy density chi and its gradients for one contact particle, Han (5.21)-(5.25). Written with
// s3 and the shear directly instead of through the QR decomposition of (5.24): r_{i3} are the
// components of a3^E in the QR frame, whose third axis is n, so r13^2 + r23^2 = |a3S^E|^2 and
// r33 = s3 whatever the tangent frame; this form is basis free.
struct ContactEnergy {
  double chi = 0.0;                                            // energy per unit volume
  Eigen::Vector3d d_a1, d_a2, d_a3 = Eigen::Vector3d::Zero();  // d chi / d a1, a2, a3^E
};

// f(s3) of Han (5.22) and its derivative.
double contactCompressionEnergy(double s3, double normal_stiffness);
double contactCompressionSlope(double s3, double normal_stiffness);

ContactEnergy contactEnergy(const Eigen::Vector3d& a1, const Eigen::Vector3d& a2,
                            const Eigen::Vector3d& a3e, const ContactMaterial& material);

// Kirchhoff stress tau^S of Han (5.26) in world coordinates (used to check the Coulomb
// condition (5.27) and for diagnostics).
Eigen::Matrix3d contactKirchhoffStress(const Eigen::Vector3d& a1, const Eigen::Vector3d& a2,
                                       const Eigen::Vector3d& a3e, const ContactMaterial& material);

// Han (5.28)-(5.30): projects a trial fibre onto the Coulomb cone. Separating fibres (s3 > 1)
// are reset to the normal n (no memory of the separation); compressed fibres keep s3 and have
// their shear scaled down to |a3S| <= c_F k^c (1 - s3)^2 / gamma. Returns the projected fibre.
Eigen::Vector3d projectContactFibre(const Eigen::Vector3d& a1, const Eigen::Vector3d& a2,
                                    const Eigen::Vector3d& a3e_trial,
                                    const ContactMaterial& material, bool* yielded = nullptr);

}  // namespace chs
