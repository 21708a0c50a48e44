#include "cloth_hair_sim/core/particle/particle_loads.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <Eigen/Geometry>

#include "cloth_hair_sim/core/common/input_error.h"

namespace chs {

ParticleLoads::ParticleLoads(const DrapeProblem& problem, const ParticleNetwork& network)
    : gravity_(problem.gravity) {
  const auto& area = network.tributaryArea();
  mass_.resize(area.size());
  for (std::size_t i = 0; i < area.size(); ++i) {
    mass_[i] = problem.material.areal_density * area[i];
    max_mass_ = std::max(max_mass_, mass_[i]);
  }
  const auto& x0 = problem.mesh.vertices;
  for (const auto& l : problem.bc.loads) {
    if (l.force.squaredNorm() > 0.0) {
      forces_.push_back(l);
      reference_load_ = std::max(reference_load_, l.force.norm());
    }
    if (l.moment.squaredNorm() == 0.0) continue;
    Couple c;
    c.vertex = l.vertex;
    c.moment = l.moment;
    double best = -1.0;
    const Eigen::Vector3d m = l.moment.normalized();
    for (int nb : network.neighbours()[l.vertex]) {
      const Eigen::Vector3d e = (x0[nb] - x0[l.vertex]).normalized();
      const double perpendicular = 1.0 - std::abs(e.dot(m));
      if (perpendicular > best) {
        best = perpendicular;
        c.partner = nb;
      }
    }
    if (c.partner < 0 || best < 1e-6)
      throw InputError("nodal moment on vertex " + std::to_string(l.vertex) +
                       ": no edge there lies off the moment axis to carry it as a couple");
    const double arm = (x0[c.partner] - x0[l.vertex]).norm();
    reference_load_ = std::max(reference_load_, l.moment.norm() / arm);
    couples_.push_back(c);
  }
}

void ParticleLoads::setGravity(const Eigen::Vector3d& gravity) {
  if (!gravity.allFinite()) throw InputError("particle loads: gravity must be finite");
  gravity_ = gravity;
}

double ParticleLoads::referenceForce() const {
  return std::max(max_mass_ * gravity_.norm(), reference_load_);
}

void ParticleLoads::addForces(const std::vector<Eigen::Vector3d>& x, double gravity_scale,
                              double load_scale, std::vector<Eigen::Vector3d>& f) const {
  if (gravity_scale != 0.0)
    for (std::size_t i = 0; i < f.size(); ++i) f[i] += (gravity_scale * mass_[i]) * gravity_;
  if (load_scale == 0.0) return;
  for (const auto& l : forces_) f[l.vertex] += load_scale * l.force;
  for (const auto& c : couples_) {
    const Eigen::Vector3d e = x[c.partner] - x[c.vertex];
    const Eigen::Vector3d fp = load_scale * c.moment.cross(e) / e.squaredNorm();
    f[c.partner] += fp;
    f[c.vertex] -= fp;
  }
}

double ParticleLoads::potential(const std::vector<Eigen::Vector3d>& x) const {
  double p = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) p -= mass_[i] * gravity_.dot(x[i]);
  for (const auto& l : forces_) p -= l.force.dot(x[l.vertex]);
  return p;
}

}  // namespace chs
