#pragma once
#include <vector>

#include <Eigen/Core>

#include "cloth_hair_sim/core/common/cancel_flag.h"
#include "cloth_hair_sim/core/drape/drape_problem.h"
#include "cloth_hair_sim/core/drape/seam_groups.h"
#include "cloth_hair_sim/core/particle/particle_network.h"

namespace chs {

// Settings of the static particle relaxation (seed 000 section 3.2.3). Each step moves every
// node by Disp^k = C_disp (F^k + C_acc Disp^(k-1)) (steps 2-6), i.e. a heavy-ball iteration
// with step C_disp and momentum C_acc C_disp.
//
// Defaults, derived from the stiffnesses: C_disp = 1 / K_max, where K_max is the largest
// Gershgorin row bound of the network's stiffness (so no single node can overshoot: the
// explicit iteration is stable for C_disp K < 2), and C_acc = momentum / C_disp with momentum
// 0.9999. A fixed momentum is only optimal for one condition number, and cloth spans many
// (membrane vs bending stiffness, 1e6 in the beam benchmarks), so with `restart` the
// pseudo-load is dropped whenever the resultant turns against the last displacement (the net
// power sum F.Disp < 0): the iteration then never climbs uphill and converges for any
// momentum below 1.
//
// Convergence: the seed's test max |Disp| < b/10000 alone is met by any small C_disp, so the
// unbalanced force must also fall below force_tolerance x the largest applied nodal force.
struct ParticleSettings {
  ParticleNetworkOptions network;        // D', B'
  double c_disp = 0.0;                   // [length/force]; 0: 1 / K_max
  double c_acc = 0.0;                    // [force/length]; 0: momentum / C_disp
  double momentum = 0.9999;              // C_acc C_disp when c_acc is 0; in [0, 1)
  bool restart = true;                   // drop the pseudo-load when F.Disp < 0
  double displacement_tolerance = 1e-4;  // x b: the seed's b/10000
  double force_tolerance = 1e-6;         // x largest applied nodal force
  int max_iterations = 500000;
  int progress_interval = 1000;    // iterations between progress callbacks
  double contact_tolerance = 0.0;  // gap counted as contact; 0: 1e-6 b

  // Sewing (seed 000 section 3.2.1): first, without gravity, loads or obstacles, springs pull
  // the seams together until every pair is closer than seam_join_distance (or the sewing
  // relaxation stalls); then each sewn group is merged and moves as one particle.
  std::vector<Seam> seams;
  double sewing_stiffness = 0.0;    // [force/length]; 0: the mean edge stretching stiffness
  double seam_join_distance = 0.0;  // 0: b/1000
  int max_sewing_iterations = 200000;

  // Start from these positions instead of the flat reference mesh (continuation); empty: mesh.
  std::vector<Eigen::Vector3d> initial_positions;

  // Polled each iteration: once set, the solve returns its current (finite) state with
  // DrapeResult::cancelled.
  const CancelFlag* cancel = nullptr;
};

// Static drape by the particle method of seed 000 section 3. Throws InputError for a bad
// problem or nonsense settings. Never throws otherwise: when it does not converge it returns
// the last (finite) state with converged = false and says why in status. DrapeResult::residual
// and the history hold max |Disp| / b.
DrapeResult solveParticleStatic(const DrapeProblem& problem, const ParticleSettings& settings,
                                const ProgressCallback& progress = {});

}  // namespace chs
