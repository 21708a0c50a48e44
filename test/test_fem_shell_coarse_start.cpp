// The FEM shell's nested start (core/fem_shell/coarse_start.h): which grids coarsen, the
// prolongation against an affine map (which bilinear interpolation reproduces exactly), and the
// 48 x 48 pedestal's drape from its 24 x 24 drape against the drape from the flat sheet.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

#include <Eigen/Geometry>

#include "cloth_hair_sim/core/drape/drape_metrics.h"
#include "cloth_hair_sim/core/fem_shell/coarse_start.h"
#include "cloth_hair_sim/core/fem_shell/fem_shell_solver.h"
#include "cloth_hair_sim/core/fem_shell/shell_model.h"
#include "cloth_hair_sim/core/io/material_presets.h"
#include "cloth_hair_sim/core/io/scene.h"
#include "cloth_hair_sim/core/mesh/grid_generators.h"

namespace chs {
namespace {

// A 20 x 20 cm wool sheet (bending length 16.6 mm; stiffened, stiffen^(1/3) times that) on a
// plane far below.
DrapeProblem sheet(int cells, double stiffen = 1.0) {
  DrapeProblem p;
  p.mesh = makeRectangleMesh(0.2, 0.2, cells, cells);
  p.material = *materialPreset("wool_suiting");
  p.material.young *= stiffen;
  p.gravity = Eigen::Vector3d(0, 0, -9.81);
  p.colliders.push_back(
      std::make_shared<PlaneSurface>(Eigen::Vector3d(0, 0, -1), Eigen::Vector3d::UnitZ()));
  return p;
}

TEST(FemShellCoarseStart, WhichMeshesCoarsen) {
  const auto g = GridCoarsening::of(sheet(48), 64);
  ASSERT_TRUE(g.has_value());
  const DrapeProblem& c = g->coarse();
  EXPECT_EQ(c.mesh.numVertices(), 25 * 25);
  EXPECT_EQ(c.mesh.numQuads(), 24 * 24);
  // Every coarse quad faces +z, as the fine ones do, and its corners are every second grid line.
  for (const auto& q : c.mesh.quads) {
    const auto& x = c.mesh.vertices;
    EXPECT_GT((x[q[2]] - x[q[0]]).cross(x[q[3]] - x[q[1]]).z(), 0.0);
    EXPECT_NEAR((x[q[1]] - x[q[0]]).norm(), 0.2 / 24, 1e-12);
  }
  std::string why;
  EXPECT_FALSE(GridCoarsening::of(sheet(47), 64, &why)) << "odd cell count";
  EXPECT_NE(why.find("not a 2 x 2 refinement"), std::string::npos) << why;
  EXPECT_FALSE(GridCoarsening::of(sheet(14, 1000.0), 64, &why)) << "7 x 7 coarse quads";
  EXPECT_NE(why.find("fewer than 64"), std::string::npos) << why;
  EXPECT_TRUE(GridCoarsening::of(sheet(16, 1000.0), 64));
  // 20 x 20 wool: coarse edges of 20 mm, 1.2 bending lengths: the folds would not fit.
  EXPECT_FALSE(GridCoarsening::of(sheet(20), 64, &why)) << "coarse cells too long";
  std::printf("  20 x 20 wool sheet: %s\n", why.c_str());
  EXPECT_NE(why.find("bending length"), std::string::npos) << why;
  // Recognised from the connectivity: any numbering of the vertices, quads in any order.
  DrapeProblem shuffled = sheet(48);
  std::swap(shuffled.mesh.vertices[3], shuffled.mesh.vertices[70]);
  for (auto& q : shuffled.mesh.quads)
    for (int& v : q) v = v == 3 ? 70 : v == 70 ? 3 : v;
  std::reverse(shuffled.mesh.quads.begin(), shuffled.mesh.quads.end());
  const auto s = GridCoarsening::of(shuffled, 64, &why);
  ASSERT_TRUE(s.has_value()) << why;
  EXPECT_EQ(s->coarse().mesh.numQuads(), 24 * 24);
  // The disc's O-grid (five blocks): 48 across (a ring of 12 cells, a square of 24) coarsens.
  DrapeProblem disc = sheet(48);
  disc.mesh = makeDiscMesh(0.127, 48);
  const auto d = GridCoarsening::of(disc, 64, &why);
  ASSERT_TRUE(d.has_value()) << why;
  EXPECT_EQ(4 * d->coarse().mesh.numQuads(), disc.mesh.numQuads());
  DrapeProblem loaded = sheet(48);
  loaded.bc.loads.push_back({0, Eigen::Vector3d(0, 0, 1), Eigen::Vector3d::Zero()});
  EXPECT_FALSE(GridCoarsening::of(loaded, 64)) << "nodal loads";
  DrapeProblem kawabata = sheet(48);
  kawabata.material.kawabata = KawabataBending();
  EXPECT_FALSE(GridCoarsening::of(kawabata, 64)) << "no bending length";
}

TEST(FemShellCoarseStart, ProlongationIsExactForAnAffineMap) {
  DrapeProblem fine = sheet(32, 100.0);
  fine.bc.fixed_components.push_back({5, 0});  // an odd grid line: interpolated, then restored
  fine.bc.clamped.push_back(0);
  fine.colliders.clear();
  // The map: a rotation, a stretch, a shift.
  const auto g = GridCoarsening::of(fine, 64);
  ASSERT_TRUE(g.has_value());
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).matrix();
  Eigen::Matrix3d A = R;
  A.col(0) *= 1.1;
  const Eigen::Vector3d b(0.01, -0.02, 0.3);
  std::vector<Eigen::Vector3d> x, t;
  for (const auto& X : g->coarse().mesh.vertices) {
    x.push_back(A * X + b);
    t.push_back(R * Eigen::Vector3d::UnitZ());
  }
  const ShellModel model(fine, 0.0);
  const std::vector<ShellNode> nodes = g->prolong(x, t, model.nodes(), fine);
  double position_error = 0.0, director_error = 0.0;
  for (int v = 0; v < fine.mesh.numVertices(); ++v) {
    if (v == 0 || v == 5) continue;
    position_error =
        std::max(position_error, (nodes[v].position - (A * fine.mesh.vertices[v] + b)).norm());
    director_error =
        std::max(director_error, (nodes[v].frame.director() - R * Eigen::Vector3d::UnitZ()).norm());
  }
  std::printf("  largest position error %.3g m, director error %.3g\n", position_error,
              director_error);
  EXPECT_LT(position_error, 1e-15);
  EXPECT_LT(director_error, 1e-15);
  EXPECT_EQ(nodes[0].position, model.nodes()[0].position) << "clamped";
  EXPECT_EQ(nodes[0].frame.director(), model.nodes()[0].frame.director()) << "clamped";
  EXPECT_EQ(nodes[5].position.x(), model.nodes()[5].position.x()) << "fixed along x";
  EXPECT_NE(nodes[5].position.y(), model.nodes()[5].position.y());
}

TEST(FemShellCoarseStart, InterpolatedNodesInsideAColliderAreMovedOut) {
  DrapeProblem fine = sheet(40);  // coarse cells of 10 mm, 0.6 bending lengths
  const Eigen::Vector3d centre(0, 0, -0.1);
  fine.colliders = {std::make_shared<SphereSurface>(centre, 0.1)};
  const auto g = GridCoarsening::of(fine, 64);
  ASSERT_TRUE(g.has_value());
  // The coarse nodes on the sphere: the chords between them cut into it.
  std::vector<Eigen::Vector3d> x, t;
  for (const auto& X : g->coarse().mesh.vertices) {
    const Eigen::Vector3d n = (X - centre).normalized();
    x.push_back(centre + 0.1 * n);
    t.push_back(n);
  }
  const ShellModel model(fine, 0.0);
  const std::vector<ShellNode> nodes = g->prolong(x, t, model.nodes(), fine);
  double deepest = 0.0;
  for (const auto& n : nodes)
    deepest = std::min(deepest, fine.colliders[0]->project(n.position).gap);
  std::printf("  deepest node after the prolongation: %.3g m\n", deepest);
  EXPECT_GT(deepest, -1e-12);
}

// A shipped scene's drape from its coarser mesh's (the scene sets coarse_levels: 1) against the
// drape from the flat sheet: the same drape, in at most a quarter of the fine mesh's iterations.
void expectTheSameDrape(const std::string& file, int coarse_quads) {
  Scene scene = loadScene(std::string(CHS_SOURCE_DIR) + "/scenes/" + file);
  ASSERT_EQ(scene.fem_shell.coarse_levels, 1);
  FemShellSettings flat = scene.fem_shell;
  flat.coarse_levels = 0;
  const DrapeResult a = solveFemShell(scene.problem, flat);
  const DrapeResult b = solveFemShell(scene.problem, scene.fem_shell);
  const DrapeSupport support = supportOf(scene.colliders.at(0));
  const DrapeMetrics ma = measureDrape(scene.problem.mesh, a.positions, support);
  const DrapeMetrics mb = measureDrape(scene.problem.mesh, b.positions, support);
  double largest_difference = 0.0;
  for (std::size_t v = 0; v < a.positions.size(); ++v)
    largest_difference = std::max(largest_difference, (a.positions[v] - b.positions[v]).norm());
  std::printf(
      "  %s\n  flat start: %d iterations, %.2f s, DC %.4f, %d folds, lowest %.2f mm\n"
      "  nested: %d + %d iterations, %.2f s, DC %.4f, %d folds, lowest %.2f mm\n"
      "  largest node distance between the two drapes %.3g mm\n",
      file.c_str(), a.iterations, a.wall_time_s, ma.drape_coefficient, ma.folds, 1e3 * ma.lowest_z,
      b.coarse_iterations, b.iterations - b.coarse_iterations, b.wall_time_s, mb.drape_coefficient,
      mb.folds, 1e3 * mb.lowest_z, 1e3 * largest_difference);
  ASSERT_TRUE(a.converged) << a.status;
  ASSERT_TRUE(b.converged) << b.status;
  EXPECT_TRUE(b.stability.stable);
  EXPECT_NE(b.status.find("started from the drape of the coarser mesh of " +
                          std::to_string(coarse_quads) + " quads"),
            std::string::npos)
      << b.status;
  EXPECT_EQ(mb.folds, ma.folds);
  EXPECT_NEAR(mb.drape_coefficient, ma.drape_coefficient, 1e-3);
  EXPECT_LT(largest_difference, 1e-4);  // 0.1 mm
  EXPECT_LE(4 * (b.iterations - b.coarse_iterations), a.iterations);
}

// The 48 x 48 pedestal (docs/BENCHMARKS.md's goal row) from its 24 x 24 drape.
TEST(FemShellCoarseStart, PedestalFromItsCoarseDrape) {
  expectTheSameDrape("pedestal_square_48.yaml", 24 * 24);
}

// Seed 001's disc of 25.4 cm on the 12.7 cm pedestal, 48 across (the O-grid's five blocks),
// from its drape 24 across.
TEST(FemShellCoarseStart, DiscFromItsCoarseDrape) {
  expectTheSameDrape("disc_254_on_127_fine.yaml", 2048 / 4);
}

}  // namespace
}  // namespace chs
