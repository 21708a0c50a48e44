#pragma once
#include <vector>

#include <Eigen/Core>

namespace chs {

// The subdivision basis at one parameter point (xi1, xi2) = (u, v) of one control-mesh face:
// x(u, v) = sum_k w[k] x_{points[k]}, Han section 5.4 (x = x_p N_p^SD), with the first and
// second parametric derivatives of N_p^SD. Kirchhoff-Love kinematics need all of them.
struct SurfaceStencil {
  std::vector<int> points;  // control point indices
  std::vector<double> w, du, dv, duu, duv, dvv;

  int size() const { return static_cast<int>(points.size()); }

  // Position and derivatives of the surface over control positions x.
  template <class Weights>
  Eigen::Vector3d combine(const Weights& weights, const std::vector<Eigen::Vector3d>& x) const {
    Eigen::Vector3d s = Eigen::Vector3d::Zero();
    for (int k = 0; k < size(); ++k) s += weights[k] * x[points[k]];
    return s;
  }
  Eigen::Vector3d position(const std::vector<Eigen::Vector3d>& x) const { return combine(w, x); }
};

}  // namespace chs
