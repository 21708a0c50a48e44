#pragma once
#include <vector>

#include <Eigen/Core>

#include "cloth_hair_sim/core/mpm/grid_collider.h"
#include "cloth_hair_sim/core/mpm/hencky_solid.h"
#include "cloth_hair_sim/core/mpm/mpm_particles.h"
#include "cloth_hair_sim/core/mpm/sparse_grid.h"
#include "cloth_hair_sim/core/mpm/support_nodes.h"

namespace chs::mpm {

// The grid-force stage of type (i) particles, a plain MPM continuum of one Hencky material:
// grid.force -= sum_p V_p^0 P(F_p) F_p^T grad w_ip (Han (3.9), section 3.4). Usable on any grid
// the particles were transferred to, alongside other particle kinds; `support` as recorded for
// these particles by particleToGrid. Throws InputError naming the first particle found with
// det F <= 0 (the step before was unstable; see HenckySolid).
void scatterElasticStress(SparseGrid& grid, const Particles& particles, const HenckySolid& material,
                          int degree, const SupportNodes* support = nullptr);

struct ElasticSolidSettings {
  double grid_spacing = 0.0;  // dx [m], must be positive
  int kernel_degree = 2;      // B-spline degree, 2 or 3
  double rpic_damping = 0.0;  // nu of Han (3.15): 0 = APIC, 1 = RPIC
  Eigen::Vector3d gravity = Eigen::Vector3d::Zero();
  std::vector<GridCollider> colliders;  // grid boundary conditions, Han section 3.4
};

// Type (i) particles on their own grid, stepped by the standard explicit MPM step of Han
// chapter 3 with symplectic Euler:
//   particle-to-grid (3.1)-(3.2) -> stress forces (3.9) -> grid velocity (3.8), (3.10)
//   -> colliders -> grid-to-particle (3.13)-(3.16), with F updated by (3.17).
// The stages are the core's free functions, so a solver that shares the grid with other
// particle kinds runs the same sequence over all of them.
class ElasticSolid {
 public:
  // Throws InputError for inconsistent particle arrays, non-positive mass or volume, det F <= 0,
  // or a bad setting.
  ElasticSolid(Particles particles, const HenckySolid& material,
               const ElasticSolidSettings& settings);

  void step(double dt);
  double time() const { return time_; }
  // min(courant dx / c_p, courant dx / max speed), c_p the fastest dilatational wave speed of the
  // particles' reference densities m_p / V_p^0.
  double stableTimeStep(double courant = 0.3) const;

  const Particles& particles() const { return particles_; }
  const HenckySolid& material() const { return material_; }
  const SparseGrid& grid() const { return grid_; }

  // Particle kinetic energy with APIC's affine part, sum_p m_p (|v_p|^2 + D |C_p|_F^2) / 2 with
  // D = dx^2 (d + 1) / 12 the kernel's inertia (the energy a particle's affine field carries).
  double kineticEnergy() const;
  double elasticEnergy() const;  // sum_p V_p^0 psi(F_p)
  double gravityEnergy() const;  // -sum_p m_p g . x_p
  Eigen::Vector3d linearMomentum() const;
  // About the origin: sum_p m_p (x_p x v_p + D eps : C_p^T), the affine part after Jiang et al.
  Eigen::Vector3d angularMomentum() const;

 private:
  double kernelInertia() const;  // D

  Particles particles_;
  HenckySolid material_;
  ElasticSolidSettings settings_;
  SparseGrid grid_;
  std::vector<SupportNodes> supports_;
  double time_ = 0.0;
  double max_wave_speed_ = 0.0;
};

}  // namespace chs::mpm
