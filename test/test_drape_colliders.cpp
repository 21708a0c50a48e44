// The drape tool on the scene colliders that come from the core's contact surfaces (capsule,
// mesh distance field), and its picture of a flat result.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "cloth_hair_sim/core/contact/capsule_surface.h"
#include "cloth_hair_sim/core/io/material_presets.h"
#include "cloth_hair_sim/core/io/scene.h"
#include "drape_tool_runner.h"

namespace {

namespace fs = std::filesystem;

using chs::testing::drape;
using chs::testing::ToolRun;

fs::path tempDir() {
  const fs::path dir =
      fs::temp_directory_path() / ("chs_test_drape_colliders_" + std::to_string(getpid()));
  fs::create_directories(dir);
  return dir;
}

nlohmann::json readReport(const fs::path& dir) {
  std::ifstream in(dir / "report.json");
  return nlohmann::json::parse(in);
}

// The draped positions, in the mesh's vertex order (readQuadMesh would refuse a drape folded
// sharply enough to turn a quad over its neighbour).
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

bool pictureMade(const fs::path& file, const nlohmann::json& report) {
  for (const auto& note : report["notes"])
    if (note.get<std::string>().find("picture") != std::string::npos) return false;
  return fs::is_regular_file(file) && fs::file_size(file) > 10000;
}

// The drape tool's towel over a bar of radius 3 cm along x: its extent, how far it keeps out of
// the bar (measured against the exact capsule) and the bar's reaction.
struct Towel {
  double z_min = 1e9, z_max = -1e9, gap_min = 1e9, y_max = 0.0, reaction_z = 0.0;
};

Towel drapeTowel(const fs::path& scene, const std::string& method, const fs::path& dir) {
  Towel t;
  const ToolRun r = drape("'" + scene.string() + "' --quiet --method " + method + " --out '" +
                          dir.string() + "'");
  EXPECT_EQ(r.status, 0) << r.output;
  const nlohmann::json report = readReport(dir);
  EXPECT_TRUE(report["converged"].get<bool>());
  EXPECT_TRUE(pictureMade(dir / "drape.png", report));
  EXPECT_TRUE(fs::is_regular_file(dir / "convergence.png"));
  const chs::CapsuleSurface bar({-0.2, 0, 0}, {0.2, 0, 0}, 0.03);
  for (const auto& p : drapedVertices(dir / "draped.obj")) {
    t.z_min = std::min(t.z_min, p.z());
    t.z_max = std::max(t.z_max, p.z());
    t.y_max = std::max(t.y_max, std::abs(p.y()));
    t.gap_min = std::min(t.gap_min, bar.project(p).gap);
  }
  t.reaction_z = report["contact_reactions"]["total"][2].get<double>();
  std::cout << "  " << method << ": lowest point " << t.z_min << " m, top " << t.z_max
            << " m, least gap " << t.gap_min << " m, half width " << t.y_max << " m\n";
  return t;
}

const fs::path kTowelScene = fs::path(CHS_SOURCE_DIR) / "scenes/towel_on_capsule.yaml";

// scenes/towel_on_capsule.yaml: a 20 cm cotton towel across the capsule. A limp,
// inextensible towel wraps a quarter turn each side and hangs straight down to
// 0.1 - pi R / 2 = 5.29 cm below the axis; the 2 cm elements, chords of the wrapped arc, cover
// a little more angle and hang ~0.5 mm lower; cotton's bending keeps the sides just off the
// bar's sides. All its weight rests on the bar.
void expectTowelOverBar(const Towel& t) {
  const double radius = 0.03, hang = 0.1 - M_PI * radius / 2;
  EXPECT_NEAR(t.z_max, radius, 1e-4);  // the middle rests on the top of the bar
  EXPECT_GT(t.gap_min, -1e-4);         // nothing inside the bar
  EXPECT_NEAR(t.z_min, -hang, 2e-3);
  EXPECT_GT(t.y_max, radius);
  EXPECT_LT(t.y_max, radius + 0.01);
  const double weight = 0.2 * 0.2 * chs::materialPreset("cotton_eischen")->areal_density * 9.80665;
  EXPECT_NEAR(t.reaction_z, weight, 1e-3 * weight);
}

TEST(DrapeColliders, TowelOverCapsuleParticle) {
  expectTowelOverBar(drapeTowel(kTowelScene, "particle", tempDir() / "particle"));
  fs::remove_all(tempDir());
}

// With the FEM shell; then the same bar as a closed 48-sided cylinder mesh (a distance field
// with 2 mm voxels): the penalty contact uses the field's gap, normal and normal gradient, and
// drapes the towel as over the exact capsule.
TEST(DrapeColliders, TowelOverCapsuleAndMeshBarFemShell) {
  const fs::path dir = tempDir();
  {
    std::ofstream obj(dir / "bar.obj");
    const int n = 48;
    for (double x : {-0.2, 0.2})
      for (int k = 0; k < n; ++k)
        obj << "v " << x << ' ' << 0.03 * std::cos(2 * M_PI * k / n) << ' '
            << 0.03 * std::sin(2 * M_PI * k / n) << '\n';
    obj << "v -0.2 0 0\nv 0.2 0 0\n";
    for (int k = 1; k <= n; ++k) {
      const int next = k % n + 1;
      obj << "f " << k << ' ' << next << ' ' << n + next << ' ' << n + k << '\n'
          << "f " << 2 * n + 1 << ' ' << next << ' ' << k << '\n'
          << "f " << 2 * n + 2 << ' ' << n + k << ' ' << n + next << '\n';
    }
  }
  std::ifstream in(kTowelScene);
  std::string scene((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string capsule = "capsule: {a: [-0.2, 0, 0], b: [0.2, 0, 0], radius: 0.03}";
  ASSERT_NE(scene.find(capsule), std::string::npos);
  scene.replace(scene.find(capsule), capsule.size(), "mesh: {file: bar.obj, voxel_size: 0.002}");
  std::ofstream(dir / "bar.yaml") << scene;
  const Towel exact = drapeTowel(kTowelScene, "fem_shell", dir / "capsule");
  expectTowelOverBar(exact);
  const Towel mesh = drapeTowel(dir / "bar.yaml", "fem_shell", dir / "mesh");
  expectTowelOverBar(mesh);
  EXPECT_NEAR(mesh.z_min, exact.z_min, 5e-4);
  EXPECT_NEAR(mesh.y_max, exact.y_max, 5e-4);
  fs::remove_all(dir);
}

// scenes/poncho_on_body.yaml: the demo poncho dropped round the neck of the MakeHuman body of
// assimp-testmodels (10 cm quads, 1 cm voxels: the coarse resolution that converges in
// seconds). It rests on the shoulders, no node inside the body, and the body carries its
// weight (the fixed nodes hold it from sliding off the sloping shoulders, vertical force none).
TEST(DrapeColliders, PonchoOnBodyMesh) {
  const fs::path dir = tempDir() / "poncho";
  const std::string scene = std::string(CHS_SOURCE_DIR) + "/scenes/poncho_on_body.yaml";
  const ToolRun r = drape("'" + scene + "' --quiet --out '" + dir.string() + "'");
  ASSERT_EQ(r.status, 0) << r.output;
  const nlohmann::json report = readReport(dir);
  EXPECT_TRUE(pictureMade(dir / "drape.png", report));

  const chs::Scene s = chs::loadScene(scene);
  const auto& body = s.colliders[0].mesh_field->bounds();
  const Eigen::Vector3d height = s.colliders[0].pose.linear() * body.sizes();
  EXPECT_NEAR(std::abs(height.z()), 1.75, 0.005);  // scaled to a 1.75 m person, standing on z
  const auto draped = drapedVertices(dir / "draped.obj");
  ASSERT_EQ(draped.size(), s.problem.mesh.vertices.size());
  double z_min = 1e9, z_max = -1e9, gap_min = 1e9;
  for (const auto& p : draped) {
    z_min = std::min(z_min, p.z());
    z_max = std::max(z_max, p.z());
    gap_min = std::min(gap_min, s.problem.colliders[0]->project(p).gap);
  }
  std::cout << "  poncho from z " << z_min << " to " << z_max << " m, least gap " << gap_min
            << " m\n";
  EXPECT_GT(gap_min, -1e-3);  // the field's voxels are 1 cm
  EXPECT_LT(z_max, 1.50);     // below its start: it fell onto the shoulders (top 1.44-1.48 m)
  EXPECT_GT(z_max, 1.42);
  EXPECT_GT(z_min, 0.7);  // hangs to the hips, no lower: the poncho is 1 m long front to back
  const double area = 1.0 * 1.2 - 0.2 * 0.2;
  const double weight = area * s.problem.material.areal_density * 9.81;
  EXPECT_NEAR(report["contact_reactions"]["total"][2].get<double>(), weight, 1e-3 * weight);
  fs::remove_all(tempDir());
}

// A result with no height difference at all (clamped, weightless, at z = 1.5) used to leave
// gnuplot with an empty colour range and no picture.
TEST(DrapeColliders, FlatResultStillDrawn) {
  const fs::path dir = tempDir() / "flat";
  fs::create_directories(dir);
  std::ofstream(dir / "flat.yaml")
      << "gravity: [0, 0, 0]\n"
         "garment: {rectangle: {size: [0.2, 0.2], cells: [4, 4], centre: [0, 0, 1.5]}}\n"
         "material: cotton_eischen\n"
         "colliders: [{plane: {point: [0, 0, 1]}}]\n"
         "boundary: {clamped: {boundary: true}}\n";
  const ToolRun r = drape("'" + (dir / "flat.yaml").string() + "' --quiet --out '" +
                          (dir / "out").string() + "'");
  ASSERT_EQ(r.status, 0) << r.output;
  const nlohmann::json report = readReport(dir / "out");
  EXPECT_DOUBLE_EQ(report["draped_bounding_box"]["min"][2].get<double>(), 1.5);
  EXPECT_DOUBLE_EQ(report["draped_bounding_box"]["max"][2].get<double>(), 1.5);
  EXPECT_TRUE(pictureMade(dir / "out" / "drape.png", report));
  fs::remove_all(tempDir());
}

}  // namespace
