#pragma once
#include <string>

#include "cloth_hair_sim/core/common/cancel_flag.h"
#include "cloth_hair_sim/core/drape/drape_problem.h"
#include "cloth_hair_sim/core/solid_shell/solid_shell_element.h"

namespace chs {

// How the solid-shell drape is solved (seed 001):
//  kStatic: the iterative scheme of section 3, eqs. (16)-(18): full load, Newton-Raphson
//    refinements K_t dD = P - F scaled by the multiplier lambda = c L_f / max|dD| (capped at 1,
//    so that the last iterations are plain Newton and converge quadratically).
//  kDynamic: explicit central differences of section 4, eqs. (19)-(23), with lumped mass and
//    Rayleigh mass damping alpha M v; with mass_scaling > 1 (seed: 100) this is the dynamic
//    relaxation of section 4.2, whose end state is the static drape.
//  kEnergy: ours, not the seed's: the total potential energy minimised by the FEM shell's
//    Newton method with a modified Hessian, a line search and saddle escapes
//    (solver/energy_newton.h), so that only a stable equilibrium is returned. The seed's scheme
//    wanders on a sheet over a table (docs/VALIDATION.md) and dynamic relaxation takes 1e5
//    explicit steps; this is the one that converges in seconds.
enum class SolidShellScheme { kStatic, kDynamic, kEnergy };

struct SolidShellSettings {
  SolidShellScheme scheme = SolidShellScheme::kStatic;
  ThicknessStrain thickness_strain = ThicknessStrain::kGreen;
  double mu = 0.5;          // switch of the quasi-engineering strain (24), in (0, 1)
  double tolerance = 1e-6;  // relative out-of-balance force |P - F| / |P| at convergence
  // Static scheme.
  double multiplier = 1e-2;  // c of eq. (18); the seed uses 1e-3 .. 1e-2
  double free_length = 0.0;  // L_f [m]; 0 takes the largest side of the garment's bounding box
  int max_iterations = 20000;
  // Dynamic scheme.
  double damping = 5.0;       // alpha of eq. (20) [1/s]
  double mass_scaling = 1.0;  // masses x this, weight unchanged
  double time_step = 0.0;     // [s]; 0 = 0.5 x the stable step 2 / omega_max (Gershgorin bound)
  double end_time = 10.0;     // [s]; the run stops earlier once the tolerance is met
  double contact_stiffness = 0.0;  // k_c [N/m]; 0 = a hundred times the membrane rigidity
  // Reversible adaptive 1-4 subdivision of seed 001 section 5 (adaptive_mesh.h): the garment's
  // quads are level 0, split at most adaptive_levels times (0: the mesh stays as given). An
  // element splits where |eps_b| L_i > refine_threshold (eq. (25)); four siblings merge where
  // each has |eps_b| L_(i-1) <= refine_threshold - merge_margin (eq. (26)). The dynamic scheme
  // adapts every adapt_interval steps, the energy scheme every adapt_iterations Newton
  // iterations of its descent; the static and energy schemes then adapt each converged drape and
  // solve again until the mesh stays.
  int adaptive_levels = 0;
  double refine_threshold = 0.2;  // const of eq. (25): the bend [rad] an element may take
  double merge_margin = 0.1;      // epsilon of eq. (26)
  int adapt_interval = 500;       // steps
  int adapt_iterations = 10;      // Newton iterations
  int progress_interval = 100;    // iterations (steps) between progress events
  const CancelFlag* cancel = nullptr;
};

// "static", "dynamic" or "energy"; InputError otherwise.
SolidShellScheme parseSolidShellScheme(const std::string& name);

// Throws InputError naming the setting that makes no sense.
void validateSolidShellSettings(const SolidShellSettings& settings);

// Solves the drape; never throws on non-convergence (the result then holds the last state,
// converged = false and why). Throws InputError for input that makes no sense. The status also
// reports directors found below the deformed mid-surface (top and bottom surfaces crossed).
DrapeResult solveSolidShell(const DrapeProblem& problem, const SolidShellSettings& settings,
                            const ProgressCallback& progress = {});

}  // namespace chs
