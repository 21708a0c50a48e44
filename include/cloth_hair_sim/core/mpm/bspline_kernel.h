#pragma once
#include <array>
#include <cmath>

#include <Eigen/Core>

namespace chs::mpm {

// One-dimensional B-spline interpolation functions of Han (3.3)-(3.4) and their derivatives, in
// grid units (x measured in cells from the node). Degree 2 (quadratic, 3 nodes per axis) or 3
// (cubic, 4 nodes per axis).
template <int Degree>
struct BSpline;

template <>
struct BSpline<2> {
  static constexpr int kSupport = 3;
  static double value(double x) {  // Han (3.4)
    x = std::abs(x);
    if (x < 0.5) return 0.75 - x * x;
    if (x < 1.5) return 0.5 * (1.5 - x) * (1.5 - x);
    return 0.0;
  }
  static double slope(double x) {
    const double a = std::abs(x), s = x < 0.0 ? -1.0 : 1.0;
    if (a < 0.5) return -2.0 * x;
    if (a < 1.5) return -s * (1.5 - a);
    return 0.0;
  }
  // First node of the support of a particle at grid coordinate x (in cells).
  static int base(double x) { return static_cast<int>(std::floor(x - 0.5)); }
};

template <>
struct BSpline<3> {
  static constexpr int kSupport = 4;
  static double value(double x) {
    x = std::abs(x);
    if (x < 1.0) return 0.5 * x * x * x - x * x + 2.0 / 3.0;
    if (x < 2.0) return (2.0 - x) * (2.0 - x) * (2.0 - x) / 6.0;
    return 0.0;
  }
  static double slope(double x) {
    const double a = std::abs(x), s = x < 0.0 ? -1.0 : 1.0;
    if (a < 1.0) return s * (1.5 * a * a - 2.0 * a);
    if (a < 2.0) return -s * 0.5 * (2.0 - a) * (2.0 - a);
    return 0.0;
  }
  static int base(double x) { return static_cast<int>(std::floor(x)) - 1; }
};

// Tensor-product weights w_ip = N(x_p - x_i) and gradients (Han (3.3) and the gradient below it)
// of one particle against the Support^3 nodes around it.
template <int Degree>
struct ParticleStencil {
  static constexpr int kSupport = BSpline<Degree>::kSupport;
  static constexpr int kNodes = kSupport * kSupport * kSupport;
  Eigen::Vector3i base;                                   // lowest node index of the support
  std::array<std::array<double, kSupport>, 3> w{}, dw{};  // per axis, dw in 1/length

  ParticleStencil(const Eigen::Vector3d& x, double dx) {
    for (int a = 0; a < 3; ++a) {
      const double g = x[a] / dx;
      base[a] = BSpline<Degree>::base(g);
      for (int k = 0; k < kSupport; ++k) {
        const double r = g - (base[a] + k);
        w[a][k] = BSpline<Degree>::value(r);
        dw[a][k] = BSpline<Degree>::slope(r) / dx;
      }
    }
  }
  // Node offset (i, j, k) in the support, its weight and weight gradient.
  double weight(int i, int j, int k) const { return w[0][i] * w[1][j] * w[2][k]; }
  Eigen::Vector3d gradient(int i, int j, int k) const {
    return {dw[0][i] * w[1][j] * w[2][k], w[0][i] * dw[1][j] * w[2][k],
            w[0][i] * w[1][j] * dw[2][k]};
  }
  // x_i - x_p per axis for the support's nodes, (base + k) dx - x_p: node (i, j, k) sits at
  // x_p + (d[0][i], d[1][j], d[2][k]) without a look-up of its coordinates in the grid.
  std::array<std::array<double, kSupport>, 3> nodeOffsets(const Eigen::Vector3d& x,
                                                          double dx) const {
    std::array<std::array<double, kSupport>, 3> d;
    for (int a = 0; a < 3; ++a)
      for (int k = 0; k < kSupport; ++k) d[a][k] = static_cast<double>(base[a] + k) * dx - x[a];
    return d;
  }
  // D_p^{-1} of APIC: 12 / (dx^2 (d + 1)), Han (3.14).
  static double inverseInertia(double dx) { return 12.0 / (dx * dx * (Degree + 1)); }
};

}  // namespace chs::mpm
