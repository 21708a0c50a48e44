#pragma once
#include <string>

namespace chs {

// How a step takes the shell's internal forces:
//  - kSymplecticEuler: on the grid (Han (3.7)-(3.9), (5.40)) at its current positions x* = x_i;
//    explicit, bounded by the membrane wave speed.
//  - kBackwardEuler: on the grid at its end-of-step positions x* = x_i + dt v_i^{n+1}; a
//    matrix-free Newton-Krylov solve over the grid velocities per step, bounded by CFL only.
//  - kLagrangianImplicit: Han's split of sections 4.2 and 6.1.1 applied to the shell. The
//    Kirchhoff-Love elasticity and gravity by backward Euler in the control points themselves
//    (shell/implicit_elasticity.h: assembled projected Hessian, CHOLMOD), then the grid for
//    contact and friction only (obstacles, the fibres' contact potential, other bodies); the
//    control points take the grid's velocities back (Han (4.12), HybridShellSettings::flip_blend).
//    Bounded by CFL only, and the grid solve is trivial where nothing touches.
//  - kLagrangianBdf2: the same split with the elastic stage by variable-step BDF2 instead of
//    backward Euler (less numerical damping of a swinging garment); a control point whose
//    velocity the grid's contact changed takes backward Euler for its next step.
enum class TimeIntegration {
  kSymplecticEuler,
  kBackwardEuler,
  kLagrangianImplicit,
  kLagrangianBdf2
};

// "symplectic_euler", "backward_euler", "lagrangian_implicit", "lagrangian_bdf2": the names
// scenes and ROS parameters use.
std::string timeIntegrationName(TimeIntegration integration);
// Throws InputError naming the accepted names for any other text.
TimeIntegration timeIntegrationFromName(const std::string& name);

}  // namespace chs
