#pragma once
// Independent references for the beam benchmarks, computed in the tests themselves: the
// tip-loaded elastica by shooting (RK4 on theta'' = -lambda cos theta) rather than through the
// elliptic-integral closed form that benchmarks.md tabulates, so the two cross-check each other.
#include <cmath>

namespace chs::reference {

struct ElasticaTip {
  double rotation;    // tip rotation theta_0 [rad]
  double shortening;  // u / L
  double deflection;  // w / L
};

// Cantilever of unit length, clamped at s = 0, dead tip load P = lambda EI / L^2 normal to the
// undeformed axis: theta'' + lambda cos(theta) = 0, theta(0) = 0, theta'(1) = 0.
inline ElasticaTip tipLoadedElastica(double lambda) {
  const int n = 4000;
  auto shoot = [&](double k0, ElasticaTip* tip) {
    // State: theta, theta', x, z.
    double y[4] = {0.0, k0, 0.0, 0.0};
    auto rhs = [&](const double* s, double* d) {
      d[0] = s[1];
      d[1] = -lambda * std::cos(s[0]);
      d[2] = std::cos(s[0]);
      d[3] = std::sin(s[0]);
    };
    const double h = 1.0 / n;
    for (int i = 0; i < n; ++i) {
      double k1[4], k2[4], k3[4], k4[4], t[4];
      rhs(y, k1);
      for (int j = 0; j < 4; ++j) t[j] = y[j] + 0.5 * h * k1[j];
      rhs(t, k2);
      for (int j = 0; j < 4; ++j) t[j] = y[j] + 0.5 * h * k2[j];
      rhs(t, k3);
      for (int j = 0; j < 4; ++j) t[j] = y[j] + h * k3[j];
      rhs(t, k4);
      for (int j = 0; j < 4; ++j) y[j] += h / 6.0 * (k1[j] + 2 * k2[j] + 2 * k3[j] + k4[j]);
    }
    if (tip) *tip = {y[0], 1.0 - y[2], y[3]};
    return y[1];  // theta'(1), zero at the solution
  };
  // theta'(0) = lambda * x_tip lies in (0, lambda]; theta'(1) increases with theta'(0).
  double lo = 0.0, hi = lambda;
  for (int it = 0; it < 200; ++it) {
    const double mid = 0.5 * (lo + hi);
    (shoot(mid, nullptr) < 0.0 ? lo : hi) = mid;
  }
  ElasticaTip tip;
  shoot(0.5 * (lo + hi), &tip);
  return tip;
}

// Cantilever under a tip moment M = lambda_M pi EI / L: a circular arc of angle theta.
inline ElasticaTip momentLoadedCantilever(double lambda_m) {
  const double th = lambda_m * M_PI;
  return {th, 1.0 - std::sin(th) / th, (1.0 - std::cos(th)) / th};
}

}  // namespace chs::reference
