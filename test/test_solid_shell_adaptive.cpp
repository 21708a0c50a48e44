// Seed 001 section 5: the reversible adaptive 1-4 subdivision of the solid shell. The active mesh
// stays conforming through random refinements and merges (every interior edge shared by two
// elements, areas summing to the sheet's), passes the membrane patch test across its
// macro-transition elements, and the discrete Kirchhoff condition places new mid-edge nodes on a
// bent sheet far closer than linear interpolation. Drapes: a strip refined near its clamp
// against the uniform fine mesh, and the sheet on a table whose coarse mesh turns directors
// inside out (interpenetration, section 4.3) with none once adaptive.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <string>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/io/scene.h"
#include "cloth_hair_sim/core/solid_shell/adaptive_mesh.h"
#include "cloth_hair_sim/core/solid_shell/solid_shell_solver.h"
#include "drape_tool_runner.h"

namespace chs {
namespace {

const std::string kScenes = std::string(CHS_SOURCE_DIR) + "/scenes/";

// A W x H sheet of nx x ny quads in the x-y plane, centred on the origin, directors +z.
QuadMesh sheet(double W, double H, int nx, int ny) {
  QuadMesh m;
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i)
      m.vertices.emplace_back(W * (static_cast<double>(i) / nx - 0.5),
                              H * (static_cast<double>(j) / ny - 0.5), 0.0);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const int v = j * (nx + 1) + i;
      m.quads.push_back({v, v + 1, v + nx + 2, v + nx + 1});
    }
  return m;
}

std::vector<Eigen::Vector3d> up(const QuadMesh& m) {
  return std::vector<Eigen::Vector3d>(m.vertices.size(), Eigen::Vector3d::UnitZ());
}

// Conformity of the active mesh: each element edge shared by two elements, or once on the
// sheet's boundary; element areas (positive, counter-clockwise) summing to the sheet's.
void expectConforming(const AdaptiveQuadMesh& mesh, double W, double H, int round) {
  const auto& X = mesh.background().vertices;
  std::map<std::pair<int, int>, int> uses;
  double area = 0.0;
  int triangles = 0;
  for (const auto& e : mesh.elements()) {
    const int n = e.nodes[3] < 0 ? 3 : 4;
    triangles += n == 3;
    for (int k = 0; k < n; ++k) {
      const int a = e.nodes[k], b = e.nodes[(k + 1) % n];
      ++uses[{std::min(a, b), std::max(a, b)}];
    }
    // Shoelace (z components of the fan's cross products).
    for (int k = 1; k + 1 < n; ++k) {
      const double t =
          0.5 * (X[e.nodes[k]] - X[e.nodes[0]]).cross(X[e.nodes[k + 1]] - X[e.nodes[0]]).z();
      ASSERT_GT(t, 0.0) << "round " << round << ": an element is folded or clockwise";
      area += t;
    }
  }
  double boundary = 0.0;
  for (const auto& [edge, count] : uses) {
    ASSERT_LE(count, 2) << "round " << round;
    if (count == 2) continue;
    const Eigen::Vector3d a = X[edge.first], b = X[edge.second];
    auto on = [&](const Eigen::Vector3d& p) {
      return std::abs(std::abs(p.x()) - W / 2) < 1e-12 || std::abs(std::abs(p.y()) - H / 2) < 1e-12;
    };
    ASSERT_TRUE(on(a) && on(b) && on(0.5 * (a + b)))
        << "round " << round << ": an edge used once inside the sheet (a hanging node)";
    boundary += (b - a).norm();
  }
  EXPECT_NEAR(area, W * H, 1e-12) << "round " << round;
  EXPECT_NEAR(boundary, 2 * (W + H), 1e-12) << "round " << round;
  EXPECT_LE(triangles, static_cast<int>(mesh.leaves().size()));
}

TEST(AdaptiveMesh, StaysConformingThroughRandomRefinementsAndMerges) {
  const double W = 0.3, H = 0.2;
  const QuadMesh level0 = sheet(W, H, 3, 2);
  AdaptiveQuadMesh mesh(level0, up(level0), 3);
  EXPECT_EQ(mesh.numNodes(), (3 * 8 + 1) * (2 * 8 + 1));
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> flag(-1, 1);
  int most = 0, transitions = 0;
  for (int round = 0; round < 60; ++round) {
    std::vector<int> flags(mesh.leaves().size());
    // Refine more than merge for the first half, then mostly merge.
    for (int& f : flags) f = round < 30 ? std::max(flag(rng), flag(rng)) : std::min(flag(rng), 0);
    mesh.adapt(flags);
    expectConforming(mesh, W, H, round);
    if (HasFatalFailure()) return;
    most = std::max(most, mesh.numActiveNodes());
    int tri = 0;
    for (const auto& e : mesh.elements()) tri += e.nodes[3] < 0;
    transitions += tri;
    // Neighbours within one level: a leaf's elements only ever use its own lattice.
    for (const auto& c : mesh.leaves()) EXPECT_LE(c.level, 3);
  }
  std::printf(
      "60 random adaptations of 3 x 2 quads, 3 levels: at most %d of %d nodes active, "
      "%d transition triangles met; back to %zu leaves\n",
      most, mesh.numNodes(), transitions, mesh.leaves().size());
  EXPECT_GT(transitions, 0);
  // Merging all the way back: level 0 again.
  for (int round = 0; round < 10; ++round) mesh.adapt(std::vector<int>(mesh.leaves().size(), -1));
  EXPECT_EQ(mesh.leaves().size(), 6u);
  EXPECT_EQ(mesh.numActiveNodes(), 12);
}

TEST(AdaptiveMesh, LevelBeyondTheLimitIsBadInput) {
  const QuadMesh level0 = sheet(0.1, 0.1, 1, 1);
  try {
    AdaptiveQuadMesh mesh(level0, up(level0), kMaxAdaptiveLevels + 1);
    FAIL() << "accepted";
  } catch (const InputError& e) {
    std::printf("message: %s\n", e.what());
    EXPECT_NE(std::string(e.what()).find("adaptive_levels"), std::string::npos);
  }
  SolidShellSettings s;
  s.adaptive_levels = kMaxAdaptiveLevels + 1;
  EXPECT_THROW(validateSolidShellSettings(s), InputError);
  s.adaptive_levels = 2;
  s.merge_margin = s.refine_threshold;  // would merge what it just split
  EXPECT_THROW(validateSolidShellSettings(s), InputError);
}

// A mesh refined twice around one corner, with every transition pattern met along the way.
AdaptiveQuadMesh cornerRefined(const QuadMesh& level0) {
  AdaptiveQuadMesh mesh(level0, up(level0), 3);
  for (int round = 0; round < 3; ++round) {
    std::vector<int> flags(mesh.leaves().size(), 0);
    for (std::size_t k = 0; k < flags.size(); ++k) {
      const auto c = mesh.corners(mesh.leaves()[k]);
      const Eigen::Vector3d x = mesh.background().vertices[c[0]];
      flags[k] = x.x() < -0.05 + 1e-9 && x.y() < -0.05 + 1e-9 ? 1 : 0;  // the cell at the corner
    }
    mesh.adapt(flags);
  }
  return mesh;
}

// Membrane patch test across levels: a homogeneous in-plane deformation x = F X with the
// directors unchanged strains every element alike (no bending or shear), so the energy is the
// closed form and the forces at every node off the boundary balance, the hanging ones included.
TEST(AdaptiveMesh, PatchTestAcrossTransitionElements) {
  const QuadMesh level0 = sheet(0.2, 0.2, 2, 2);
  AdaptiveQuadMesh mesh = cornerRefined(level0);
  int triangles = 0;
  for (const auto& e : mesh.elements()) triangles += e.nodes[3] < 0;
  ASSERT_GT(triangles, 0);
  DrapeProblem problem;
  problem.mesh = level0;
  problem.gravity.setZero();
  ShellMaterial& m = problem.material;
  m.young = 1e6, m.poisson = 0.3, m.thickness = 1e-3, m.areal_density = 0.2;
  SolidShellModel model(problem, mesh.activeMesh({}), ThicknessStrain::kGreen, 0.5, 0.0);
  Eigen::Matrix3d F = Eigen::Matrix3d::Identity();
  F.topLeftCorner<2, 2>() << 1.02, 0.01, -0.005, 0.97;
  const auto& X = mesh.background().vertices;
  std::vector<Eigen::Vector3d> u(X.size()), un(X.size(), Eigen::Vector3d::Zero());
  for (std::size_t v = 0; v < X.size(); ++v) u[v] = (F - Eigen::Matrix3d::Identity()) * X[v];
  model.setDisplacements(u, un);
  Eigen::VectorXd R;
  const double energy = model.assemble(R, nullptr);
  const Eigen::Matrix2d E = 0.5 * (F.topLeftCorner<2, 2>().transpose() * F.topLeftCorner<2, 2>() -
                                   Eigen::Matrix2d::Identity());
  const Eigen::Vector3d eps(E(0, 0), E(1, 1), 2 * E(0, 1));
  Eigen::Matrix3d C;
  C << 1, m.poisson, 0, m.poisson, 1, 0, 0, 0, 0.5 * (1 - m.poisson);
  C *= m.membraneStiffness();
  const double exact = 0.5 * eps.dot(C * eps) * 0.04;
  // Interior forces: the model's unknowns of active nodes off the boundary.
  double interior = 0.0, scale = 0.0;
  const SolidShellMesh active = mesh.activeMesh({});
  std::vector<Eigen::Vector3d> f(X.size(), Eigen::Vector3d::Zero());
  int k = 0;
  for (std::size_t v = 0; v < X.size(); ++v) {
    if (!model.isActive(static_cast<int>(v))) continue;
    for (int a = 0; a < 6; ++a, ++k)
      if (a < 3) f[v][a] = R[k];
  }
  for (std::size_t v = 0; v < X.size(); ++v) {
    if (!model.isActive(static_cast<int>(v))) continue;
    scale = std::max(scale, f[v].norm());
    if (std::abs(std::abs(X[v].x()) - 0.1) > 1e-12 && std::abs(std::abs(X[v].y()) - 0.1) > 1e-12)
      interior = std::max(interior, f[v].norm());
  }
  std::printf(
      "patch test on %zu elements (%d triangles), %d active nodes: energy %.10e J, exact "
      "%.10e J; largest interior force %.2e N (boundary %.2e N)\n",
      active.elements.size(), triangles, mesh.numActiveNodes(), energy, exact, interior, scale);
  EXPECT_NEAR(energy, exact, 1e-9 * exact);
  EXPECT_LT(interior, 1e-9 * scale);
}

// A sheet bent onto a cylinder of radius rho about the x axis: positions on the arc, directors
// normal to it. Places the bent state on the active nodes of `mesh`.
void bend(const AdaptiveQuadMesh& mesh, double rho, std::vector<Eigen::Vector3d>& u,
          std::vector<Eigen::Vector3d>& un) {
  const auto& X = mesh.background().vertices;
  u.assign(X.size(), Eigen::Vector3d::Zero());
  un.assign(X.size(), Eigen::Vector3d::Zero());
  for (std::size_t v = 0; v < X.size(); ++v) {
    const double phi = X[v].y() / rho;
    const Eigen::Vector3d n(0, -std::sin(phi), std::cos(phi));
    u[v] = Eigen::Vector3d(X[v].x(), rho * std::sin(phi), rho - rho * std::cos(phi)) - X[v];
    un[v] = n - Eigen::Vector3d::UnitZ();
  }
}

TEST(DiscreteKirchhoff, RigidMotionIsReproducedExactly) {
  const QuadMesh level0 = sheet(0.2, 0.1, 2, 1);
  AdaptiveQuadMesh mesh(level0, up(level0), 2);
  const Eigen::Matrix3d R =
      Eigen::AngleAxisd(0.9, Eigen::Vector3d(1, -2, 0.5).normalized()).toRotationMatrix();
  const Eigen::Vector3d t(0.03, -0.2, 0.5);
  const auto& X = mesh.background().vertices;
  std::vector<Eigen::Vector3d> u(X.size()), un(X.size());
  for (std::size_t v = 0; v < X.size(); ++v) {
    u[v] = R * X[v] + t - X[v];
    un[v] = R * Eigen::Vector3d::UnitZ() - Eigen::Vector3d::UnitZ();
  }
  const std::vector<Eigen::Vector3d> exact_u = u, exact_un = un;
  const std::vector<bool> before = mesh.activeNodes();
  for (std::size_t v = 0; v < X.size(); ++v)
    if (!before[v]) u[v].setConstant(1e3), un[v].setConstant(1e3);  // garbage to overwrite
  mesh.adapt(std::vector<int>(mesh.leaves().size(), 1));
  mesh.adapt(std::vector<int>(mesh.leaves().size(), 1));
  mesh.fillSwitchedOnNodes(before, u, un);
  double worst = 0.0;
  int filled = 0;
  const std::vector<bool> now = mesh.activeNodes();
  for (std::size_t v = 0; v < X.size(); ++v)
    if (now[v] && !before[v]) {
      ++filled;
      worst = std::max({worst, (u[v] - exact_u[v]).norm(), (un[v] - exact_un[v]).norm()});
    }
  std::printf("rigid motion, %d nodes switched on over two levels: largest error %.2e\n", filled,
              worst);
  EXPECT_EQ(filled, mesh.numNodes() - 6);
  EXPECT_LT(worst, 1e-14);
}

// Seed 001 5.4's point: a new node by the discrete Kirchhoff condition sits on the bent surface,
// where linear interpolation cuts the chord (and leaves out-of-balance forces that shake a
// dynamic run).
TEST(DiscreteKirchhoff, NewNodesFollowABentSheetUnlikeLinearInterpolation) {
  const QuadMesh level0 = sheet(0.1, 0.1, 1, 4);  // edges of 2.5 cm along the bend
  AdaptiveQuadMesh mesh(level0, up(level0), 1);
  const double rho = 0.05;
  std::vector<Eigen::Vector3d> exact_u, exact_un;
  bend(mesh, rho, exact_u, exact_un);
  const std::vector<bool> before = mesh.activeNodes();
  std::vector<Eigen::Vector3d> u = exact_u, un = exact_un;
  mesh.adapt(std::vector<int>(mesh.leaves().size(), 1));
  mesh.fillSwitchedOnNodes(before, u, un);
  const auto& X = mesh.background().vertices;
  double dk = 0.0, linear = 0.0, director = 0.0;
  // Mid-edge nodes of the level-0 edges along the bend (between nodes differing in y).
  for (int q = 0; q < 4; ++q)
    for (int side : {0, 2}) {
      const int a = side == 0 ? 0 : 2;
      const int A = mesh.node(q, a, 0), B = mesh.node(q, a, 2), M = mesh.node(q, a, 1);
      const Eigen::Vector3d exact = X[M] + exact_u[M];
      dk = std::max(dk, (X[M] + u[M] - exact).norm());
      linear = std::max(linear, (0.5 * (X[A] + exact_u[A] + X[B] + exact_u[B]) - exact).norm());
      director = std::max(director, (un[M] - exact_un[M]).norm());
    }
  std::printf(
      "cylinder of radius %.0f mm, 25 mm edges: new mid-edge node off the surface by "
      "%.3e mm (discrete Kirchhoff) vs %.3e mm (linear); director off by %.2e\n",
      1e3 * rho, 1e3 * dk, 1e3 * linear, director);
  EXPECT_LT(dk, 0.02 * linear);
  EXPECT_LT(director, 2e-3);
}

// The clamped 5 cm warp strip of seed 001 3.1 from 5 x 1 level-0 quads, adapting up to 2 levels,
// against the uniform 20 x 4 mesh (the finest the adaptive mesh can reach).
TEST(AdaptiveDrape, ClampedStripAgainstTheUniformFineMesh) {
  auto strip = [](int cells) {
    return parseScene(
        "method: solid_shell\ngravity: [0, 0, -9.80665]\n"
        "garment: {rectangle: {size: [0.05, 0.01], cells: [" +
            std::to_string(cells) + ", " + std::to_string(cells / 5) +
            "], centre: [0.025, 0, 0]}}\n"
            "material: {woven: wool_suiting_kes, warp: [1, 0, 0]}\n"
            "boundary: {clamped: {plane: {axis: x, value: 0}}}\n",
        "", "strip");
  };
  SolidShellSettings s;
  s.multiplier = 0.05;
  s.free_length = 0.05;
  const Scene fine = strip(20);
  const DrapeResult uniform = solveSolidShell(fine.problem, s);
  ASSERT_TRUE(uniform.converged) << uniform.status;
  const Scene coarse = strip(5);
  s.adaptive_levels = 2;
  s.refine_threshold = 0.1;
  s.merge_margin = 0.05;
  const DrapeResult adaptive = solveSolidShell(coarse.problem, s);
  ASSERT_TRUE(adaptive.converged) << adaptive.status;
  ASSERT_TRUE(adaptive.refined_mesh.has_value());
  // The background's tip nodes: largest x.
  double tip_uniform = 0.0, tip_adaptive = 0.0, x_max = 0.0;
  for (const auto& x : fine.problem.mesh.vertices) x_max = std::max(x_max, x.x());
  for (std::size_t v = 0; v < uniform.positions.size(); ++v)
    if (fine.problem.mesh.vertices[v].x() > x_max - 1e-9)
      tip_uniform = std::min(tip_uniform, uniform.positions[v].z());
  for (std::size_t v = 0; v < adaptive.positions.size(); ++v)
    if (adaptive.refined_mesh->vertices[v].x() > x_max - 1e-9)
      tip_adaptive = std::min(tip_adaptive, adaptive.positions[v].z());
  std::printf(
      "clamped warp strip: tip z %.3f mm adaptive (%d nodes at most, %s) vs %.3f mm on "
      "the uniform 20 x 4 mesh (%d nodes): %.2f %%\n",
      1e3 * tip_adaptive, adaptive.peak_active_nodes, adaptive.status.c_str(), 1e3 * tip_uniform,
      fine.problem.mesh.numVertices(), 100 * (tip_adaptive / tip_uniform - 1));
  EXPECT_NEAR(tip_adaptive, tip_uniform, 0.01 * std::abs(tip_uniform));
  EXPECT_LT(adaptive.peak_active_nodes, fine.problem.mesh.numVertices());
}

// Seed 001 4.3 and 5: on 6 x 6 quads the sheet on the table folds too sharply for its mesh and
// element corners turn their directors below the mid-surface (top and bottom surfaces cross);
// adapting from the same level-0 mesh, none do.
TEST(AdaptiveDrape, SheetOnTableWithoutInterpenetration) {
  auto scene = [](const std::string& adaptive) {
    return parseScene(
        "method: solid_shell\ngravity: [0, 0, -9.80665]\n"
        "garment: {rectangle: {size: [0.2, 0.2], cells: [6, 6], centre: [0, 0, 0]}}\n"
        "material: {woven: wool_suiting_kes, warp: [1, 0, 0]}\n"
        "colliders: [{table: {top_centre: [0, 0, 0], size: [0.1, 0.1], depth: 0.2}}]\n"
        "boundary: {fixed: [{vertices: {nearest: [0, 0, 0]}, axes: [x, y]},\n"
        "                   {vertices: {nearest: [0.1, 0, 0]}, axes: [y]}]}\n"
        "solid_shell: {scheme: dynamic, mass_scaling: 100, damping: 2, tolerance: 2.0e-3,\n"
        "              end_time: 30, contact_stiffness: 1.0e4" +
            adaptive + "}\n",
        "", "sheet");
  };
  const Scene plain = scene("");
  const DrapeResult uniform = solveSolidShell(plain.problem, plain.solid_shell);
  const Scene adapting = scene(", adaptive_levels: 2, adapt_interval: 2000");
  const DrapeResult adaptive = solveSolidShell(adapting.problem, adapting.solid_shell);
  std::printf("sheet on table, 6 x 6 level 0: uniform %s (%.1f s)\n  adaptive %s (%.1f s)\n",
              uniform.status.c_str(), uniform.wall_time_s, adaptive.status.c_str(),
              adaptive.wall_time_s);
  EXPECT_NE(uniform.status.find("interpenetrate"), std::string::npos) << uniform.status;
  ASSERT_TRUE(adaptive.converged) << adaptive.status;
  EXPECT_EQ(adaptive.status.find("interpenetrate"), std::string::npos) << adaptive.status;
  double lowest = 0.0, deepest = 0.0;
  for (const auto& x : adaptive.positions) {
    lowest = std::min(lowest, x.z());
    if (std::abs(x.x()) < 0.05 && std::abs(x.y()) < 0.05) deepest = std::min(deepest, x.z());
  }
  std::printf("  adaptive: lowest node %.1f mm, deepest on the top %.4f mm, %d nodes at most\n",
              1e3 * lowest, 1e3 * deepest, adaptive.peak_active_nodes);
  EXPECT_LT(lowest, -0.04);
  EXPECT_GT(deepest, -1e-4);
}

// The energy scheme with adaptivity: the descent adapts every few Newton iterations (solved to the
// end on 6 x 6 quads first, 120 element corners end reversed). Against the uniform finest mesh
// (24 x 24) solved the same way: the same drape, no reversed director, fewer nodes, stable.
TEST(AdaptiveDrape, EnergySchemeOnTheTableAgainstTheUniformFinestMesh) {
  auto scene = [](int cells, const std::string& adaptive) {
    return parseScene(
        "method: solid_shell\ngravity: [0, 0, -9.80665]\n"
        "garment: {rectangle: {size: [0.2, 0.2], cells: [" +
            std::to_string(cells) + ", " + std::to_string(cells) +
            "], centre: [0, 0, 0]}}\n"
            "material: {woven: wool_suiting_kes, warp: [1, 0, 0]}\n"
            "colliders: [{table: {top_centre: [0, 0, 0], size: [0.1, 0.1], depth: 0.2}}]\n"
            "boundary: {fixed: [{vertices: {nearest: [0, 0, 0]}, axes: [x, y]},\n"
            "                   {vertices: {nearest: [0.1, 0, 0]}, axes: [y]}]}\n"
            "solid_shell: {scheme: energy, tolerance: 1.0e-6, contact_stiffness: 1.0e4" +
            adaptive + "}\n",
        "", "sheet");
  };
  const Scene fine = scene(24, "");
  const DrapeResult uniform = solveSolidShell(fine.problem, fine.solid_shell);
  ASSERT_TRUE(uniform.converged) << uniform.status;
  const Scene coarse = scene(6, ", adaptive_levels: 2");
  const DrapeResult adaptive = solveSolidShell(coarse.problem, coarse.solid_shell);
  ASSERT_TRUE(adaptive.converged) << adaptive.status;
  auto lowest = [](const DrapeResult& r) {
    double z = 0.0;
    for (const auto& x : r.positions) z = std::min(z, x.z());
    return z;
  };
  std::printf(
      "table, energy scheme: uniform 24 x 24 %s, lowest %.2f mm, %.1f s\n  adaptive 6 x 6 + 2 "
      "levels %s, lowest %.2f mm, %d nodes at most, %.1f s\n",
      uniform.status.c_str(), 1e3 * lowest(uniform), uniform.wall_time_s, adaptive.status.c_str(),
      1e3 * lowest(adaptive), adaptive.peak_active_nodes, adaptive.wall_time_s);
  EXPECT_EQ(adaptive.status.find("interpenetrate"), std::string::npos) << adaptive.status;
  EXPECT_TRUE(adaptive.stability.assessed && adaptive.stability.stable);
  EXPECT_NEAR(lowest(adaptive), lowest(uniform), 0.5e-3);
  EXPECT_LT(adaptive.peak_active_nodes, fine.problem.mesh.numVertices());
}

// The drape tool on an adaptive scene: the draped background mesh, the elements in use at the end
// (quads and triangles) in active_mesh.obj, the peak node count in the report; a level beyond
// the limit is refused with the scene key named.
TEST(AdaptiveDrape, DrapeToolWritesTheActiveMesh) {
  const std::string dir = ::testing::TempDir() + "adaptive_strip";
  std::filesystem::create_directories(dir);
  const std::string scene = dir + "/strip.yaml";
  auto write = [&](int levels) {
    std::ofstream(scene)
        << "name: adaptive_strip\nmethod: solid_shell\ngravity: [0, 0, -9.80665]\n"
           "garment: {rectangle: {size: [0.05, 0.01], cells: [5, 1], centre: [0.025, 0, 0]}}\n"
           "material: {woven: wool_suiting_kes, warp: [1, 0, 0]}\n"
           "boundary: {clamped: {plane: {axis: x, value: 0}}}\n"
           "solid_shell: {multiplier: 0.05, free_length: 0.05, adaptive_levels: "
        << levels << ", refine_threshold: 0.1, merge_margin: 0.05}\n";
  };
  write(2);
  const auto run = testing::drape(scene + " --quiet --out " + dir + "/out");
  ASSERT_EQ(run.status, 0) << run.output;
  std::ifstream obj(dir + "/out/active_mesh.obj");
  ASSERT_TRUE(obj.good());
  int vertices = 0, quads = 0, triangles = 0;
  for (std::string line; std::getline(obj, line);) {
    if (line.rfind("v ", 0) == 0) ++vertices;
    if (line.rfind("f ", 0) != 0) continue;
    const int corners = static_cast<int>(std::count(line.begin(), line.end(), ' '));
    (corners == 4 ? quads : triangles) += corners == 4 || corners == 3;
  }
  std::ifstream report(dir + "/out/report.json");
  std::string text((std::istreambuf_iterator<char>(report)), std::istreambuf_iterator<char>());
  std::printf("drape tool, adaptive strip: active_mesh.obj %d vertices, %d quads, %d triangles\n",
              vertices, quads, triangles);
  EXPECT_EQ(vertices, 21 * 5);  // the background mesh's nodes
  EXPECT_GT(quads, 5);
  EXPECT_GT(triangles, 0);
  EXPECT_NE(text.find("nodes in use at most"), std::string::npos);
  EXPECT_TRUE(std::filesystem::exists(dir + "/out/drape.png"));
  write(kMaxAdaptiveLevels + 1);
  const auto bad = testing::drape(scene + " --quiet --out " + dir + "/bad");
  EXPECT_EQ(bad.status, 1);  // bad input
  EXPECT_NE(bad.output.find("adaptive_levels"), std::string::npos) << bad.output;
}

}  // namespace
}  // namespace chs
