// Mesh files (assimp round trip, bad files), the scene parser and the report writer.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/io/drape_report.h"
#include "cloth_hair_sim/core/io/material_presets.h"
#include "cloth_hair_sim/core/io/mesh_reader.h"
#include "cloth_hair_sim/core/io/mesh_writer.h"
#include "cloth_hair_sim/core/io/scene.h"
#include "cloth_hair_sim/core/mesh/grid_generators.h"

namespace chs {
namespace {

namespace fs = std::filesystem;

fs::path tempDir() {
  const fs::path dir = fs::temp_directory_path() / ("chs_test_io_" + std::to_string(getpid()));
  fs::create_directories(dir);
  return dir;
}

void writeText(const fs::path& path, const std::string& text) {
  std::ofstream(path) << text;
}

// Expects fn to throw InputError mentioning every fragment.
template <typename Fn>
void expectInputError(Fn fn, std::initializer_list<std::string> fragments) {
  try {
    fn();
    FAIL() << "no error";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    std::cout << "  rejected: " << msg << "\n";
    for (const auto& f : fragments) EXPECT_NE(msg.find(f), std::string::npos) << msg;
  }
}

// Same quads, corner by corner; assimp holds positions as float.
void expectSameMesh(const QuadMesh& a, const QuadMesh& b, double scale = 1.0) {
  ASSERT_EQ(a.numVertices(), b.numVertices());
  ASSERT_EQ(a.numQuads(), b.numQuads());
  for (int q = 0; q < a.numQuads(); ++q)
    for (int k = 0; k < 4; ++k)
      EXPECT_LT((scale * a.vertices[a.quads[q][k]] - b.vertices[b.quads[q][k]]).norm(),
                1e-6 * scale)
          << "quad " << q << " corner " << k;
}

TEST(MeshIo, ObjAndPlyRoundTripKeepQuads) {
  const fs::path dir = tempDir();
  QuadMesh mesh = makeDiscMesh(0.127, 12, {0.1, 0.2, 0.3});
  std::vector<Eigen::Vector3d> deformed = mesh.vertices;
  for (auto& p : deformed) p.z() -= 0.5 * p.head<2>().squaredNorm();  // a bowl
  QuadMesh expected = mesh;
  expected.vertices = deformed;
  for (const char* ext : {".obj", ".ply"}) {
    const std::string path = (dir / (std::string("disc") + ext)).string();
    if (std::string(ext) == ".obj")
      writeObj(path, mesh, deformed);
    else
      writePly(path, mesh, deformed);
    const QuadMesh back = readQuadMesh(path);
    std::cout << "  " << ext << ": " << back.numVertices() << " vertices, " << back.numQuads()
              << " quads\n";
    expectSameMesh(expected, back);
    expectSameMesh(expected, readQuadMesh(path, 100.0), 100.0);
  }
  fs::remove_all(dir);
}

// A triangle mesh takes one Catmull-Clark step: each n-gon becomes n quads (Han section 5.4).
TEST(MeshIo, TrianglesBecomeQuads) {
  const fs::path dir = tempDir();
  writeText(dir / "two.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\n");
  const QuadMesh m = readQuadMesh((dir / "two.obj").string());
  std::cout << "  two triangles: " << m.numVertices() << " vertices, " << m.numQuads()
            << " quads\n";
  EXPECT_EQ(m.numQuads(), 6);
  EXPECT_EQ(m.numVertices(), 4 + 5 + 2);  // corners, edge points, face points
  for (const auto& v : m.vertices) EXPECT_NEAR(v.z(), 0.0, 1e-15);
  fs::remove_all(dir);
}

TEST(MeshIo, BadFiles) {
  const fs::path dir = tempDir();
  expectInputError([&] { readQuadMesh((dir / "missing.obj").string()); },
                   {"missing.obj", "no such"});
  writeText(dir / "garbage.ply", "ply\nthis is not\x01\x02 a ply file at all\n");
  expectInputError([&] { readQuadMesh((dir / "garbage.ply").string()); }, {"garbage.ply"});
  writeText(dir / "garbage.obj", "\x7f\x45\x4c\x46 binary junk \x01\x02\x03\n");
  expectInputError([&] { readQuadMesh((dir / "garbage.obj").string()); }, {"garbage.obj"});
  writeText(dir / "tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  writeText(dir / "line.obj", "v 0 0 0\nv 1 0 0\nl 1 2\n");
  expectInputError([&] { readQuadMesh((dir / "line.obj").string()); }, {"line.obj", "no faces"});
  writeText(dir / "flipped.obj",
            "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nv 1 1 0\nv 2 1 0\nf 1 2 5 4\nf 2 5 6 3\n");
  expectInputError([&] { readQuadMesh((dir / "flipped.obj").string()); },
                   {"flipped.obj", "orientation"});
  expectInputError([&] { readQuadMesh((dir / "tri.obj").string(), -1.0); }, {"scale"});
  fs::remove_all(dir);
}

// A file that does not parse whole is refused with the line (or element) that broke, not loaded
// with the faces before the damage (assimp alone drops a face cut in the middle).
TEST(MeshIo, TruncatedAndDamagedFilesNameTheLine) {
  const fs::path dir = tempDir();
  const QuadMesh mesh = makeRectangleMesh(0.1, 0.1, 3, 3);
  const std::string obj = (dir / "full.obj").string(), ply = (dir / "full.ply").string();
  writeObj(obj, mesh, mesh.vertices);
  writePly(ply, mesh, mesh.vertices);
  EXPECT_EQ(readQuadMesh(obj).numQuads(), 9);
  EXPECT_EQ(readQuadMesh(ply).numQuads(), 9);
  std::ifstream in(obj);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  int lines = 0;
  for (char c : text) lines += c == '\n';
  // The last face cut in the middle (after "f a b"): the file ends inside its line.
  const std::size_t last_face = text.rfind("\nf ") + 1;
  const std::size_t cut = text.find(' ', text.find(' ', last_face + 2) + 1);
  writeText(dir / "cut.obj", text.substr(0, cut));
  expectInputError([&] { readQuadMesh((dir / "cut.obj").string()); },
                   {"cut.obj", "line " + std::to_string(lines), "truncated"});
  // The same cut, but the writer still closed the line: a face of two vertices.
  writeText(dir / "short.obj", text.substr(0, cut) + "\n");
  expectInputError([&] { readQuadMesh((dir / "short.obj").string()); },
                   {"short.obj", "line " + std::to_string(lines), "at least 3", "it has 2"});
  writeText(dir / "range.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 3 4\n");
  expectInputError([&] { readQuadMesh((dir / "range.obj").string()); },
                   {"line 4", "vertex 4", "only 3"});
  writeText(dir / "junk.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\n0.5 0.5 0\nv 0 1 0\nf 1 2 3 4\n");
  expectInputError([&] { readQuadMesh((dir / "junk.obj").string()); },
                   {"line 4", "not an OBJ statement"});
  writeText(dir / "coord.obj", "v 0 0 0\nv 1 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n");
  expectInputError([&] { readQuadMesh((dir / "coord.obj").string()); },
                   {"line 2", "needs 3 to 7 numbers, it has 2"});
  writeText(dir / "nan.obj", "v 0 0 0\nv 1 0 zero\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n");
  expectInputError([&] { readQuadMesh((dir / "nan.obj").string()); },
                   {"line 2", "'zero' is not a number"});
  // Continuation lines, comments, negative (relative) indices and texture references are OBJ.
  writeText(dir / "ok.obj",
            "# a quad\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\no sheet\nf -4/1 -3/1 \\\n"
            "  -2/1 -1/1\n");
  EXPECT_EQ(readQuadMesh((dir / "ok.obj").string()).numQuads(), 1);
  // assimp reads a comment after a face as a bad index: said with the line.
  writeText(dir / "comment.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4 # a quad\n");
  expectInputError([&] { readQuadMesh((dir / "comment.obj").string()); },
                   {"line 5", "'#' is not a vertex reference"});

  // PLY: an ASCII body that stops early, and a binary one cut mid-face.
  std::ifstream pin(ply);
  const std::string ptext((std::istreambuf_iterator<char>(pin)), std::istreambuf_iterator<char>());
  writeText(dir / "cut.ply", ptext.substr(0, ptext.size() - 6));
  expectInputError([&] { readQuadMesh((dir / "cut.ply").string()); },
                   {"cut.ply", "face 8 of 9", "truncated"});
  {
    std::ofstream b(dir / "cut_binary.ply", std::ios::binary);
    b << "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\n"
         "property float y\nproperty float z\nelement face 1\nproperty list uchar int "
         "vertex_indices\nend_header\n";
    const float xyz[12] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
    b.write(reinterpret_cast<const char*>(xyz), sizeof xyz);
    const unsigned char four = 4;
    const int corners[2] = {0, 1};  // two of the four indices
    b.write(reinterpret_cast<const char*>(&four), 1);
    b.write(reinterpret_cast<const char*>(corners), sizeof corners);
  }
  expectInputError([&] { readQuadMesh((dir / "cut_binary.ply").string()); },
                   {"cut_binary.ply", "face 0 of 1", "truncated"});
  fs::remove_all(dir);
}

const char* kGoodScene = R"(
name: test_scene
method: fem_shell
gravity: [0, 0, -9.80665]
garment:
  rectangle: {size: [0.2, 0.1], cells: [4, 2], centre: [0, 0, 0.001]}
material: {preset: cotton_eischen}
colliders:
  - table: {top_centre: [0, 0, 0], size: [0.08, 0.08], depth: 0.2}
  - sphere: {centre: [0, 0, -1], radius: 0.5}
  - plane: {point: [0, 0, -0.5], normal: [0, 0, 1]}
  - pedestal: {top_centre: [0.3, 0, 0], radius: 0.05}
boundary:
  clamped: [0, {plane: {axis: x, value: 0.1}}]
  fixed: [{vertices: {nearest: [0, 0, 0]}, axes: [x, y]}]
fem_shell: {tolerance: 1.0e-6, max_load_steps: 50, arc_length: false}
particle: {momentum: 0.99, max_iterations: 1000, stretch_compression: 0.1}
output: {directory: somewhere}
)";

TEST(Scene, GoodScene) {
  const Scene s = parseScene(kGoodScene, ".", "fallback");
  EXPECT_EQ(s.name, "test_scene");
  EXPECT_EQ(s.method, DrapeMethod::kFemShell);
  EXPECT_EQ(s.problem.mesh.numVertices(), 15);
  EXPECT_EQ(s.problem.colliders.size(), 4u);
  EXPECT_EQ(s.colliders[0].type, ColliderSpec::Type::kBox);
  EXPECT_EQ(s.problem.bc.clamped, (std::vector<int>{0, 4, 9, 14}));
  ASSERT_EQ(s.problem.bc.fixed_components.size(), 2u);
  EXPECT_EQ(s.problem.bc.fixed_components[0].vertex, 7);
  EXPECT_DOUBLE_EQ(s.fem_shell.tolerance, 1e-6);
  EXPECT_EQ(s.fem_shell.max_load_steps, 50);
  EXPECT_FALSE(s.fem_shell.arc_length);
  EXPECT_DOUBLE_EQ(s.particle.momentum, 0.99);
  EXPECT_EQ(s.particle.max_iterations, 1000);
  EXPECT_DOUBLE_EQ(s.particle.network.stretch_compression, 0.1);
  EXPECT_EQ(s.output.directory, "somewhere");
  // Seed 000 section 4.4 cotton in SI.
  const ShellMaterial& m = s.problem.material;
  EXPECT_NEAR(m.young, 118.1176 * 9806.65, 1e-6);
  EXPECT_NEAR(m.areal_density * 9.80665, 0.2384e-3 * 9806.65, 1e-12);
  EXPECT_NEAR(m.bendingStiffness(), 1.725 * 9.80665e-3 * 1e-3, 0.002 * 1.725e-5);  // 1.725 gf mm
}

TEST(Scene, WoolPreset) {
  const ShellMaterial m = *materialPreset("wool_suiting");
  EXPECT_NEAR(m.bendingStiffness(), 0.1 * 9.80665e-6 / 1e-1, 1e-15);  // 0.1 gf cm^2/cm
  EXPECT_NEAR(m.areal_density, 0.22, 1e-15);
  std::cout << "  wool_suiting E = " << m.young << " Pa\n";
}

TEST(Scene, ShippedScenesParse) {
  for (const auto& entry : fs::directory_iterator(fs::path(CHS_SOURCE_DIR) / "scenes")) {
    if (entry.path().extension() != ".yaml") continue;
    // The simulate tool's scenes (another format) are checked by test_simulation_scene.
    if (entry.path().stem().string().rfind("simulate_", 0) == 0) continue;
    const Scene s = loadScene(entry.path().string());
    std::cout << "  " << s.name << ": " << s.problem.mesh.numVertices() << " vertices, "
              << s.problem.mesh.numQuads() << " quads, " << methodName(s.method) << "\n";
    EXPECT_EQ(s.name, entry.path().stem().string());
  }
}

// The good scene with one line replaced.
std::string edited(const std::string& from, const std::string& to) {
  std::string s = kGoodScene;
  const auto at = s.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return s.replace(at, from.size(), to);
}

TEST(Scene, NonsenseMaterial) {
  const std::string base = "material: {preset: cotton_eischen}";
  expectInputError(
      [&] { parseScene(edited(base, "material: {preset: cotton_eischen, young: 0}"), ".", "t"); },
      {"material.young", "positive"});
  expectInputError(
      [&] {
        parseScene(edited(base, "material: {preset: cotton_eischen, young: -3e5}"), ".", "t");
      },
      {"material.young"});
  expectInputError(
      [&] {
        parseScene(edited(base, "material: {preset: cotton_eischen, poisson: 0.5}"), ".", "t");
      },
      {"material.poisson", "[0, 0.5)"});
  expectInputError(
      [&] {
        parseScene(edited(base, "material: {preset: cotton_eischen, poisson: -0.1}"), ".", "t");
      },
      {"material.poisson"});
  expectInputError(
      [&] {
        parseScene(edited(base, "material: {preset: cotton_eischen, thickness: 0}"), ".", "t");
      },
      {"material.thickness"});
  expectInputError(
      [&] {
        parseScene(edited(base, "material: {preset: cotton_eischen, areal_density: -1}"), ".", "t");
      },
      {"material.areal_density", "negative"});
  expectInputError(
      [&] { parseScene(edited(base, "material: {preset: cotton_eischen, young: abc}"), ".", "t"); },
      {"material.young", "number"});
  expectInputError([&] { parseScene(edited(base, "material: silk"), ".", "t"); },
                   {"material", "silk", "cotton_eischen"});
  expectInputError(
      [&] { parseScene(edited(base, "material: {young: 1e6, poisson: 0.3}"), ".", "t"); },
      {"material.thickness", "missing"});
}

TEST(Scene, UnknownKeysAndBadValues) {
  expectInputError([&] { parseScene(std::string(kGoodScene) + "colour: red\n", ".", "t"); },
                   {"colour", "unknown key"});
  expectInputError([&] { parseScene(edited("tolerance: 1.0e-6", "tolerence: 1.0e-6"), ".", "t"); },
                   {"fem_shell.tolerence", "unknown key"});
  expectInputError([&] { parseScene(edited("depth: 0.2", "depht: 0.2"), ".", "t"); },
                   {"colliders[0].table.depht", "unknown key"});
  expectInputError([&] { parseScene(edited("sphere:", "cone:"), ".", "t"); },
                   {"colliders[1].cone", "unknown collider"});
  expectInputError([&] { parseScene(edited("method: fem_shell", "method: magic"), ".", "t"); },
                   {"method", "magic"});
  expectInputError([&] { parseScene(edited("cells: [4, 2]", "cells: [4, 0]"), ".", "t"); },
                   {"garment.rectangle.cells"});
  expectInputError([&] { parseScene(edited("clamped: [0,", "clamped: [99,"), ".", "t"); },
                   {"boundary.clamped[0]", "99"});
  expectInputError([&] { parseScene(edited("axes: [x, y]", "axes: [x, w]"), ".", "t"); },
                   {"boundary.fixed[0].axes", "'w'"});
  expectInputError(
      [&] { parseScene(edited("max_load_steps: 50", "max_load_steps: 2.5"), ".", "t"); },
      {"fem_shell.max_load_steps", "integer"});
  expectInputError([&] { parseScene(edited("arc_length: false", "solver: magic"), ".", "t"); },
                   {"fem_shell.solver", "magic"});
  expectInputError(
      [&] { parseScene(edited("arc_length: false", "imperfection_shape: dents"), ".", "t"); },
      {"fem_shell.imperfection_shape", "dents"});
  expectInputError(
      [&] { parseScene(edited("arc_length: false", "imperfection_waves: 0"), ".", "t"); },
      {"fem_shell.imperfection_waves"});
  expectInputError([&] { parseScene(edited("radius: 0.5", "radius: -0.5"), ".", "t"); },
                   {"colliders[1].sphere.radius", "positive"});
  expectInputError([&] { parseScene(edited("momentum: 0.99", "momentum: 1.5"), ".", "t"); },
                   {"particle.momentum"});
  expectInputError([&] { parseScene(edited("momentum: 0.99", "momentun: 0.9"), ".", "t"); },
                   {"particle.momentun", "unknown key"});
  expectInputError([&] { parseScene("garment: [unclosed", ".", "t"); }, {"YAML"});
  expectInputError([&] { parseScene("", ".", "t"); }, {"empty"});
  expectInputError([&] { loadScene("/nonexistent/scene.yaml"); },
                   {"/nonexistent/scene.yaml", "no such"});
}

TEST(Scene, GarmentFile) {
  const fs::path dir = tempDir();
  writeObj((dir / "cloth.obj").string(), makeRectangleMesh(20, 20, 4, 4));  // in cm
  writeText(dir / "scene.yaml",
            "garment: {file: {path: cloth.obj, scale: 0.01, translate: [0, 0, 0.5]}}\n"
            "material: wool_suiting\n");
  const Scene s = loadScene((dir / "scene.yaml").string());
  EXPECT_EQ(s.name, "scene");
  EXPECT_EQ(s.problem.mesh.numQuads(), 16);
  for (const auto& p : s.problem.mesh.vertices) {
    EXPECT_LE(p.head<2>().cwiseAbs().maxCoeff(), 0.1 + 1e-12);
    EXPECT_DOUBLE_EQ(p.z(), 0.5);
  }
  writeText(dir / "scene.yaml", "garment: {file: nothere.obj}\nmaterial: wool_suiting\n");
  expectInputError([&] { loadScene((dir / "scene.yaml").string()); }, {"nothere.obj"});
  fs::remove_all(dir);
}

// A closed cube [-1, 1]^3 (quads, triangulated by assimp); with missing_face one face is left
// out and the surface is open.
void writeCube(const fs::path& path, bool missing_face = false) {
  std::string s =
      "v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\n"
      "f 1 4 3 2\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";
  if (!missing_face) s += "f 5 6 7 8\n";
  writeText(path, s);
}

std::string colliderScene(const std::string& collider) {
  return "garment: {rectangle: {size: [0.2, 0.2], cells: [2, 2], centre: [0, 0, 2]}}\n"
         "material: cotton_eischen\ncolliders:\n  - " +
         collider + "\n";
}

TEST(Scene, CapsuleAndMeshColliders) {
  const fs::path dir = tempDir();
  writeCube(dir / "cube.obj");
  writeText(dir / "scene.yaml",
            "garment: {rectangle: {size: [0.2, 0.2], cells: [2, 2], centre: [0, 0, 2]}}\n"
            "material: cotton_eischen\n"
            "colliders:\n"
            "  - capsule: {a: [-0.3, 0, 0], b: [0.3, 0, 0], radius: 0.05}\n"
            "  - capsule: {centre: [0, 0, 1], axis: [0, 0, 2], length: 0.4, radius: 0.1}\n"
            "  - mesh: {file: cube.obj, scale: 0.1, position: [0, 0, 1], rpy: [0, 0, "
            "0.7853981633974483], voxel_size: 0.005}\n"
            "  - mesh: {file: cube.obj, scale: [0.1, 0.1, 0.1], position: [0, 0, 1], "
            "quaternion: [0, 0, 0.3826834323650898, 0.9238795325112867], voxel_size: 0.01}\n");
  const Scene s = loadScene((dir / "scene.yaml").string());
  ASSERT_EQ(s.colliders.size(), 4u);
  ASSERT_EQ(s.problem.colliders.size(), 4u);
  EXPECT_EQ(s.colliders[0].type, ColliderSpec::Type::kCapsule);
  EXPECT_EQ(s.colliders[1].end_a, Eigen::Vector3d(0, 0, 0.8));
  EXPECT_EQ(s.colliders[1].end_b, Eigen::Vector3d(0, 0, 1.2));
  const auto& bar = *s.problem.colliders[0];
  EXPECT_NEAR(bar.project({0.1, 0, 0.2}).gap, 0.15, 1e-12);
  EXPECT_NEAR(bar.project({0.4, 0, 0}).gap, 0.05, 1e-12);  // beyond the cap centre
  EXPECT_NEAR(s.problem.colliders[1]->project({0, 0, 1.5}).gap, 0.2, 1e-12);
  // The cube turned 45 degrees about z: a corner edge at x = 0.1 sqrt(2), the top at z = 1.1.
  EXPECT_EQ(s.colliders[2].type, ColliderSpec::Type::kMesh);
  EXPECT_EQ(s.colliders[2].mesh_file, (dir / "cube.obj").string());
  EXPECT_DOUBLE_EQ(s.colliders[2].mesh_field->voxelSize(), 0.005);
  for (int c = 2; c < 4; ++c) {
    const auto& cube = *s.problem.colliders[c];
    const SurfaceProjection top = cube.project({0, 0, 1.12});
    EXPECT_NEAR(top.gap, 0.02, 2e-3);
    EXPECT_GT(top.normal.z(), 0.99);
    EXPECT_NEAR(cube.project({0.16, 0, 1}).gap, 0.16 - 0.1 * std::sqrt(2.0), 5e-3);
    EXPECT_LT(cube.project({0, 0.05, 1}).gap, -0.04);
  }
  fs::remove_all(dir);
}

TEST(Scene, BadCapsuleAndMeshColliders) {
  const fs::path dir = tempDir();
  writeCube(dir / "cube.obj");
  writeCube(dir / "open.obj", true);
  auto load = [&](const std::string& collider) {
    writeText(dir / "scene.yaml", colliderScene(collider));
    return loadScene((dir / "scene.yaml").string());
  };
  expectInputError([&] { load("capsule: {a: [0, 0, 0], b: [1, 0, 0], radius: 0}"); },
                   {"colliders[0].capsule.radius", "positive"});
  expectInputError([&] { load("capsule: {a: [0, 0, 0], b: [1, 0, 0], radius: 0.1, r: 1}"); },
                   {"colliders[0].capsule.r", "unknown key"});
  expectInputError([&] { load("capsule: {a: [0, 0, 0], radius: 0.1}"); },
                   {"colliders[0].capsule.b", "missing"});
  expectInputError(
      [&] { load("capsule: {centre: [0, 0, 0], axis: [0, 0, 0], length: 1, radius: 0.1}"); },
      {"colliders[0].capsule.axis", "zero"});
  expectInputError([&] { load("mesh: {file: nothere.stl}"); },
                   {"colliders[0].mesh.file", "nothere.stl", "no such mesh file"});
  expectInputError([&] { load("mesh: {scale: 2}"); }, {"colliders[0].mesh.file", "missing"});
  expectInputError([&] { load("mesh: {file: open.obj}"); },
                   {"colliders[0].mesh.file", "open.obj", "not closed"});
  expectInputError([&] { load("mesh: {file: cube.obj, scale: -1}"); },
                   {"colliders[0].mesh.scale", "positive"});
  expectInputError([&] { load("mesh: {file: cube.obj, scale: [1, 0, 1]}"); },
                   {"colliders[0].mesh.scale", "positive"});
  expectInputError([&] { load("mesh: {file: cube.obj, voxel_size: 0}"); },
                   {"colliders[0].mesh.voxel_size", "positive"});
  expectInputError([&] { load("mesh: {file: cube.obj, colour: red}"); },
                   {"colliders[0].mesh.colour", "unknown key"});
  expectInputError([&] { load("mesh: {file: cube.obj, quaternion: [0, 0, 0, 2]}"); },
                   {"colliders[0].mesh.quaternion", "unit"});
  expectInputError(
      [&] { load("mesh: {file: cube.obj, rpy: [0, 0, 0], quaternion: [0, 0, 0, 1]}"); },
      {"colliders[0].mesh.quaternion", "either"});
  expectInputError([&] { load("mesh: {file: cube.obj, parts: [torso]}"); },
                   {"colliders[0].mesh.file", "torso"});
  expectInputError([&] { load("cone: {radius: 1}"); }, {"colliders[0].cone", "capsule", "mesh"});
  fs::remove_all(dir);
}

TEST(Report, JsonHasResultAndReactions) {
  DrapeResult r;
  r.converged = false;
  r.status = "diverged";
  r.positions = {{0, 0, 0}, {1, 2, -3}};
  r.history = {{1, 0.1, 1, 0.5, 0}, {1, 0.1, 2, std::nan(""), 3}};
  r.reactions = {{0, 0, {0, 0, 1}}, {1, 0, {0, 0, 2}}, {1, 1, {1, 0, 0}}};
  ReportContext c;
  c.scene_name = "x";
  c.method = "fem_shell";
  c.settings = {{"tolerance", 1e-8}};
  const auto j = nlohmann::json::parse(drapeReportJson(r, c));
  EXPECT_FALSE(j["converged"].get<bool>());
  EXPECT_EQ(j["residual_history"].size(), 2u);
  EXPECT_TRUE(j["residual_history"][1]["residual"].is_null());  // NaN is not JSON
  EXPECT_EQ(j["contact_reactions"]["total"], nlohmann::json({1.0, 0.0, 3.0}));
  EXPECT_EQ(j["contact_reactions"]["per_surface"].size(), 2u);
  EXPECT_EQ(j["draped_bounding_box"]["min"], nlohmann::json({0.0, 0.0, -3.0}));
}

}  // namespace
}  // namespace chs
