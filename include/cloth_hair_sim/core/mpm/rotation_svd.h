#pragma once
#include <Eigen/Core>

namespace chs::mpm {

// Singular value decomposition F = U diag(sigma) V^T with U and V rotations (det +1), the form
// isotropic elasticity needs: Eigen's SVD may return reflections, and a reflection moved into
// sigma instead flips the sign of the smallest singular value (Stomakhin et al. 2013's
// convention), which then is negative exactly when det F < 0.
struct RotationSvd {
  Eigen::Matrix3d U, V;
  Eigen::Vector3d sigma;  // descending magnitude; only sigma(2) can be negative
};
RotationSvd rotationSvd(const Eigen::Matrix3d& F);

}  // namespace chs::mpm
