#pragma once
#include <vector>

#include <Eigen/Core>

namespace chs::mpm {

// Lagrangian state of material points (Han section 3.2): position, velocity, APIC affine
// velocity C, deformation gradient F, mass and initial volume. Later particle kinds (shell
// control points, contact particles, Kirchhoff-Love quadrature points) build on these fields.
struct Particles {
  std::vector<Eigen::Vector3d> x, v;
  std::vector<Eigen::Matrix3d> C, F;
  std::vector<double> mass, volume0;

  int size() const { return static_cast<int>(x.size()); }
  void add(const Eigen::Vector3d& position, const Eigen::Vector3d& velocity, double m,
           double volume) {
    x.push_back(position);
    v.push_back(velocity);
    C.push_back(Eigen::Matrix3d::Zero());
    F.push_back(Eigen::Matrix3d::Identity());
    mass.push_back(m);
    volume0.push_back(volume);
  }
};

}  // namespace chs::mpm
