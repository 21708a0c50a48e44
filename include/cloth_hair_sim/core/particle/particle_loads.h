#pragma once
#include <vector>

#include <Eigen/Core>

#include "cloth_hair_sim/core/drape/drape_problem.h"
#include "cloth_hair_sim/core/particle/particle_network.h"

namespace chs {

// The external loads of a drape problem on the particle network: the nodal weight W of seed 000
// eq. (48) (areal density x tributary area x gravity) and the prescribed nodal loads. A nodal
// moment has no rotation to act on in a particle network, so it becomes a force couple on the
// edge at that vertex most nearly perpendicular to the moment: f = M x e / |e|^2 at the
// neighbour and -f at the vertex, recomputed from the current edge so that it keeps acting
// in the plane normal to M as the edge turns.
class ParticleLoads {
 public:
  ParticleLoads(const DrapeProblem& problem, const ParticleNetwork& network);

  const std::vector<double>& masses() const { return mass_; }
  // Replaces the problem's gravity (the weights change with it); throws InputError if not finite.
  void setGravity(const Eigen::Vector3d& gravity);
  // Adds weight (scaled by gravity_scale) and the nodal loads (scaled by load_scale) to f.
  void addForces(const std::vector<Eigen::Vector3d>& x, double gravity_scale, double load_scale,
                 std::vector<Eigen::Vector3d>& f) const;
  // Largest applied nodal force at full load: the scale of the equilibrium residual.
  double referenceForce() const;
  // Potential of gravity and of the nodal forces (couples are not included).
  double potential(const std::vector<Eigen::Vector3d>& x) const;

 private:
  struct Couple {
    int vertex = -1, partner = -1;
    Eigen::Vector3d moment = Eigen::Vector3d::Zero();
  };
  Eigen::Vector3d gravity_;
  std::vector<double> mass_;
  std::vector<NodalLoad> forces_;
  std::vector<Couple> couples_;
  double max_mass_ = 0.0;        // the heaviest node's mass: its weight scales with gravity
  double reference_load_ = 0.0;  // the largest prescribed nodal force (or couple's force)
};

}  // namespace chs
