#include "cloth_hair_sim/core/shell/contact_potential.h"

#include <cmath>
#include <string>

#include <Eigen/Geometry>

#include "cloth_hair_sim/core/common/input_error.h"

namespace chs {

void ContactMaterial::validate() const {
  auto check = [](double value, const char* name) {
    if (!std::isfinite(value) || value < 0.0)
      throw InputError(std::string("contact material: ") + name + " must be finite and >= 0, got " +
                       std::to_string(value));
  };
  check(shear_stiffness, "shear stiffness gamma");
  check(normal_stiffness, "normal stiffness k_c");
  check(friction, "friction coefficient c_F");
  if (friction > 0.0 && shear_stiffness == 0.0)
    throw InputError("contact material: friction c_F > 0 needs a shear stiffness gamma > 0");
}

double contactCompressionEnergy(double s3, double k) {  // Han (5.22)
  if (s3 >= 1.0) return 0.0;
  const double c = 1.0 - s3;
  return k / 3.0 * c * c * c;
}

double contactCompressionSlope(double s3, double k) {
  if (s3 >= 1.0) return 0.0;
  return -k * (1.0 - s3) * (1.0 - s3);
}

ContactEnergy contactEnergy(const Eigen::Vector3d& a1, const Eigen::Vector3d& a2,
                            const Eigen::Vector3d& a3e, const ContactMaterial& mat) {
  const Eigen::Vector3d m = a1.cross(a2);
  const double m_norm = m.norm();
  const Eigen::Vector3d n = m / m_norm;
  const double s3 = a3e.dot(n);
  const Eigen::Vector3d shear = a3e - s3 * n;
  ContactEnergy e;
  e.chi = 0.5 * mat.shear_stiffness * shear.squaredNorm() +
          contactCompressionEnergy(s3, mat.normal_stiffness);  // Han (5.21)
  const double fp = contactCompressionSlope(s3, mat.normal_stiffness);
  e.d_a3 = mat.shear_stiffness * shear + fp * n;
  // chi(n) through s3 = a3e . n: d chi / d n = (f'(s3) - gamma s3) a3e; n = m / |m| with
  // m = a1 x a2, so d chi = g . dm with g = (I - n n^T) d chi/dn / |m|.
  const Eigen::Vector3d dn = (fp - mat.shear_stiffness * s3) * a3e;
  const Eigen::Vector3d g = (dn - n * n.dot(dn)) / m_norm;
  e.d_a1 = a2.cross(g);
  e.d_a2 = g.cross(a1);
  return e;
}

Eigen::Matrix3d contactKirchhoffStress(const Eigen::Vector3d& a1, const Eigen::Vector3d& a2,
                                       const Eigen::Vector3d& a3e, const ContactMaterial& mat) {
  // Han (5.26) in the QR frame q1 = a1/|a1|, q3 = n, q2 = q3 x q1.
  Eigen::Matrix3d q;
  q.col(0) = a1.normalized();
  q.col(2) = a1.cross(a2).normalized();
  q.col(1) = q.col(2).cross(q.col(0));
  const Eigen::Vector3d s = q.transpose() * a3e;
  Eigen::Matrix3d t = mat.shear_stiffness * s * s.transpose();
  t(2, 2) += contactCompressionSlope(s[2], mat.normal_stiffness) * s[2] -
             mat.shear_stiffness * s[2] * s[2];
  return q * t * q.transpose();
}

Eigen::Vector3d projectContactFibre(const Eigen::Vector3d& a1, const Eigen::Vector3d& a2,
                                    const Eigen::Vector3d& a3e_trial, const ContactMaterial& mat,
                                    bool* yielded) {
  const Eigen::Vector3d n = a1.cross(a2).normalized();
  const double s3 = a3e_trial.dot(n);
  const Eigen::Vector3d shear = a3e_trial - s3 * n;
  if (yielded) *yielded = false;
  if (s3 > 1.0) {  // separating: Han (5.29) second case
    if (yielded) *yielded = true;
    return n;
  }
  // Compressed (0 < s3 <= 1); a fibre compressed through zero is treated likewise, so the
  // cone stays defined and the compression energy keeps pushing it back.
  const double bound = mat.shear_stiffness > 0.0 ? mat.friction * mat.normal_stiffness *
                                                       (1.0 - s3) * (1.0 - s3) / mat.shear_stiffness
                                                 : 0.0;  // Han (5.28)
  const double t = shear.norm();
  if (t <= bound) return a3e_trial;
  if (yielded) *yielded = true;
  return s3 * n + shear * (bound / t);  // Han (5.29)-(5.30)
}

}  // namespace chs
