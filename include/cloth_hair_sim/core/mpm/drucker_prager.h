#pragma once
#include <Eigen/Core>

#include "cloth_hair_sim/core/mpm/hencky_solid.h"

namespace chs::mpm {

// Cohesionless Drucker-Prager plasticity in Hencky strain (Klar et al. 2016, Han's [29]): the
// return mapping that makes a Hencky solid (hencky_solid.h) a granular continuum, resisting
// compression and, in proportion to it, shear, but never tension. Han section 4.1 uses it for
// the frictional contact between hair strands: Coulomb's s^T sigma n + c_F n^T sigma n <= 0 for
// every direction n becomes the cone ||dev tau|| + alpha tr(tau) <= 0 in the Kirchhoff stress,
// with the friction angle phi = atan(c_F) and alpha = sqrt(2/3) 2 sin(phi) / (3 - sin(phi)), the
// cone through Mohr-Coulomb's compression meridian (under triaxial compression the two agree:
// sigma_1 / sigma_3 = (1 + sin phi) / (1 - sin phi)).
//
// With F^E = U exp(eps) V^T (eps the principal log stretches), Klar's three cases:
//   tr eps >= 0                    the material separates: no stress, F^E = U V^T;
//   inside the cone                unchanged (elastic);
//   outside                        eps moved along its deviator back onto the cone, its trace
//                                  (the compression) kept: the strands slide.
class DruckerPrager {
 public:
  enum class Case { kElastic, kSeparated, kSlid };
  // Throws InputError unless friction >= 0 and finite.
  DruckerPrager(const HenckySolid& material, double friction_coefficient);

  double frictionCoefficient() const { return c_f_; }
  double alpha() const { return alpha_; }
  // The elastic deformation gradient after the return. Throws InputError for det F <= 0 or a
  // non-finite F (as HenckySolid).
  Eigen::Matrix3d project(const Eigen::Matrix3d& F, Case* which = nullptr) const;
  // ||dev tau|| + alpha tr(tau) of F's Kirchhoff stress [Pa]: <= 0 on or inside the cone.
  double yield(const Eigen::Matrix3d& F) const;

 private:
  HenckySolid material_;
  double c_f_, alpha_;
};

}  // namespace chs::mpm
