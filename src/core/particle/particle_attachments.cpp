#include "cloth_hair_sim/core/particle/particle_attachments.h"

#include <string>

#include "cloth_hair_sim/core/common/input_error.h"

namespace chs {

std::vector<Eigen::Vector3d> holdingForces(const ParticleDynamics& dynamics,
                                           const std::vector<int>& vertices,
                                           const std::vector<Eigen::Vector3d>& accelerations) {
  if (!accelerations.empty() && accelerations.size() != vertices.size())
    throw InputError("holding forces: " + std::to_string(accelerations.size()) +
                     " accelerations for " + std::to_string(vertices.size()) + " vertices");
  for (int v : vertices)
    if (v < 0 || v >= dynamics.numVertices())
      throw InputError("holding forces: vertex " + std::to_string(v) + " out of range (" +
                       std::to_string(dynamics.numVertices()) + " vertices)");
  // All applied forces are evaluated for a few held vertices: cheap next to a step (4 of them).
  const std::vector<Eigen::Vector3d> f = dynamics.appliedForces();
  std::vector<Eigen::Vector3d> r(vertices.size());
  for (std::size_t k = 0; k < vertices.size(); ++k) {
    const int v = vertices[k];
    r[k] = -f[v];
    if (!accelerations.empty()) r[k] += dynamics.masses()[v] * accelerations[k];
  }
  return r;
}

HoldingWrench holdingWrench(const ParticleDynamics& dynamics, const std::vector<int>& vertices,
                            const Eigen::Vector3d& origin,
                            const std::vector<Eigen::Vector3d>& accelerations) {
  const std::vector<Eigen::Vector3d> r = holdingForces(dynamics, vertices, accelerations);
  HoldingWrench w;
  for (std::size_t k = 0; k < vertices.size(); ++k) {
    w.force += r[k];
    w.torque += (dynamics.positions()[vertices[k]] - origin).cross(r[k]);
  }
  return w;
}

}  // namespace chs
