#include "cloth_hair_sim/core/mpm/rotation_svd.h"

#include <Eigen/LU>
#include <Eigen/SVD>

namespace chs::mpm {

RotationSvd rotationSvd(const Eigen::Matrix3d& F) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(F, Eigen::ComputeFullU | Eigen::ComputeFullV);
  RotationSvd r{svd.matrixU(), svd.matrixV(), svd.singularValues()};
  // Eigen sorts sigma in decreasing order: absorbing a reflection into the smallest singular
  // value changes F's closest rotation least. With det F > 0 both or neither are reflections,
  // and the two flips cancel in sigma.
  if (r.U.determinant() < 0.0) {
    r.U.col(2) *= -1.0;
    r.sigma(2) *= -1.0;
  }
  if (r.V.determinant() < 0.0) {
    r.V.col(2) *= -1.0;
    r.sigma(2) *= -1.0;
  }
  return r;
}

}  // namespace chs::mpm
