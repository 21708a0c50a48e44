#pragma once

#include <Eigen/Core>
#include <Eigen/Eigenvalues>

namespace chs {

// The rigid velocity field v(x) = linear + angular x (x - centre) that fits a set of point
// velocities best in the mass-weighted least-squares sense: the same linear and angular momentum
// about the centre of mass. omega = I^+ L (a collinear set has no inertia about its line).
struct RigidVelocity {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  Eigen::Vector3d linear = Eigen::Vector3d::Zero();
  Eigen::Vector3d angular = Eigen::Vector3d::Zero();
  Eigen::Vector3d at(const Eigen::Vector3d& x) const { return linear + angular.cross(x - centre); }
};

// point(k, m, x, v) gives point k's mass, position and velocity, k = 0 .. n - 1; the total mass
// must be positive.
template <class Point>
RigidVelocity fitRigidVelocity(int n, const Point& point) {
  RigidVelocity fit;
  double mass = 0.0, m;
  Eigen::Vector3d x, v;
  for (int k = 0; k < n; ++k) {
    point(k, m, x, v);
    mass += m;
    fit.centre += m * x;
    fit.linear += m * v;
  }
  fit.centre /= mass;
  fit.linear /= mass;
  Eigen::Vector3d moment = Eigen::Vector3d::Zero();
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();
  for (int k = 0; k < n; ++k) {
    point(k, m, x, v);
    const Eigen::Vector3d r = x - fit.centre;
    moment += m * r.cross(v - fit.linear);
    inertia += m * (r.squaredNorm() * Eigen::Matrix3d::Identity() - r * r.transpose());
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(inertia);
  const double top = eig.eigenvalues().maxCoeff();
  for (int j = 0; j < 3; ++j)
    if (eig.eigenvalues()[j] > 1e-12 * top)
      fit.angular +=
          eig.eigenvectors().col(j).dot(moment) / eig.eigenvalues()[j] * eig.eigenvectors().col(j);
  return fit;
}

}  // namespace chs
