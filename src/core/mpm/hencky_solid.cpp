#include "cloth_hair_sim/core/mpm/hencky_solid.h"

#include <cmath>
#include <sstream>
#include <string>

#include <Eigen/LU>

#include "cloth_hair_sim/core/common/input_error.h"

namespace chs::mpm {
namespace {

std::string str(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

}  // namespace

HenckySolid::HenckySolid(double youngs_modulus, double poisson_ratio)
    : E_(youngs_modulus), nu_(poisson_ratio) {
  if (!(E_ > 0.0 && std::isfinite(E_)))
    throw InputError("Hencky solid: Young's modulus must be positive and finite, got " + str(E_));
  // nu -> 1/2 is incompressible (lambda -> inf), nu -> -1 has zero bulk modulus.
  if (!(nu_ > -1.0 && nu_ < 0.5))
    throw InputError("Hencky solid: Poisson's ratio must lie in (-1, 0.5), got " + str(nu_));
  mu_ = E_ / (2.0 * (1.0 + nu_));
  lambda_ = E_ * nu_ / ((1.0 + nu_) * (1.0 - 2.0 * nu_));
}

double HenckySolid::dilatationalWaveSpeed(double density) const {
  if (!(density > 0.0 && std::isfinite(density)))
    throw InputError("Hencky solid: density must be positive and finite, got " + str(density));
  return std::sqrt((lambda_ + 2.0 * mu_) / density);
}

HenckySolid::Principal HenckySolid::principal(const Eigen::Matrix3d& F) const {
  const double J = F.determinant();
  if (!F.allFinite() || !(J > 0.0)) {
    throw InputError("Hencky solid: deformation gradient with det F = " + str(J) +
                     " (inverted, flattened or not finite) has no Hencky strain; the explicit "
                     "step has outrun its stable time step");
  }
  Principal p{rotationSvd(F), Eigen::Vector3d::Zero()};
  p.log_sigma = p.svd.sigma.array().log();
  return p;
}

double HenckySolid::energyDensity(const Eigen::Matrix3d& F) const {
  const Eigen::Vector3d e = principal(F).log_sigma;
  const double tr = e.sum();
  return mu_ * e.squaredNorm() + 0.5 * lambda_ * tr * tr;  // Han (4.5)
}

Eigen::Matrix3d HenckySolid::firstPiolaStress(const Eigen::Matrix3d& F) const {
  const Principal p = principal(F);
  const Eigen::Vector3d& e = p.log_sigma;
  const Eigen::Vector3d dpsi = 2.0 * mu_ * e.array() + lambda_ * e.sum();  // dpsi / d ln sigma
  const Eigen::Vector3d P_hat = dpsi.array() / p.svd.sigma.array();        // Han (4.6), corrected
  return p.svd.U * P_hat.asDiagonal() * p.svd.V.transpose();
}

Eigen::Matrix3d HenckySolid::kirchhoffStress(const Eigen::Matrix3d& F) const {
  const Principal p = principal(F);
  const Eigen::Vector3d& e = p.log_sigma;
  const Eigen::Vector3d tau_hat = 2.0 * mu_ * e.array() + lambda_ * e.sum();
  return p.svd.U * tau_hat.asDiagonal() * p.svd.U.transpose();
}

}  // namespace chs::mpm
