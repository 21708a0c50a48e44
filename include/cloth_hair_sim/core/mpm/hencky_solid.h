#pragma once
#include <Eigen/Core>

#include "cloth_hair_sim/core/mpm/rotation_svd.h"

namespace chs::mpm {

// The isotropic St.Venant-Kirchhoff Hencky solid of Han (4.5): with F = U S V^T,
//   psi = mu tr((ln S)^2) + lambda/2 (tr ln S)^2,
// the St.Venant-Kirchhoff energy in the logarithmic (Hencky) strain ln S. Its first
// Piola-Kirchhoff stress is P = U (2 mu S^-1 ln S + lambda tr(ln S) S^-1) V^T (Han (4.6); the
// seed text drops the trace in the lambda term). Lame parameters from Young's modulus and
// Poisson's ratio, mu = E / (2 (1 + nu)), lambda = E nu / ((1 + nu)(1 - 2 nu)), so that small
// strains follow linear elasticity with those moduli.
//
// ln S is undefined for an inverted or flattened element (det F <= 0): the material cannot be
// turned inside out, and an explicit step that does so has outrun its stable time step. Every
// function below therefore throws InputError for det F <= 0 or a non-finite F instead of
// inventing a stress.
class HenckySolid {
 public:
  // Throws InputError unless 0 < E < inf and -1 < nu < 1/2.
  HenckySolid(double youngs_modulus, double poisson_ratio);

  double youngsModulus() const { return E_; }
  double poissonRatio() const { return nu_; }
  double mu() const { return mu_; }
  double lambda() const { return lambda_; }
  // Speed of the dilatational (P) wave, sqrt((lambda + 2 mu) / rho): the fastest signal an
  // explicit step must resolve.
  double dilatationalWaveSpeed(double density) const;

  double energyDensity(const Eigen::Matrix3d& F) const;  // psi per reference volume
  Eigen::Matrix3d firstPiolaStress(const Eigen::Matrix3d& F) const;
  // Kirchhoff stress tau = P F^T = U (2 mu ln S + lambda tr(ln S) I) U^T: symmetric, so the grid
  // forces it makes exert no net torque. This is what the grid force needs (Han (3.9)).
  Eigen::Matrix3d kirchhoffStress(const Eigen::Matrix3d& F) const;

 private:
  // F's rotation SVD and the principal log stretches ln S; throws for det F <= 0 or non-finite F.
  struct Principal {
    RotationSvd svd;
    Eigen::Vector3d log_sigma;
  };
  Principal principal(const Eigen::Matrix3d& F) const;

  double E_, nu_, mu_, lambda_;
};

}  // namespace chs::mpm
