// checkMesh: every bad-mesh case is an InputError whose message names the offender; the
// generators produce meshes that pass.
#include <cmath>
#include <limits>
#include <string>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/mesh/grid_generators.h"
#include "cloth_hair_sim/core/mesh/mesh_check.h"
#include "cloth_hair_sim/core/mesh/mesh_weld.h"
#include "cloth_hair_sim/core/mesh/vertex_selection.h"

namespace chs {
namespace {

// Expects checkMesh to throw InputError whose message contains every given fragment.
void expectRejected(const QuadMesh& mesh, std::initializer_list<std::string> fragments) {
  try {
    checkMesh(mesh);
    FAIL() << "mesh accepted";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    std::cout << "  rejected: " << msg << "\n";
    for (const auto& f : fragments) EXPECT_NE(msg.find(f), std::string::npos) << msg;
  }
}

// 16 vertices, 9 quads; vertex (i, j) at (i, j, 0).
QuadMesh grid() {
  return makeRectangleMesh(3.0, 3.0, 3, 3, {1.5, 1.5, 0.0});
}

TEST(MeshCheck, GeneratedMeshesPass) {
  EXPECT_NO_THROW(checkMesh(grid()));
  EXPECT_NO_THROW(checkMesh(makeRectangleMesh(0.2, 0.1, 20, 10, {1, 2, 3})));
  for (int n : {3, 4, 8, 24, 33}) EXPECT_NO_THROW(checkMesh(makeDiscMesh(0.127, n))) << n;
}

TEST(MeshCheck, Empty) {
  expectRejected(QuadMesh{}, {"empty"});
  QuadMesh m = grid();
  m.quads.clear();
  expectRejected(m, {"empty", "0 quads"});
}

TEST(MeshCheck, NanAndInfVertex) {
  QuadMesh m = grid();
  m.vertices[5].y() = std::numeric_limits<double>::quiet_NaN();
  expectRejected(m, {"vertex 5", "non-finite"});
  m = grid();
  m.vertices[11].z() = std::numeric_limits<double>::infinity();
  expectRejected(m, {"vertex 11"});
}

TEST(MeshCheck, IndexOutOfRangeAndRepeated) {
  QuadMesh m = grid();
  m.quads[4][2] = 16;
  expectRejected(m, {"quad 4", "vertex 16"});
  m = grid();
  m.quads[7][3] = -1;
  expectRejected(m, {"quad 7", "vertex -1"});
  m = grid();
  m.quads[2][1] = m.quads[2][3];
  expectRejected(m, {"quad 2", "repeats vertex"});
}

TEST(MeshCheck, UnusedVertex) {
  QuadMesh m = grid();
  m.vertices.emplace_back(10, 10, 0);
  expectRejected(m, {"vertex 16", "no quad"});
}

TEST(MeshCheck, DegenerateQuad) {
  QuadMesh m = grid();
  m.vertices[5] = m.vertices[6];  // zero-length edge 6-5 of quad 1
  expectRejected(m, {"quad 1", "degenerate", "zero length"});
  // Zero area without a zero-length edge: all four corners on a line.
  QuadMesh flat;
  flat.vertices = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}};
  flat.quads = {{0, 1, 2, 3}};
  expectRejected(flat, {"quad 0", "degenerate"});
}

TEST(MeshCheck, ConcaveQuad) {
  QuadMesh m = grid();
  m.vertices[5] = {0.2, 0.2, 0.0};  // pushed through the diagonal 1-4 of quad 0
  expectRejected(m, {"quad 0", "vertex 5"});
}

TEST(MeshCheck, InvertedQuadByNumbering) {
  QuadMesh m = grid();
  std::swap(m.quads[4][1], m.quads[4][3]);  // the centre quad, clockwise
  expectRejected(m, {"quad 4", "inverted"});
  m = grid();
  std::swap(m.quads[0][1], m.quads[0][3]);  // a corner quad, two neighbours
  expectRejected(m, {"quad 0", "inverted"});
}

TEST(MeshCheck, InvertedQuadByGeometry) {
  // Two quads sharing edge 1-2, numbered consistently, the second folded back onto the first.
  QuadMesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.2, 1, 1e-3}, {0.2, 0, 1e-3}};
  m.quads = {{0, 1, 2, 3}, {1, 5, 4, 2}};
  expectRejected(m, {"inverted", "normal is opposite"});
}

TEST(MeshCheck, NonManifoldEdge) {
  QuadMesh m = grid();
  // A fin on edge 5-6 (shared by quads 1 and 4): a third quad standing up.
  m.vertices.emplace_back(1, 1, 1);
  m.vertices.emplace_back(2, 1, 1);
  m.quads.push_back({5, 6, 17, 16});
  expectRejected(m, {"edge 5-6", "non-manifold", "3 quads"});
}

TEST(MeshGenerators, RectangleLayout) {
  const QuadMesh m = makeRectangleMesh(0.2, 0.1, 4, 2, {1, 2, 3});
  ASSERT_EQ(m.numVertices(), 15);
  ASSERT_EQ(m.numQuads(), 8);
  const int i = 3, j = 2;  // index j * (nx + 1) + i
  EXPECT_TRUE(m.vertices[j * 5 + i].isApprox(Eigen::Vector3d(1.05, 2.05, 3.0)));
  EXPECT_TRUE(m.vertices[0].isApprox(Eigen::Vector3d(0.9, 1.95, 3.0)));
  for (const auto& q : m.quads) {  // normal +z
    const Eigen::Vector3d n =
        (m.vertices[q[2]] - m.vertices[q[0]]).cross(m.vertices[q[3]] - m.vertices[q[1]]);
    EXPECT_GT(n.z(), 0.0);
  }
  EXPECT_THROW(makeRectangleMesh(0.0, 1.0, 2, 2), InputError);
  EXPECT_THROW(makeRectangleMesh(1.0, 1.0, 0, 2), InputError);
}

TEST(MeshGenerators, DiscIsUniformAndRound) {
  const double r = 0.127;
  const int n = 32;
  const QuadMesh m = makeDiscMesh(r, n, {0, 0, 0.5});
  // k = 5, m = 22: 22^2 + 4 * 22 * 5 quads.
  EXPECT_EQ(m.numQuads(), 22 * 22 + 4 * 22 * 5);
  double area = 0.0, min_edge = 1e9, max_edge = 0.0;
  for (const auto& q : m.quads) {
    const Eigen::Vector3d a =
        0.5 * (m.vertices[q[2]] - m.vertices[q[0]]).cross(m.vertices[q[3]] - m.vertices[q[1]]);
    EXPECT_GT(a.z(), 0.0);
    area += a.z();
    for (int k = 0; k < 4; ++k) {
      const double e = (m.vertices[q[(k + 1) % 4]] - m.vertices[q[k]]).norm();
      min_edge = std::min(min_edge, e);
      max_edge = std::max(max_edge, e);
    }
  }
  // Polygon of 4 * 16 chords: area within 0.2 % of the circle's.
  std::cout << "  disc area / pi r^2 = " << area / (M_PI * r * r)
            << ", edge ratio max/min = " << max_edge / min_edge << "\n";
  EXPECT_NEAR(area / (M_PI * r * r), 1.0, 2e-3);
  EXPECT_LT(max_edge / min_edge, 1.7);
  const auto rim = boundaryVertices(m);
  EXPECT_EQ(static_cast<int>(rim.size()), 4 * 22);
  for (int v : rim) EXPECT_NEAR((m.vertices[v] - Eigen::Vector3d(0, 0, 0.5)).norm(), r, 1e-12);
  EXPECT_NEAR(m.vertices[nearestVertex(m, {0, 0, 0.5})].norm(), 0.5, 1e-12);  // centre vertex
}

TEST(MeshSelection, Selectors) {
  const QuadMesh m = makeRectangleMesh(2.0, 2.0, 4, 4);
  EXPECT_EQ(verticesOnPlane(m, 0, -1.0, 1e-9), (std::vector<int>{0, 5, 10, 15, 20}));
  EXPECT_EQ(nearestVertex(m, {0.6, 0.4, 1.0}), 3 * 5 + 3);  // (0.5, 0.5)
  EXPECT_EQ(verticesInBox(m, {-0.1, -0.1, -1}, {0.6, 0.1, 1}), (std::vector<int>{12, 13}));
  EXPECT_EQ(boundaryVertices(m).size(), 16u);
}

TEST(MeshWeld, MergesSeamsAndDropsUnused) {
  QuadMesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0},         {0, 1, 0}, {1, 0, 0},
                {2, 0, 0}, {2, 1, 0}, {1, 1 + 1e-12, 0}, {9, 9, 9}};
  m.quads = {{0, 1, 2, 3}, {4, 5, 6, 7}};
  weldVertices(m, 1e-9);
  EXPECT_EQ(m.numVertices(), 6);
  EXPECT_EQ(m.quads[1][0], m.quads[0][1]);
  EXPECT_EQ(m.quads[1][3], m.quads[0][2]);
  EXPECT_NO_THROW(checkMesh(m));
}

}  // namespace
}  // namespace chs
