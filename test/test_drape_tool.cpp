// The drape executable's contract on bad input: exit status 1 and a message naming the problem.
#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "drape_tool_runner.h"

namespace {

namespace fs = std::filesystem;

using chs::testing::drape;
using chs::testing::ToolRun;

fs::path tempDir() {
  const fs::path dir = fs::temp_directory_path() / ("chs_test_drape_" + std::to_string(getpid()));
  fs::create_directories(dir);
  return dir;
}

TEST(DrapeTool, MissingSceneFile) {
  const ToolRun r = drape("/nonexistent/scene.yaml --quiet");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.output.find("/nonexistent/scene.yaml"), std::string::npos);
  EXPECT_NE(r.output.find("no such scene file"), std::string::npos);
}

TEST(DrapeTool, BadUsage) {
  EXPECT_EQ(drape("").status, 1);
  EXPECT_EQ(drape("--frobnicate x.yaml").status, 1);
  const std::string scene = std::string(CHS_SOURCE_DIR) + "/scenes/tablecloth_fem.yaml";
  const ToolRun r = drape("'" + scene + "' --method magic --out " + (tempDir() / "m").string());
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.output.find("magic"), std::string::npos);
  fs::remove_all(tempDir());
}

TEST(DrapeTool, BadMaterial) {
  const fs::path dir = tempDir();
  std::ofstream(dir / "bad.yaml") << "garment: {rectangle: {size: [0.2, 0.2], cells: [4, 4]}}\n"
                                     "material: {preset: cotton_eischen, poisson: 0.7}\n";
  const ToolRun r =
      drape("'" + (dir / "bad.yaml").string() + "' --out '" + (dir / "out").string() + "'");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.output.find("material.poisson"), std::string::npos);
  fs::remove_all(dir);
}

}  // namespace
