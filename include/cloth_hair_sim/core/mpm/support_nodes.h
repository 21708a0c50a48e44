#pragma once
#include <vector>

namespace chs::mpm {

// The grid nodes of each particle's B-spline support, recorded by the particle-to-grid transfer
// (which activates them), so that the stages that follow at the same particle positions (grid
// forces, grid-to-particle) index the nodes directly instead of looking their coordinates up in
// the grid's hash again. Node offset (i, j, k) of particle p's support is
// of(p)[(i * n + j) * n + k] with n the support width per axis.
struct SupportNodes {
  int per_particle = 0;    // n^3
  std::vector<int> nodes;  // per_particle entries per particle

  int numParticles() const {
    return per_particle > 0 ? static_cast<int>(nodes.size()) / per_particle : 0;
  }
  const int* of(int particle) const { return nodes.data() + per_particle * particle; }
  // Throws InputError unless these are the supports of num_particles particles for B-splines of
  // the given degree (e.g. recorded for another particle set or kernel).
  void check(int num_particles, int degree) const;
};

}  // namespace chs::mpm
