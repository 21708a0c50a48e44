// Seed 001's drapes with the solid shell: the clamped warp and weft strips of section 3.1 against
// the FEM shell (side view), dynamic relaxation (section 4.2) against the static scheme, a drape
// on a table with contact, and the scene format / drape tool for method solid_shell.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/fem_shell/fem_shell_solver.h"
#include "cloth_hair_sim/core/io/scene.h"
#include "cloth_hair_sim/core/solid_shell/solid_shell_model.h"
#include "cloth_hair_sim/core/solid_shell/solid_shell_solver.h"
#include "drape_tool_runner.h"

namespace chs {
namespace {

const std::string kScenes = std::string(CHS_SOURCE_DIR) + "/scenes/";

// The FEM shell's isotropic counterpart of a strip cut along `along` (0 warp, 1 weft): the same
// thickness, density and nu, and E giving the woven bending rigidity of that direction.
DrapeProblem femCounterpart(const Scene& scene, int along) {
  DrapeProblem p = scene.problem;
  const WovenFabric& f = *p.fabric;
  const double B = along == 0 ? f.bending_warp : f.bending_weft;
  p.material.young = 12.0 * (1.0 - f.poisson * f.poisson) * B / std::pow(f.thickness, 3);
  p.fabric.reset();
  return p;
}

// Seed 001 section 3.2's set-up on a coarse mesh: a 20 x 20 cm wool sheet on a 10 x 10 cm table,
// 8 x 8 quads, held from sliding and spinning on the frictionless top; solid_shell settings given.
Scene sheetOnTable(const std::string& solid_shell) {
  return parseScene(
      "method: solid_shell\ngravity: [0, 0, -9.80665]\n"
      "garment: {rectangle: {size: [0.2, 0.2], cells: [8, 8], centre: [0, 0, 0]}}\n"
      "material: {woven: wool_suiting_kes, warp: [1, 0, 0]}\n"
      "colliders: [{table: {top_centre: [0, 0, 0], size: [0.1, 0.1], depth: 0.2}}]\n"
      "boundary: {fixed: [{vertices: {nearest: [0, 0, 0]}, axes: [x, y]},\n"
      "                   {vertices: {nearest: [0.1, 0, 0]}, axes: [y]}]}\n"
      "solid_shell: " +
          solid_shell + "\n",
      "", "sheet");
}

// Section 3.1, Fig. 4(b): side views of the 5 cm warp and weft strips under their own weight,
// solid shell (seed multiplier scheme) against the FEM shell on the same 10 x 1 and 20 x 1 meshes.
TEST(SolidShellDrape, ClampedWarpAndWeftStripsAgainstFemShell) {
  double tip[2] = {0, 0};
  for (int cut = 0; cut < 2; ++cut) {
    Scene scene = loadScene(
        kScenes + (cut == 0 ? "strip_warp_solid_shell.yaml" : "strip_weft_solid_shell.yaml"));
    for (int cells : {10, 20}) {
      if (cells == 20) {
        scene = parseScene(
            "method: solid_shell\ngravity: [0, 0, -9.80665]\n"
            "garment: {rectangle: {size: [0.05, 0.01], cells: [20, 1], centre: [0.025, 0, 0]}}\n"
            "material: {woven: wool_suiting_kes, warp: " +
                std::string(cut == 0 ? "[1, 0, 0]" : "[0, 1, 0]") +
                "}\nboundary: {clamped: {plane: {axis: x, value: 0}}}\n",
            "", "strip20");
      }
      SolidShellSettings s;
      s.multiplier = 0.05;  // the seed's 1e-2 needs ~3000 iterations; the end state is the same
      s.free_length = 0.05;
      const DrapeResult solid = solveSolidShell(scene.problem, s);
      ASSERT_TRUE(solid.converged) << solid.status;
      const DrapeResult fem = solveFemShell(femCounterpart(scene, cut), FemShellSettings());
      ASSERT_TRUE(fem.converged) << fem.status;
      std::printf("%s strip, %d x 1: side view x [mm], z [mm] solid shell | FEM shell\n",
                  cut == 0 ? "warp" : "weft", cells);
      double worst = 0.0;
      for (int i = 0; i <= cells; ++i) {
        const Eigen::Vector3d a = solid.positions[i], b = fem.positions[i];
        worst = std::max(worst, (a - b).norm());
        if (i % (cells / 5) == 0)
          std::printf("  %6.2f %7.2f | %6.2f %7.2f\n", 1e3 * a.x(), 1e3 * a.z(), 1e3 * b.x(),
                      1e3 * b.z());
      }
      std::printf("  largest node distance %.3f mm (%.2f %% of the 50 mm strip), %d iterations\n",
                  1e3 * worst, 100 * worst / 0.05, solid.iterations);
      EXPECT_LT(worst, 0.01 * 0.05);
      if (cells == 20) tip[cut] = solid.positions[cells].z();
    }
  }
  // The weft is the softer direction: its strip hangs lower.
  std::printf("tip z: warp %.2f mm, weft %.2f mm\n", 1e3 * tip[0], 1e3 * tip[1]);
  EXPECT_LT(tip[1], tip[0]);
}

// Section 4.2: dynamic relaxation (central differences, Rayleigh damping, mass scaling 100) ends
// where the static scheme ends. alpha = 2 / s is near the critical damping of the strip's first
// mode under the scaled mass (the seed's 5 / s is overdamped and settles 3 x slower).
TEST(SolidShellDrape, DynamicRelaxationEndsAtTheStaticDrape) {
  const Scene scene = loadScene(kScenes + "strip_warp_solid_shell.yaml");
  SolidShellSettings s;
  s.multiplier = 0.05;
  s.free_length = 0.05;
  const DrapeResult st = solveSolidShell(scene.problem, s);
  ASSERT_TRUE(st.converged) << st.status;
  s.scheme = SolidShellScheme::kDynamic;
  s.mass_scaling = 100;
  s.damping = 2.0;
  s.tolerance = 1e-3;
  s.end_time = 60;
  const DrapeResult dy = solveSolidShell(scene.problem, s);
  ASSERT_TRUE(dy.converged) << dy.status;
  double worst = 0.0;
  for (std::size_t v = 0; v < st.positions.size(); ++v)
    worst = std::max(worst, (st.positions[v] - dy.positions[v]).norm());
  std::printf("dynamic relaxation: %s; largest distance to the static drape %.3f mm, %.1f s\n",
              dy.status.c_str(), 1e3 * worst, dy.wall_time_s);
  EXPECT_LT(worst, 0.5e-3);
}

// The energy scheme (ours) minimises the total potential: strain energy, the weights' work and the
// penalty's potential. Its gradient must be the model's out-of-balance force, contact included:
// central differences of the energy against -R on a sheet pressed into a table near its edge.
TEST(SolidShellDrape, PotentialEnergyGradientIsTheOutOfBalanceForce) {
  Scene scene = parseScene(
      "method: solid_shell\ngravity: [0, 0, -9.80665]\n"
      "garment: {rectangle: {size: [0.06, 0.06], cells: [3, 3], centre: [0.041, 0, 0]}}\n"
      "material: {woven: wool_suiting_kes, warp: [1, 0, 0]}\n"
      "colliders: [{table: {top_centre: [0, 0, 0], size: [0.1, 0.1], depth: 0.2}}]\n",
      "", "sheet");
  SolidShellModel model(scene.problem, ThicknessStrain::kGreen, 0.5, 1.0e4);
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 1.0);
  Eigen::VectorXd D(model.size());
  for (int i = 0; i < model.size(); ++i) D[i] = (model.isTranslation(i) ? 2e-4 : 2e-2) * noise(rng);
  model.setFreeState(D);
  Eigen::VectorXd R;
  model.assemble(R, nullptr);
  ASSERT_GT(model.activeContacts(), 0);
  double worst = 0.0;
  for (int i = 0; i < model.size(); ++i) {
    const double h = model.isTranslation(i) ? 1e-8 : 1e-6;
    Eigen::VectorXd Dp = D, Dm = D;
    Dp[i] += h;
    Dm[i] -= h;
    model.setFreeState(Dp);
    const double ep = model.potentialEnergy(1.0);
    model.setFreeState(Dm);
    const double em = model.potentialEnergy(1.0);
    worst = std::max(worst, std::abs((ep - em) / (2 * h) + R[i]));
  }
  std::printf("energy gradient vs -R: worst difference %.3g of |R|_inf %.3g, %d contacts\n", worst,
              R.cwiseAbs().maxCoeff(), model.activeContacts());
  EXPECT_LT(worst, 1e-5 * R.cwiseAbs().maxCoeff());
}

// The energy scheme on the clamped warp strip ends where the seed's multiplier scheme ends, and
// reports the equilibrium stable.
TEST(SolidShellDrape, EnergySchemeMatchesTheSeedsStaticScheme) {
  const Scene scene = loadScene(kScenes + "strip_warp_solid_shell.yaml");
  SolidShellSettings s;
  s.multiplier = 0.05;
  s.free_length = 0.05;
  s.tolerance = 1e-8;
  const DrapeResult st = solveSolidShell(scene.problem, s);
  ASSERT_TRUE(st.converged) << st.status;
  s.scheme = SolidShellScheme::kEnergy;
  const DrapeResult en = solveSolidShell(scene.problem, s);
  ASSERT_TRUE(en.converged) << en.status;
  double worst = 0.0;
  for (std::size_t v = 0; v < st.positions.size(); ++v)
    worst = std::max(worst, (st.positions[v] - en.positions[v]).norm());
  std::printf(
      "energy scheme: %s (%d iterations, %.2f s; multiplier scheme %d, %.2f s); largest "
      "distance %.3g mm; lowest eigenvalue %.3g\n",
      en.status.c_str(), en.iterations, en.wall_time_s, st.iterations, st.wall_time_s, 1e3 * worst,
      en.stability.lowest_eigenvalue);
  EXPECT_LT(worst, 1e-6);
  EXPECT_TRUE(en.stability.assessed && en.stability.stable) << en.stability.verdict;
}

// The table case the seed's scheme does not settle (below: dynamic relaxation, 1e5 explicit
// steps): the energy scheme converges to a stable drape whose contact reactions carry the weight.
TEST(SolidShellDrape, SheetOnTableByEnergyMinimisation) {
  const Scene scene = sheetOnTable("{scheme: energy, tolerance: 1.0e-8, contact_stiffness: 1.0e4}");
  const DrapeResult r = solveSolidShell(scene.problem, scene.solid_shell);
  ASSERT_TRUE(r.converged) << r.status;
  double lowest = 0.0, deepest = 0.0, carried = 0.0;
  for (const auto& x : r.positions) {
    lowest = std::min(lowest, x.z());
    if (std::abs(x.x()) < 0.05 && std::abs(x.y()) < 0.05) deepest = std::min(deepest, x.z());
  }
  for (const auto& c : r.reactions) carried += c.force.z();
  const double weight = scene.problem.fabric->areal_density * 0.04 * 9.80665;
  std::printf(
      "sheet on table (8 x 8), energy scheme: %s, %.2f s; lowest node %.2f mm, deepest on the top "
      "%.4f mm; table carries %.9f N of %.9f N; lowest eigenvalue %.3g\n",
      r.status.c_str(), r.wall_time_s, 1e3 * lowest, 1e3 * deepest, carried, weight,
      r.stability.lowest_eigenvalue);
  EXPECT_TRUE(r.stability.assessed && r.stability.stable) << r.stability.verdict;
  EXPECT_NEAR(carried, weight, 1e-6 * weight);
  EXPECT_LT(lowest, -0.04);
  EXPECT_GT(deepest, -1e-4);
  EXPECT_EQ(r.status.find("interpenetrate"), std::string::npos) << r.status;
}

// A 20 x 20 cm sheet on a 10 x 10 cm table (seed 001 section 3.2's set-up, coarse 8 x 8 mesh)
// by dynamic relaxation (section 4.2): penalty contact holds it and the overhang hangs. The
// seed's static scheme does not settle this case (docs/VALIDATION.md). k_c = 1e4 N/m instead of
// the default 100 x the tensile rigidity doubles the stable time step; the penetration stays
// below 0.1 mm.
TEST(SolidShellDrape, SheetOnTableByDynamicRelaxation) {
  const Scene scene = sheetOnTable(
      "{scheme: dynamic, mass_scaling: 100, damping: 2, tolerance: 2.0e-3, end_time: 30, "
      "contact_stiffness: 1.0e4}");
  const DrapeResult r = solveSolidShell(scene.problem, scene.solid_shell);
  ASSERT_TRUE(r.converged) << r.status;
  double lowest = 0.0, deepest = 0.0;
  for (const auto& x : r.positions) {
    lowest = std::min(lowest, x.z());
    if (std::abs(x.x()) < 0.05 && std::abs(x.y()) < 0.05) deepest = std::min(deepest, x.z());
  }
  std::printf(
      "sheet on table (8 x 8): %s; lowest node %.1f mm, deepest on the top %.4f mm, "
      "%d contacts, %.1f s\n",
      r.status.c_str(), 1e3 * lowest, 1e3 * deepest, static_cast<int>(r.reactions.size()),
      r.wall_time_s);
  EXPECT_LT(lowest, -0.04);   // the 5 cm overhang hangs
  EXPECT_GT(deepest, -1e-4);  // penetration below 0.1 mm
  // On 6 x 6 quads the folds are too sharp for the mesh and 40 element corners turn their
  // director below the mid-surface (seed 001 section 4.3's interpenetration); 8 x 8 has none.
  EXPECT_EQ(r.status.find("interpenetrate"), std::string::npos) << r.status;
}

TEST(SolidShellScene, OrthotropicFabricWithoutWarpIsBadInput) {
  const std::string base =
      "method: solid_shell\ngarment: {rectangle: {size: [0.05, 0.01], cells: [4, 1]}}\n"
      "boundary: {clamped: 0}\n";
  for (const char* material :
       {"material: wool_suiting_kes\n", "material: {woven: wool_suiting_kes}\n",
        "material: {woven: wool_suiting_kes, warp: [0, 0, 0]}\n",
        "material: {woven: {preset: wool_suiting_kes, bending_weft: -1}, warp: [1, 0, 0]}\n"}) {
    try {
      parseScene(base + material, "", "bad");
      ADD_FAILURE() << material << " was accepted";
    } catch (const InputError& e) {
      std::printf("%s  -> %s\n", material, e.what());
    }
  }
  EXPECT_THROW(
      parseScene(base + "material: cotton_eischen\nsolid_shell: {scheme: implicit}\n", "", "bad"),
      InputError);
}

// The drape tool runs method solid_shell from a scene and reports it; an orthotropic fabric with
// another method is refused.
TEST(SolidShellScene, DrapeToolRunsTheWarpStrip) {
  const std::string out = ::testing::TempDir() + "solid_shell_strip";
  const auto run = testing::drape(kScenes + "strip_warp_solid_shell.yaml --quiet --out " + out);
  EXPECT_EQ(run.status, 0) << run.output;
  std::ifstream in(out + "/report.json");
  ASSERT_TRUE(in.good());
  const nlohmann::json j = nlohmann::json::parse(in);
  std::printf("drape tool: method %s, converged %d, %d iterations, %.2f s\n",
              j["method"].get<std::string>().c_str(), j["converged"].get<bool>(),
              j["iterations"].get<int>(), j["wall_time_s"].get<double>());
  EXPECT_EQ(j["method"], "solid_shell");
  EXPECT_TRUE(std::filesystem::exists(out + "/draped.obj"));
  const auto other = testing::drape(
      kScenes + "strip_warp_solid_shell.yaml --quiet --method fem_shell --out " + out);
  EXPECT_EQ(other.status, 1);
  EXPECT_NE(other.output.find("solid_shell only"), std::string::npos);
}

}  // namespace
}  // namespace chs
