// Garments sewn from flat panels (scene `garment: {panels}` and `seams`): the seams close and
// stay closed with both the particle method and the FEM shell, a two-panel tube top rests on a
// capsule torso, and the drape tool refuses seams and panels that make no sense.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/drape/seam_groups.h"
#include "cloth_hair_sim/core/fem_shell/fem_shell_solver.h"
#include "cloth_hair_sim/core/io/scene.h"
#include "cloth_hair_sim/core/particle/particle_static_solver.h"
#include "drape_tool_runner.h"

namespace {

namespace fs = std::filesystem;

using chs::testing::drape;
using chs::testing::ToolRun;

fs::path tempDir() {
  const fs::path dir =
      fs::temp_directory_path() / ("chs_test_drape_seams_" + std::to_string(getpid()));
  fs::create_directories(dir);
  return dir;
}

// Two 0.2 m square cotton panels hanging in the plane y = 0, 5 cm apart: the upper clamped along
// its top edge (z = 1.1 m), the lower held by nothing but the seam that sews its top edge to the
// upper's bottom edge. Sewn, they hang as one 0.4 m sheet: its lowest edge at 1.1 - 0.4 = 0.7 m,
// less the stretch under its own weight, rho g L^2 / (2 E h) = 0.30 mm (Poisson's contraction
// neglected).
const char* kHangingPanels = R"(
garment:
  panels:
    - {name: upper, rectangle: {size: [0.2, 0.2], cells: [4, 4]}, position: [0, 0, 1.0],
       rpy: [1.5707963267948966, 0, 0]}
    - {name: lower, rectangle: {size: [0.2, 0.2], cells: [4, 4]}, position: [0, 0, 0.75],
       rpy: [1.5707963267948966, 0, 0]}
seams:
  - {a: {panel: upper, side: bottom}, b: {panel: lower, side: top}}
material: cotton_eischen
boundary:
  clamped: {plane: {axis: z, value: 1.1, tolerance: 1e-6}}
fem_shell: {solver: energy_newton}
)";

struct Hanging {
  double gap = 1e9, z_min = 1e9;
};

Hanging measure(const chs::Scene& scene, const chs::DrapeResult& r) {
  Hanging h;
  const chs::SeamGroups seams(scene.problem.mesh.numVertices(), scene.problem.seams);
  h.gap = seams.maxGap(r.positions);
  for (const auto& x : r.positions) h.z_min = std::min(h.z_min, x.z());
  return h;
}

TEST(DrapeSeams, TwoHangingPanelsSewnByBothMethods) {
  const chs::Scene scene = chs::parseScene(kHangingPanels, ".", "hanging_panels");
  ASSERT_EQ(scene.problem.mesh.numVertices(), 50);
  ASSERT_EQ(scene.problem.seams.size(), 1u);
  const chs::SeamGroups seams(50, scene.problem.seams);
  EXPECT_NEAR(seams.maxGap(scene.problem.mesh.vertices), 0.05, 1e-12);  // before sewing

  const chs::DrapeResult particle = chs::solveParticleStatic(scene.problem, scene.particle);
  ASSERT_TRUE(particle.converged) << particle.status;
  const Hanging p = measure(scene, particle);
  const chs::DrapeResult fem = chs::solveFemShell(scene.problem, scene.fem_shell);
  ASSERT_TRUE(fem.converged) << fem.status;
  const Hanging f = measure(scene, fem);
  std::cout << "  particle: seam gap " << p.gap << " m, lowest point " << p.z_min << " m ("
            << particle.status << ")\n  fem_shell: seam gap " << f.gap << " m, lowest point "
            << f.z_min << " m (" << fem.status << ")\n";
  const auto& m = scene.problem.material;
  const double z_low = 0.7 - m.areal_density * 9.81 * 0.16 / (2 * m.young * m.thickness);
  std::cout << "  one 0.4 m sheet stretched by its weight: lowest point " << z_low << " m\n";
  for (const Hanging& h : {p, f}) {
    EXPECT_LE(h.gap, 1e-9);             // joined: the partners move as one
    EXPECT_NEAR(h.z_min, z_low, 1e-4);  // 10 % of the stretch
  }
}

nlohmann::json readReport(const fs::path& dir) {
  std::ifstream in(dir / "report.json");
  return nlohmann::json::parse(in);
}

std::vector<Eigen::Vector3d> drapedVertices(const fs::path& obj) {
  std::ifstream in(obj);
  std::vector<Eigen::Vector3d> v;
  std::string tag;
  for (std::string line; std::getline(in, line);) {
    std::istringstream s(line);
    Eigen::Vector3d p;
    if (s >> tag && tag == "v" && s >> p.x() >> p.y() >> p.z()) v.push_back(p);
  }
  return v;
}

// scenes/tube_top_on_torso.yaml: a tube 0.92 m round sewn from a front and a back panel round a
// capsule torso of radius R = 0.14 m (2 pi R = 0.880 m), its top edge held at z = 1.2 m. The
// panels lie on the torso and the excess length P - 2 pi R stands out at the two hinge-like
// seams as ears: for a limp, inextensible band, straight tangents from the ear's tip at distance
// D = R / cos(a) meet the circle, and 4 R (tan a - a) = P - 2 pi R. The tube hangs 0.3 m from its
// top, less the stretch under its weight rho g L^2 / (2 E h).
void tubeTopOnTorso(const std::string& method) {
  const fs::path dir = tempDir() / ("tube_" + method);
  const std::string scene = std::string(CHS_SOURCE_DIR) + "/scenes/tube_top_on_torso.yaml";
  const ToolRun r =
      drape("'" + scene + "' --quiet --method " + method + " --out '" + dir.string() + "'");
  ASSERT_EQ(r.status, 0) << r.output;
  const nlohmann::json report = readReport(dir);
  const chs::Scene s = chs::loadScene(scene);
  const auto draped = drapedVertices(dir / "draped.obj");
  ASSERT_EQ(draped.size(), s.problem.mesh.vertices.size());
  const double R = 0.14, P = 0.92;
  auto gapOf = [&](const Eigen::Vector3d& p) {  // to the exact capsule
    const double zc = std::clamp(p.z(), 0.85, 1.25);
    return std::hypot(p.x(), p.y(), p.z() - zc) - R;
  };
  double z_min = 1e9, y_max = 0.0, gap_min = 1e9;
  int touching = 0;
  for (const auto& p : draped) {
    z_min = std::min(z_min, p.z());
    y_max = std::max(y_max, std::abs(p.y()));
    gap_min = std::min(gap_min, gapOf(p));
    touching += gapOf(p) < 1e-3;
  }
  double a = 0.5;  // 4 R (tan a - a) = P - 2 pi R by Newton
  for (int k = 0; k < 50; ++k) {
    const double t = std::tan(a);
    a -= (4 * R * (t - a) - (P - 2 * M_PI * R)) / (4 * R * t * t);
  }
  const double ear = R / std::cos(a);
  const auto& m = s.problem.material;
  const double z_low = 0.9 - m.areal_density * 9.81 * 0.09 / (2 * m.young * m.thickness);
  const double seam_gap = report["seams"]["max_gap_m"].get<double>();
  std::cout << "\n  tube top (" << method << "): seam gap " << seam_gap << " m, ear at |y| "
            << y_max << " m (limp band " << ear << "), lowest point " << z_min << " m (" << z_low
            << "), least gap " << gap_min << " m, " << touching
            << " nodes within 1 mm of the torso, " << report["wall_time_s"] << " s\n";
  EXPECT_LE(seam_gap, 1e-9);
  EXPECT_GT(gap_min, -1e-4);  // penetration: at most 0.1 mm
  EXPECT_GT(touching, 20);    // it rests on the torso
  EXPECT_NEAR(y_max, ear, 1e-3);
  EXPECT_NEAR(z_min, z_low, 1e-4);
  fs::remove_all(dir);
}

TEST(DrapeSeams, TubeTopOnTorsoParticle) {
  tubeTopOnTorso("particle");
}
TEST(DrapeSeams, TubeTopOnTorsoFemShell) {
  tubeTopOnTorso("fem_shell");
}

// Bad seams and panels: the drape tool exits 1 and names the problem.
const char* kPanels = R"(
garment:
  panels:
    - {name: front, rectangle: {size: [0.2, 0.2], cells: [4, 4]}, position: [0, 0, 1.0],
       rpy: [1.5707963267948966, 0, 0]}
    - {name: back, PANEL_B, position: [0, 0.1, 1.0], rpy: [1.5707963267948966, 0, 0]}
seams:
  - {a: {panel: front, SIDE_A}, b: {panel: PANEL_NAME, side: left}}
material: cotton_eischen
boundary:
  clamped: {plane: {axis: z, value: 1.1, tolerance: 1e-6}}
)";

ToolRun badScene(const std::string& panel_b, const std::string& side_a, const std::string& name,
                 const std::string& extra_file = "") {
  std::string text = kPanels;
  auto put = [&](const std::string& key, const std::string& value) {
    text.replace(text.find(key), key.size(), value);
  };
  put("PANEL_B", panel_b);
  put("SIDE_A", side_a);
  put("PANEL_NAME", name);
  const fs::path dir = tempDir();
  if (!extra_file.empty()) std::ofstream(dir / "bent.obj") << extra_file;
  std::ofstream(dir / "bad.yaml") << text;
  const ToolRun r =
      drape("'" + (dir / "bad.yaml").string() + "' --quiet --out '" + (dir / "out").string() + "'");
  fs::remove_all(dir);
  return r;
}

const std::string kSquare = "rectangle: {size: [0.2, 0.2], cells: [4, 4]}";

TEST(DrapeSeams, GoodSceneOfTheBadInputTestsLoads) {
  // The template itself is valid: each refusal below comes from its one change.
  std::string text = kPanels;
  text.replace(text.find("PANEL_B"), 7, kSquare);
  text.replace(text.find("SIDE_A"), 6, "side: right");
  text.replace(text.find("PANEL_NAME"), 10, "back");
  const chs::Scene s = chs::parseScene(text, ".", "good");
  EXPECT_EQ(s.problem.seams.at(0).side_a.size(), 5u);
}

TEST(DrapeSeams, FemShellRefusesSeamsHeldApart) {
  std::string text = kHangingPanels;
  const std::string clamp = "clamped: {plane: {axis: z, value: 1.1, tolerance: 1e-6}}";
  text.replace(text.find(clamp), clamp.size(),
               "clamped: [{plane: {axis: z, value: 1.1, tolerance: 1e-6}},\n"
               "            {plane: {axis: z, value: 0.9, tolerance: 1e-6}},\n"
               "            {plane: {axis: z, value: 0.85, tolerance: 1e-6}}]");
  const chs::Scene scene = chs::parseScene(text, ".", "held_apart");
  try {
    chs::solveFemShell(scene.problem, scene.fem_shell);
    FAIL() << "no InputError";
  } catch (const chs::InputError& e) {
    std::cout << "  " << e.what() << "\n";
    EXPECT_NE(std::string(e.what()).find("sewn together but held apart along z"),
              std::string::npos);
  }
}

TEST(DrapeSeams, SolidShellRefusesSeams) {
  const fs::path dir = tempDir();
  std::ofstream(dir / "sewn.yaml") << kHangingPanels;
  const ToolRun r = drape("'" + (dir / "sewn.yaml").string() +
                          "' --quiet --method solid_shell --out '" + (dir / "out").string() + "'");
  fs::remove_all(dir);
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.output.find("the solid shell does not sew"), std::string::npos);
}

TEST(DrapeSeams, RefusesSidesOfUnequalVertexCount) {
  const ToolRun r = badScene("rectangle: {size: [0.2, 0.2], cells: [4, 6]}", "side: right", "back");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.output.find("seams[0]: sews 5 vertices (panel front, side right) to 7"),
            std::string::npos);
}

TEST(DrapeSeams, RefusesSidesOfUnequalLength) {
  const ToolRun r =
      badScene("rectangle: {size: [0.2, 0.25], cells: [4, 4]}", "side: right", "back");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.output.find("lengths must agree within 1%"), std::string::npos);
}

TEST(DrapeSeams, RefusesAVertexOffTheBoundary) {
  // Vertex 12 is the square's centre (i = j = 2 of 5 x 5).
  const ToolRun r = badScene(kSquare, "vertices: [4, 12, 14, 19, 24]", "back");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.output.find("vertex 12 of panel 'front' is not on its boundary"), std::string::npos);
}

TEST(DrapeSeams, RefusesAnUnknownPanel) {
  const ToolRun r = badScene(kSquare, "side: right", "sleeve");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.output.find("unknown panel 'sleeve' (panels: front, back)"), std::string::npos);
}

TEST(DrapeSeams, RefusesAnUnknownSide) {
  const ToolRun r = badScene(kSquare, "side: middle", "back");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.output.find("must be left, right, bottom or top, got 'middle'"), std::string::npos);
}

TEST(DrapeSeams, RefusesAPanelThatIsNotFlat) {
  // A 2 x 1 strip of 0.1 m quads folded 2 cm out of plane at its far edge.
  const std::string bent =
      "v 0 0 0\nv 0.1 0 0\nv 0.2 0 0.02\nv 0 0.2 0\nv 0.1 0.2 0\nv 0.2 0.2 0.02\n"
      "f 1 2 5 4\nf 2 3 6 5\n";
  const ToolRun r = badScene("file: bent.obj", "side: right", "back", bent);
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.output.find("garment.panels[1]: is not flat"), std::string::npos);
}

TEST(DrapeSeams, RefusesNamedSidesOfAMeshFilePanel) {
  const std::string flat =
      "v 0 0 0\nv 0.1 0 0\nv 0.2 0 0\nv 0 0.2 0\nv 0.1 0.2 0\nv 0.2 0.2 0\n"
      "f 1 2 5 4\nf 2 3 6 5\n";
  const ToolRun r = badScene("file: bent.obj", "side: right", "back", flat);
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.output.find("only rectangle panels have named sides"), std::string::npos);
}

}  // namespace
