#include "cloth_hair_sim/core/mpm/elastic_solid.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include <Eigen/LU>

#include <tbb/parallel_for.h>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/mpm/bspline_kernel.h"
#include "cloth_hair_sim/core/mpm/grid_forces.h"
#include "cloth_hair_sim/core/mpm/transfers.h"

namespace chs::mpm {

void scatterElasticStress(SparseGrid& grid, const Particles& particles, const HenckySolid& material,
                          int degree, const SupportNodes* support) {
  std::vector<Eigen::Matrix3d> volume_stress(particles.size());
  tbb::parallel_for(0, particles.size(), [&](int p) {
    try {
      volume_stress[p] = particles.volume0[p] * material.kirchhoffStress(particles.F[p]);
    } catch (const InputError& e) {
      throw InputError("particle " + std::to_string(p) + ": " + e.what());
    }
  });
  scatterStressForces(grid, particles.x, volume_stress, degree, support);
}

ElasticSolid::ElasticSolid(Particles particles, const HenckySolid& material,
                           const ElasticSolidSettings& settings)
    : particles_(std::move(particles)),
      material_(material),
      settings_(settings),
      grid_(settings.grid_spacing) {
  const std::size_t n = particles_.x.size();
  if (particles_.v.size() != n || particles_.C.size() != n || particles_.F.size() != n ||
      particles_.mass.size() != n || particles_.volume0.size() != n)
    throw InputError("elastic solid: particle arrays of different lengths");
  if (settings_.kernel_degree != 2 && settings_.kernel_degree != 3)
    throw InputError("elastic solid: B-spline degree must be 2 or 3, got " +
                     std::to_string(settings_.kernel_degree));
  if (!(settings_.rpic_damping >= 0.0 && settings_.rpic_damping <= 1.0))
    throw InputError("elastic solid: RPIC damping must lie in [0, 1]");
  if (!settings_.gravity.allFinite()) throw InputError("elastic solid: gravity is not finite");
  for (std::size_t c = 0; c < settings_.colliders.size(); ++c)
    if (!settings_.colliders[c].surface)
      throw InputError("elastic solid: collider " + std::to_string(c) + " has no surface");
  for (int p = 0; p < particles_.size(); ++p) {
    const double m = particles_.mass[p], V = particles_.volume0[p];
    if (!(m > 0.0 && std::isfinite(m) && V > 0.0 && std::isfinite(V)))
      throw InputError("elastic solid: particle " + std::to_string(p) +
                       " needs a positive finite mass and volume");
    if (!particles_.x[p].allFinite() || !particles_.v[p].allFinite() ||
        !particles_.C[p].allFinite())
      throw InputError("elastic solid: particle " + std::to_string(p) + " has a non-finite state");
    if (!(particles_.F[p].determinant() > 0.0))
      throw InputError("elastic solid: particle " + std::to_string(p) + " starts with det F <= 0");
    max_wave_speed_ = std::max(max_wave_speed_, material_.dilatationalWaveSpeed(m / V));
  }
}

void ElasticSolid::step(double dt) {
  if (!(dt > 0.0 && std::isfinite(dt)))
    throw InputError("elastic solid: time step must be positive");
  const int d = settings_.kernel_degree;
  particleToGrid({&particles_}, grid_, d, &supports_);
  scatterElasticStress(grid_, particles_, material_, d, &supports_[0]);
  updateGridVelocity(grid_, settings_.gravity, dt);
  applyGridColliders(grid_, settings_.colliders);
  gridToParticle(grid_, particles_, d, settings_.rpic_damping, dt, &supports_[0]);
  time_ += dt;
}

double ElasticSolid::stableTimeStep(double courant) const {
  if (!(courant > 0.0)) throw InputError("elastic solid: Courant number must be positive");
  const double dx = grid_.spacing();
  const double elastic = max_wave_speed_ > 0.0 ? courant * dx / max_wave_speed_ : HUGE_VAL;
  return cflTimeStep(particles_, dx, courant, elastic);
}

double ElasticSolid::kernelInertia() const {
  const double dx = grid_.spacing();
  return 1.0 / (settings_.kernel_degree == 2 ? ParticleStencil<2>::inverseInertia(dx)
                                             : ParticleStencil<3>::inverseInertia(dx));
}

double ElasticSolid::kineticEnergy() const {
  const double D = kernelInertia();
  double e = 0.0;
  for (int p = 0; p < particles_.size(); ++p)
    e += 0.5 * particles_.mass[p] *
         (particles_.v[p].squaredNorm() + D * particles_.C[p].squaredNorm());
  return e;
}

double ElasticSolid::elasticEnergy() const {
  double e = 0.0;
  for (int p = 0; p < particles_.size(); ++p)
    e += particles_.volume0[p] * material_.energyDensity(particles_.F[p]);
  return e;
}

double ElasticSolid::gravityEnergy() const {
  double e = 0.0;
  for (int p = 0; p < particles_.size(); ++p)
    e -= particles_.mass[p] * settings_.gravity.dot(particles_.x[p]);
  return e;
}

Eigen::Vector3d ElasticSolid::linearMomentum() const {
  Eigen::Vector3d P = Eigen::Vector3d::Zero();
  for (int p = 0; p < particles_.size(); ++p) P += particles_.mass[p] * particles_.v[p];
  return P;
}

Eigen::Vector3d ElasticSolid::angularMomentum() const {
  const double D = kernelInertia();
  Eigen::Vector3d L = Eigen::Vector3d::Zero();
  for (int p = 0; p < particles_.size(); ++p) {
    const Eigen::Matrix3d& C = particles_.C[p];
    L += particles_.mass[p] *
         (particles_.x[p].cross(particles_.v[p]) +
          D * Eigen::Vector3d(C(2, 1) - C(1, 2), C(0, 2) - C(2, 0), C(1, 0) - C(0, 1)));
  }
  return L;
}

}  // namespace chs::mpm
