#include "cloth_hair_sim/core/mpm/support_nodes.h"

#include <string>

#include "cloth_hair_sim/core/common/input_error.h"

namespace chs::mpm {

void SupportNodes::check(int num_particles, int degree) const {
  const int width = degree + 1;
  if (per_particle != width * width * width || numParticles() != num_particles)
    throw InputError(
        "MPM support nodes: recorded " + std::to_string(numParticles()) + " supports of " +
        std::to_string(per_particle) + " nodes, needed " + std::to_string(num_particles) + " of " +
        std::to_string(width * width * width) + " (degree " + std::to_string(degree) + ")");
}

}  // namespace chs::mpm
