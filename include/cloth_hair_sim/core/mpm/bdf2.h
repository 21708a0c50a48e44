#pragma once

namespace chs {

// The variable-step BDF2 formula y'_{n+1} = (a0 y_{n+1} + a1 y_n + a2 y_{n-1}) / dt for steps
// dt = t_{n+1} - t_n after previous_dt = t_n - t_{n-1} (omega = dt / previous_dt):
// a0 = (1 + 2 omega) / (1 + omega), a1 = -(1 + omega), a2 = omega^2 / (1 + omega); exact for
// quadratics. Without a previous step (previous_dt <= 0) it is backward Euler (1, -1, 0).
struct Bdf2Coefficients {
  double a0 = 1.0, a1 = -1.0, a2 = 0.0;
};

inline Bdf2Coefficients bdf2Coefficients(double dt, double previous_dt) {
  if (!(previous_dt > 0.0)) return {};
  const double w = dt / previous_dt;
  return {(1.0 + 2.0 * w) / (1.0 + w), -(1.0 + w), w * w / (1.0 + w)};
}

}  // namespace chs
