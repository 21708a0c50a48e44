// The simulate tool's command-line contract: a tiny scene of two sheets on a table gives its
// frame meshes, report and pictures; a scene that blows up stops with status 2 and keeps its
// frames; bad input is status 1.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "drape_tool_runner.h"

namespace chs {
namespace {

namespace fs = std::filesystem;
using testing::simulate;
using testing::ToolRun;

// A 4 x 4 cm sheet dropped from 2 cm onto a 6 x 6 cm sheet lying on a table, 1 cm cells.
const char* kTwoSheets = R"(
name: tiny_two_sheets
duration: 0.1
frame_rate: 100
world: {grid_spacing: 0.01, damping: 2.0)";
const char* kBodies = R"(}
bodies:
  - name: lower
    rectangle: {size: [0.06, 0.06], cells: [6, 6]}
    position: [0, 0, 0.0025]
    material: cotton_eischen
  - name: upper
    rectangle: {size: [0.04, 0.04], cells: [4, 4]}
    position: [0, 0, 0.02]
    material: cotton_eischen
colliders:
  - name: table
    table: {size: [0.2, 0.2], depth: 0.05}
    friction: 0.5
)";

fs::path tempDir() {
  return fs::temp_directory_path() / ("chs_test_simulate_" + std::to_string(getpid()));
}

std::string writeScene(const std::string& name, const std::string& text) {
  fs::create_directories(tempDir());
  const fs::path p = tempDir() / (name + ".yaml");
  std::ofstream(p) << text;
  return p.string();
}

nlohmann::json readJson(const fs::path& p) {
  std::ifstream in(p);
  return nlohmann::json::parse(in);
}

// Lowest and highest z of an OBJ file's vertices.
std::pair<double, double> zRange(const fs::path& obj) {
  std::ifstream in(obj);
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("v ", 0) != 0) continue;
    double x, y, z;
    std::sscanf(line.c_str(), "v %lf %lf %lf", &x, &y, &z);
    lo = std::min(lo, z);
    hi = std::max(hi, z);
  }
  return {lo, hi};
}

int countFiles(const fs::path& dir, const std::string& ext) {
  int n = 0;
  for (const auto& e : fs::directory_iterator(dir)) n += e.path().extension() == ext;
  return n;
}

TEST(SimulateTool, TwoSheetsOnATable) {
  const fs::path out = tempDir() / "pair";
  const ToolRun r = simulate("'" + writeScene("pair", std::string(kTwoSheets) + kBodies) +
                             "' --out '" + out.string() + "' --render-frames 0,5,last");
  ASSERT_EQ(r.status, 0);
  EXPECT_NE(r.output.find("frame 10/10"), std::string::npos);
  EXPECT_EQ(countFiles(out / "frames", ".obj"), 2 * 11);  // frames 0..10, two bodies
  for (const char* png :
       {"render_0000.png", "render_0005.png", "render_0010.png", "energy.png", "timing.png"})
    EXPECT_GT(fs::file_size(out / png), 1000u) << png;

  const nlohmann::json j = readJson(out / "report.json");
  EXPECT_EQ(j["scene"], "tiny_two_sheets");
  EXPECT_EQ(j["status"], "completed");
  ASSERT_EQ(j["frames"].size(), 11u);
  for (std::size_t k = 1; k < 11; ++k) {
    const auto& f = j["frames"][k];
    EXPECT_GT(f["substeps"].get<int>(), 0);
    EXPECT_GT(f["wall_time_s"].get<double>(), 0.0);
    EXPECT_GE(f["bodies"]["upper"]["largest_stretch"].get<double>(), 1.0);
    EXPECT_LT(f["bodies"]["upper"]["largest_stretch"].get<double>(), 1.05);
    EXPECT_LT(f["bodies"]["lower"]["deepest_penetration_m"].get<double>(), 1e-3);
  }
  EXPECT_NEAR(j["frames"][10]["time_s"].get<double>(), 0.1, 1e-9);
  EXPECT_GT(j["totals"]["real_time_factor"].get<double>(), 0.0);
  EXPECT_EQ(j["totals"]["frames_written"], 11);

  // Both sheets rest on the table by the end: it carries their weight (rho A g, 0.0122 N).
  const double weight = 0.2384 * (0.06 * 0.06 + 0.04 * 0.04) * 9.81;
  const double fz = j["frames"][10]["colliders"]["table"]["force_N"][2].get<double>();
  std::printf("[figure] table load at 0.1 s: %.4f N (weight %.4f N)\n", -fz, weight);
  EXPECT_NEAR(-fz, weight, 0.3 * weight);

  // The dropped sheet stopped on the lower one instead of passing through it.
  const auto upper = zRange(out / "frames" / "upper_0010.obj");
  const auto lower = zRange(out / "frames" / "lower_0010.obj");
  std::printf("[figure] upper sheet lowest z %.2f mm, lower sheet highest z %.2f mm\n",
              1e3 * upper.first, 1e3 * lower.second);
  EXPECT_GT(upper.first, lower.second);
  EXPECT_LT(upper.second, 0.01);  // it did fall
  fs::remove_all(out);
}

// A loose lock of hair (10 strands of 4 cm, 8 segments, free roots) dropped onto a table with
// the strands' continuum on: PLY strands per frame, the report's hair entries, a picture, and
// the table carrying the lock's weight at the end.
TEST(SimulateTool, HairDroppedOnATable) {
  const fs::path out = tempDir() / "hair";
  const ToolRun r = simulate("'" + writeScene("hair", R"(
name: hair_on_table
duration: 0.4
frame_rate: 20
world: {grid_spacing: 0.01}
hair:
  - name: lock
    groom: {strands: 10, length: 0.04, segments: 8, radii: 0.005, centre: [0, 0, 0.02],
            direction: [1, 0, 0], cone_angle: 0.3}
    roots: loose
    continuum: {enabled: true}
colliders:
  - name: table
    table: {size: [0.3, 0.3], depth: 0.05}
    friction: 0.5
)") + "' --out '" + out.string() +
                             "' --format ply --render-frames last");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("1 hair (10 strands, 90 vertices)"), std::string::npos) << r.output;
  EXPECT_EQ(countFiles(out / "frames", ".ply"), 9);  // frames 0..8
  std::ifstream ply(out / "frames" / "lock_0008.ply");
  const std::string text((std::istreambuf_iterator<char>(ply)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("element vertex 90\n"), std::string::npos);
  EXPECT_NE(text.find("element edge 80\n"), std::string::npos);
  EXPECT_GT(fs::file_size(out / "render_0008.png"), 1000u);

  const nlohmann::json j = readJson(out / "report.json");
  ASSERT_EQ(j["bodies"].size(), 1u);
  EXPECT_EQ(j["bodies"][0]["kind"], "hair");
  EXPECT_EQ(j["bodies"][0]["strands"], 10);
  const auto& last = j["frames"][8];
  EXPECT_LT(last["bodies"]["lock"]["deepest_penetration_m"].get<double>(), 1e-4);
  EXPECT_LT(last["bodies"]["lock"]["largest_stretch"].get<double>(), 1.01);
  // The lock's weight, rho pi r^2 L g per strand (human hair: 1300 kg/m^3, r 40 um).
  const double weight = 10 * 1300.0 * M_PI * 40e-6 * 40e-6 * 0.04 * 9.81;
  const double fz = last["colliders"]["table"]["force_N"][2].get<double>();
  std::printf(
      "[figure] hair lock on the table after 0.4 s: table load %.4e N, weight %.4e N "
      "(error %.2e), lowest vertex %.2e m into it\n",
      -fz, weight, -fz / weight - 1.0,
      last["bodies"]["lock"]["deepest_penetration_m"].get<double>());
  EXPECT_NEAR(-fz, weight, 0.05 * weight);
  fs::remove_all(out);
}

TEST(SimulateTool, BlowUpStopsWithStatus2AndKeepsFrames) {
  // Eighty times the explicit stability bound: the sheets blow up within a few frames, and the
  // steps the CFL bound then asks for exceed the frame's budget.
  std::string text = std::string(kTwoSheets) + ", safety: 40" + kBodies;
  text += "max_substeps_per_frame: 60\n";
  const fs::path out = tempDir() / "blowup";
  const ToolRun r = simulate("'" + writeScene("blowup", text) + "' --out '" + out.string() +
                             "' --format ply --render-frames none --quiet");
  ASSERT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("stopped:"), std::string::npos);
  const nlohmann::json j = readJson(out / "report.json");
  EXPECT_EQ(j["status"], "stopped");
  const int last = j["stop"]["last_complete_frame"].get<int>();
  EXPECT_LT(last, 10);
  EXPECT_NE(j["stop"]["reason"].get<std::string>().find("frame " + std::to_string(last + 1)),
            std::string::npos);
  EXPECT_EQ(j["frames"].size(), static_cast<std::size_t>(last + 1));
  EXPECT_EQ(countFiles(out / "frames", ".ply"), 2 * (last + 1));
  fs::remove_all(out);
}

TEST(SimulateTool, BadInputIsStatus1) {
  EXPECT_EQ(simulate("/no/such/scene.yaml").status, 1);
  const std::string scene = writeScene("bad", std::string(kTwoSheets) + kBodies + "colour: red\n");
  const ToolRun r = simulate("'" + scene + "' --out '" + (tempDir() / "bad").string() + "'");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.output.find("colour: unknown key"), std::string::npos);
  const std::string good = writeScene("good", std::string(kTwoSheets) + kBodies);
  EXPECT_EQ(simulate("'" + good + "' --format stl").status, 1);
  EXPECT_EQ(simulate("'" + good + "' --render-frames 11").status, 1);
  fs::remove_all(tempDir());
}

}  // namespace
}  // namespace chs
