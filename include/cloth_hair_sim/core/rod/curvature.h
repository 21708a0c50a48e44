#pragma once
#include <Eigen/Core>

namespace chs::rod {

// Local variables of an interior vertex of a discrete elastic rod: its incoming edge e, the
// edge's twist angle, its outgoing edge f and that one's angle, in the order
// (e_x, e_y, e_z, theta_e, f_x, f_y, f_z, theta_f).
using Vector8d = Eigen::Matrix<double, 8, 1>;
using Matrix8d = Eigen::Matrix<double, 8, 8>;

// The material frames (m1, m2) of the two edges.
struct EdgePairFrames {
  Eigen::Vector3d m1e, m2e, m1f, m2f;
};

// Discrete curvature at a vertex (Bergou et al. 2008, (1) and section 4.2): the curvature
// binormal kb = 2 te x tf / (1 + te . tf), and its material components
//   kappa_1 = (kb . (m2e + m2f)) / 2,  kappa_2 = -(kb . (m1e + m1f)) / 2,
// with their gradients in the local variables (curvatureDerivatives) and the weighted sum of
// their Hessians w_1 hess kappa_1 + w_2 hess kappa_2 (curvatureHessian). The frames depend on the
// edges by (time-)parallel transport of the reference frame and on the angles by rotation about the
// tangent; the derivatives are those of that dependence (Bergou et al. 2010, section 7;
// in the closed form of Jawed, Novelia and O'Reilly, "A primer on the kinematics of discrete
// elastic rods", 2018, section 7).
struct CurvatureDerivatives {
  Eigen::Vector3d kb = Eigen::Vector3d::Zero();
  Eigen::Vector2d kappa = Eigen::Vector2d::Zero();
  Vector8d gradient[2];
};
CurvatureDerivatives curvatureDerivatives(const Eigen::Vector3d& e, const Eigen::Vector3d& f,
                                          const EdgePairFrames& frames);
Matrix8d curvatureHessian(const Eigen::Vector3d& e, const Eigen::Vector3d& f,
                          const EdgePairFrames& frames, const Eigen::Vector2d& weights);

// The discrete twist m = theta_f - theta_e + (reference twist) depends on the edges through the
// reference twist (the holonomy of transporting e's frame to f): its gradient and Hessian in the
// local variables (Bergou et al. 2010, section 7; Jawed et al. 2018, section 8).
struct TwistDerivatives {
  Vector8d gradient;
  Matrix8d hessian;  // filled only when asked for
};
TwistDerivatives twistDerivatives(const Eigen::Vector3d& e, const Eigen::Vector3d& f,
                                  const Eigen::Vector3d& kb, bool hessian);

}  // namespace chs::rod
