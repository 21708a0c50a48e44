// Seed 000 section 4.4: the tablecloth on a square table, both methods, through the shipped
// scene files. Checks what statics guarantees exactly (the table carries the whole weight, the
// cloth does not penetrate it) and prints corner and midside positions beside the seed's
// experiment (see docs/VALIDATION.md for why they are not asserted).
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "cloth_hair_sim/core/fem_shell/fem_shell_solver.h"
#include "cloth_hair_sim/core/io/scene.h"
#include "cloth_hair_sim/core/particle/particle_static_solver.h"

namespace chs {
namespace {

constexpr double kL = 0.2;  // cloth side [m]

void report(const char* method, const Scene& scene, const DrapeResult& r) {
  const int n = 20, corner = n * (n + 1) + n, midside = (n / 2) * (n + 1) + n;
  const Eigen::Vector3d c = r.positions[corner] / kL, m = r.positions[midside] / kL;
  std::printf("%s: %s (%.2f s)\n", method, r.status.c_str(), r.wall_time_s);
  std::printf("  corner  x/L %.3f  y/L %.3f  z/L %.3f   midside x/L %.3f  z/L %.3f\n", c.x(), c.y(),
              -c.z(), m.x(), -m.z());
  std::printf("  seed experiment: corner 0.39 0.38 0.39, midside 0.18 0.40 (see VALIDATION.md)\n");
  // The frictionless table is the only support: its vertical reactions carry the weight.
  const double weight =
      scene.problem.material.areal_density * kL * kL * scene.problem.gravity.norm();
  double lift = 0.0;
  for (const auto& f : r.reactions) lift += f.force.z();
  const double err = std::abs(lift - weight) / weight;
  std::printf("  table reaction %.6e N vs weight %.6e N: error %.2e\n", lift, weight, err);
  EXPECT_LT(err, 1e-4);
  // No node inside the table beyond the penalty's penetration.
  double deepest = 0.0;
  for (const auto& x : r.positions)
    deepest = std::min(deepest, scene.problem.colliders[0]->project(x).gap);
  std::printf("  deepest penetration %.3e m\n", -deepest);
  EXPECT_GT(deepest, -1e-5);
  // Everything beyond the table hangs below its top.
  for (std::size_t i = 0; i < r.positions.size(); ++i) {
    const Eigen::Vector3d& x0 = scene.problem.mesh.vertices[i];
    if (std::max(std::abs(x0.x()), std::abs(x0.y())) > 0.05) {
      EXPECT_LT(r.positions[i].z(), 0.0);
    }
  }
}

TEST(Tablecloth, FemShellDrapeIsAStaticEquilibrium) {
  const Scene scene = loadScene(std::string(CHS_SOURCE_DIR) + "/scenes/tablecloth_fem.yaml");
  const DrapeResult r = solveFemShell(scene.problem, scene.fem_shell);
  ASSERT_TRUE(r.converged) << r.status;
  EXPECT_LE(r.residual, scene.fem_shell.tolerance);
  report("FEM shell", scene, r);
  // The symmetric flat start would keep the diagonal mirror symmetry; the energy minimiser
  // leaves it where it is not a minimum and must end on a stable equilibrium.
  const int n = 20;
  double asym = 0.0;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const Eigen::Vector3d a = r.positions[j * (n + 1) + i], b = r.positions[i * (n + 1) + j];
      asym = std::max(asym, (a - Eigen::Vector3d(b.y(), b.x(), b.z())).norm());
    }
  std::printf("  mirror asymmetry about the diagonal: %.2e m; %s, lowest eigenvalue %.3e\n", asym,
              r.stability.verdict.c_str(), r.stability.lowest_eigenvalue);
  EXPECT_TRUE(r.stability.stable);
  EXPECT_GT(r.stability.lowest_eigenvalue, 0.0);
}

TEST(Tablecloth, ParticleDrapeIsAStaticEquilibrium) {
  const Scene scene = loadScene(std::string(CHS_SOURCE_DIR) + "/scenes/tablecloth_particle.yaml");
  const DrapeResult r = solveParticleStatic(scene.problem, scene.particle);
  ASSERT_TRUE(r.converged) << r.status;
  report("particle", scene, r);
}

}  // namespace
}  // namespace chs
