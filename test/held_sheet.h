#pragma once
// Scenes shared by the implicit hybrid shell tests (test_hybrid_shell_implicit,
// test_hybrid_shell_lagrangian).
#include <vector>

#include <Eigen/Core>

#include "cloth_hair_sim/core/drape/drape_problem.h"
#include "cloth_hair_sim/core/mesh/grid_generators.h"
#include "cloth_hair_sim/core/mpm/hybrid_shell_dynamics.h"
#include "cloth_test_material.h"

namespace chs::test {

// A 10 x 10 cm sheet of 8 x 8 quads held along its top edge, hanging in the xz plane
// (vertical) or lying in the xy plane (horizontal, it swings down).
struct HeldSheet {
  DrapeProblem problem;
  std::vector<int> top;
  explicit HeldSheet(bool vertical) {
    const int n = 8;
    problem.mesh = makeRectangleMesh(0.1, 0.1, n, n);
    if (vertical)
      for (auto& x : problem.mesh.vertices) x = Eigen::Vector3d(x.x(), 0.0, x.y());
    problem.material = testCloth();
    for (int i = 0; i <= n; ++i) top.push_back(n * (n + 1) + i);
    problem.bc.pinned = top;
  }
};

// Kinetic, Kirchhoff-Love and gravitational energy (the fibres of a sheet that never touches
// itself store none).
inline double totalEnergy(const HybridShellDynamics& d, const Eigen::Vector3d& g) {
  double e = d.kineticEnergy() + d.elasticEnergy();
  for (int p = 0; p < d.numVertices(); ++p) e -= d.masses()[p] * g.dot(d.positions()[p]);
  return e;
}

}  // namespace chs::test
