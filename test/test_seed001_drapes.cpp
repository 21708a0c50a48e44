// Seed 001 end to end: a wool disc of 25.4 cm on a 12.7 cm pedestal through loadScene and
// solveFemShell, checked for a sensible shape and against the drape coefficient and fold count
// measured in docs/seed001_study.md. The test uses a 24-across O-grid (the study's coarse mesh is
// 32 across) to stay well under a minute.
//
// DISABLED_MeasureStudyOutputs is the study's measuring tool, run by scripts/seed001_study.sh:
// CHS_SEED001_CASES names a file of lines "scene.yaml out_dir" (out_dir holds the drape tool's
// draped.obj); it writes out_dir/metrics.json for each.
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cloth_hair_sim/core/drape/drape_metrics.h"
#include "cloth_hair_sim/core/fem_shell/fem_shell_solver.h"
#include "cloth_hair_sim/core/io/scene.h"

namespace {

using Eigen::Vector3d;

std::string readText(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Vertex positions of an OBJ written by writeObj, in file order (the scene mesh's order).
std::vector<Vector3d> readObjPositions(const std::string& path) {
  std::ifstream in(path);
  std::vector<Vector3d> p;
  std::string line;
  while (std::getline(in, line)) {
    if (line.size() < 2 || line[0] != 'v' || line[1] != ' ') continue;
    std::istringstream ls(line.substr(2));
    Vector3d x;
    ls >> x.x() >> x.y() >> x.z();
    p.push_back(x);
  }
  return p;
}

chs::DrapeSupport supportOf(const chs::Scene& scene) {
  return chs::supportOf(scene.colliders.at(0));
}

nlohmann::json metricsJson(const chs::DrapeMetrics& m, double penetration) {
  return {{"flat_area", m.flat_area},
          {"support_area", m.support_area},
          {"shadow_area", m.shadow_area},
          {"shadow_area_error_bound", m.shadow_area_error_bound},
          {"drape_coefficient", m.drape_coefficient},
          {"folds", m.folds},
          {"fold_angles_deg",
           [&] {
             std::vector<double> a;
             for (double t : m.fold_angles) a.push_back(t * 180.0 / M_PI);
             return a;
           }()},
          {"lowest_z", m.lowest_z},
          {"highest_z", m.highest_z},
          {"min_outline_radius", m.min_outline_radius},
          {"max_outline_radius", m.max_outline_radius},
          {"mean_outline_radius", m.mean_outline_radius},
          {"max_radius", m.max_radius},
          {"max_penetration", penetration}};
}

TEST(Seed001Drapes, DISABLED_MeasureStudyOutputs) {
  const char* list = std::getenv("CHS_SEED001_CASES");
  ASSERT_NE(list, nullptr) << "set CHS_SEED001_CASES to a file of 'scene.yaml out_dir' lines";
  std::ifstream in(list);
  std::string scene_path, dir;
  while (in >> scene_path >> dir) {
    const chs::Scene scene = chs::loadScene(scene_path);
    const auto positions = readObjPositions(dir + "/draped.obj");
    ASSERT_EQ(positions.size(), scene.problem.mesh.vertices.size()) << dir;
    const chs::DrapeMetrics m = chs::measureDrape(scene.problem.mesh, positions, supportOf(scene));
    const nlohmann::json j =
        metricsJson(m, chs::maxPenetration(positions, scene.problem.colliders));
    std::ofstream(dir + "/metrics.json") << j.dump(2) << "\n";
    std::cout << scene.name << " " << dir << ": DC " << m.drape_coefficient << ", folds " << m.folds
              << ", lowest " << m.lowest_z << "\n";
  }
}

// Measured in docs/seed001_study.md for this mesh and these settings.
// Measured for the 24-across mesh of this test (the 32-across study mesh: see the study).
constexpr double kMeasuredDc = 0.512;  // energy minimisation with edge contact (0.494 before)
constexpr int kMeasuredFolds = 8;

TEST(Seed001Drapes, DiscOnPedestalCoarse) {
  // The study's scene with a 24-across mesh (rim nodes: 4 m; ~10.6 mm quads).
  std::string text = readText(std::string(CHS_SOURCE_DIR) + "/scenes/disc_254_on_127.yaml");
  const std::string from = "cells: 32", to = "cells: 24";
  const auto at = text.find(from);
  ASSERT_NE(at, std::string::npos);
  text.replace(at, from.size(), to);
  const chs::Scene scene =
      chs::parseScene(text, std::string(CHS_SOURCE_DIR) + "/scenes", "disc_254_on_127_test");
  const chs::DrapeResult r = chs::solveFemShell(scene.problem, scene.fem_shell);
  const chs::DrapeMetrics m = chs::measureDrape(scene.problem.mesh, r.positions, supportOf(scene));
  const double penetration = chs::maxPenetration(r.positions, scene.problem.colliders);
  std::cout << "  " << scene.problem.mesh.numVertices() << " nodes: " << r.status << ", "
            << r.wall_time_s << " s\n  DC " << m.drape_coefficient << " (shadow " << m.shadow_area
            << " +- " << m.shadow_area_error_bound << "), folds " << m.folds << ", lowest "
            << m.lowest_z << ", highest " << m.highest_z << ", outline r " << m.min_outline_radius
            << " - " << m.max_outline_radius << ", penetration " << penetration << "\n";
  ASSERT_TRUE(r.converged) << r.status;

  // Shape: cloth over the pedestal top rests on it (z ~ 0, within the penalty's sink), the rest
  // hangs below the top, and no node is inside the pedestal beyond the penalty tolerance.
  const double rd = scene.colliders[0].radius;
  for (size_t i = 0; i < r.positions.size(); ++i) {
    const Vector3d& p = r.positions[i];
    const double radius = p.head<2>().norm();
    // Folds may lift the cloth near the rim off the top a little (measured 1.9 mm), not more.
    EXPECT_LT(p.z(), 5e-3) << "node " << i << " lifted off";
    // Fold crests run onto the top: at 0.8 rd the cloth stands 1.0 mm off it (measured), so
    // only the inner half must lie on it.
    if (radius < 0.5 * rd) {
      EXPECT_NEAR(p.z(), 0.0, 5e-4) << "node " << i << " not on the top";
    }
    if (scene.problem.mesh.vertices[i].head<2>().norm() > rd + 0.02) {
      EXPECT_LT(p.z(), -0.005) << "node " << i << " of the hanging part is not hanging";
    }
  }
  EXPECT_LT(penetration, 1e-3);  // 1 mm: the penalty lets a node sink by weight / k_c
  EXPECT_LT(m.lowest_z, -0.03);
  EXPECT_GT(m.lowest_z, -(0.127 - rd) - 1e-3);          // no deeper than the hanging length
  EXPECT_NEAR(m.drape_coefficient, kMeasuredDc, 0.03);  // band: +-0.03 around the measured value
  EXPECT_EQ(m.folds, kMeasuredFolds);
}

}  // namespace
