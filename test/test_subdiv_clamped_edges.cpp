// Clamped edges of a Catmull-Clark shell (subdiv/clamped_edges.h): the ghost faces leave the
// reference surface as it was, the slaving holds the limit position and tangent plane along the
// clamp line for any position of the free points and leaves the curvature free, and the folded
// forces are the chain rule through the slaving.
#include <cmath>
#include <cstdio>
#include <random>

#include <gtest/gtest.h>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/mesh/grid_generators.h"
#include "cloth_hair_sim/core/subdiv/clamped_edges.h"
#include "cloth_hair_sim/core/subdiv/limit_surface.h"

namespace chs {
namespace {

using Vec3 = Eigen::Vector3d;

constexpr int kNx = 4, kNy = 3;
int vertex(int i, int j) {
  return j * (kNx + 1) + i;
}

// A 4 x 3 sheet over [0, 0.4] x [0, 0.3] clamped along x = 0 (column i = 0).
QuadMesh sheet() {
  return makeRectangleMesh(0.4, 0.3, kNx, kNy, Vec3(0.2, 0.15, 0.0));
}
std::vector<int> firstColumn() {
  std::vector<int> v;
  for (int j = 0; j <= kNy; ++j) v.push_back(vertex(0, j));
  return v;
}

TEST(ClampedEdges, GhostFacesKeepTheReferenceSurface) {
  const QuadMesh mesh = sheet();
  const ClampedEdges clamps(mesh, firstColumn());
  ASSERT_EQ(clamps.clamps().size(), static_cast<std::size_t>(kNy + 1));
  EXPECT_EQ(clamps.extendedMesh().numVertices(), mesh.numVertices() + kNy + 1);
  EXPECT_EQ(clamps.extendedMesh().numQuads(), mesh.numQuads() + kNy);
  EXPECT_EQ(clamps.numMeshFaces(), mesh.numQuads());
  for (const auto& c : clamps.clamps()) {
    EXPECT_EQ(c.interior, c.boundary + 1);  // the next point of the same row
    EXPECT_NEAR((c.direction - Vec3::UnitX()).norm(), 0.0, 1e-15);
    EXPECT_TRUE(clamps.isSlaved(c.boundary) && clamps.isSlaved(c.ghost));
    EXPECT_FALSE(clamps.isSlaved(c.interior));
  }
  // The mesh's own faces, limit surface with and without the ghosts, on a 7 x 7 sample grid.
  const LimitSurface free_surface(mesh), clamped_surface(clamps.extendedMesh());
  double largest = 0.0;
  for (int f = 0; f < mesh.numQuads(); ++f)
    for (int a = 0; a <= 6; ++a)
      for (int b = 0; b <= 6; ++b) {
        const Vec3 x0 = free_surface.stencil(f, a / 6.0, b / 6.0).position(mesh.vertices);
        const Vec3 x1 =
            clamped_surface.stencil(f, a / 6.0, b / 6.0).position(clamps.extendedMesh().vertices);
        largest = std::max(largest, (x1 - x0).norm());
      }
  std::printf("[figure] clamped edges: reference surface moved by the ghost faces %.2e m\n",
              largest);
  EXPECT_LT(largest, 1e-14);
}

TEST(ClampedEdges, SlavingHoldsPositionAndTangentPlaneAndFreesCurvature) {
  const QuadMesh mesh = sheet();
  const ClampedEdges clamps(mesh, firstColumn());
  const LimitSurface surface(clamps.extendedMesh());
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> jitter(-0.05, 0.05);
  std::vector<Vec3> x = clamps.extendedMesh().vertices;
  for (Vec3& p : x) p += Vec3(jitter(rng), jitter(rng), 2.0 * jitter(rng));
  clamps.placePositions(x);
  // Along the clamp line x = 0 (u = 0 of the faces i = 0): on the line through the clamp
  // points, and the cross tangent x_u along t = +x; the cross curvature x_uu is free.
  double off_line = 0.0, off_tangent = 0.0, curvature = 0.0;
  for (int j = 0; j < kNy; ++j) {
    const int f = j * kNx;  // face (0, j)
    for (int b = 0; b <= 8; ++b) {
      const SurfaceStencil s = surface.stencil(f, 0.0, b / 8.0);
      const Vec3 p = s.position(x), xu = s.combine(s.du, x), xuu = s.combine(s.duu, x);
      off_line = std::max(off_line, std::hypot(p.x(), p.z()));
      off_tangent = std::max(off_tangent, std::hypot(xu.y(), xu.z()) / xu.norm());
      curvature = std::max(curvature, std::abs(xuu.z()) / xu.squaredNorm());
    }
  }
  std::printf(
      "[figure] clamped edges, free points jittered by 5 cm: clamp line off its place by %.2e "
      "m, cross tangent off t by %.2e, cross curvature up to %.2f 1/m (free)\n",
      off_line, off_tangent, curvature);
  EXPECT_LT(off_line, 1e-14);
  EXPECT_LT(off_tangent, 1e-14);
  EXPECT_GT(curvature, 0.1);
}

// Virtual work: f_B . dB + f_G . dG = (J_B^T f_B + J_G^T f_G) . dN for any dN.
TEST(ClampedEdges, FoldedForcesAreTheChainRule) {
  const QuadMesh mesh = sheet();
  const ClampedEdges clamps(mesh, firstColumn());
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const auto random = [&] { return Vec3(u(rng), u(rng), u(rng)); };
  std::vector<Vec3> x = clamps.extendedMesh().vertices, v(x.size(), Vec3::Zero());
  double largest = 0.0;
  for (const auto& c : clamps.clamps()) {
    const Vec3 fb = random(), fg = random(), dn = random();
    std::vector<Vec3> moved = x;
    moved[c.interior] += 1e-3 * dn;
    clamps.placePositions(moved);
    clamps.placePositions(x);
    const double work = fb.dot(moved[c.boundary] - x[c.boundary]) +
                        fg.dot(moved[c.ghost] - x[c.ghost]) -
                        clamps.foldedForce(c, fb, fg).dot(moved[c.interior] - x[c.interior]);
    largest = std::max(largest, std::abs(work));
    // Velocities are the same linear map.
    v[c.interior] = dn;
  }
  clamps.placeVelocities(v);
  std::vector<Vec3> x1 = x;
  for (const auto& c : clamps.clamps()) x1[c.interior] += v[c.interior];
  clamps.placePositions(x1);
  double velocity_error = 0.0;
  for (const auto& c : clamps.clamps())
    velocity_error =
        std::max({velocity_error, (x1[c.boundary] - x[c.boundary] - v[c.boundary]).norm(),
                  (x1[c.ghost] - x[c.ghost] - v[c.ghost]).norm()});
  std::printf("[figure] clamped edges: virtual work mismatch %.2e, velocity map %.2e\n", largest,
              velocity_error);
  EXPECT_LT(largest, 1e-15);
  EXPECT_LT(velocity_error, 1e-14);
}

TEST(ClampedEdges, RefusesClampsWithoutAnEdgeOrDirection) {
  const QuadMesh mesh = sheet();
  const auto message = [&](const std::vector<int>& clamped) {
    try {
      ClampedEdges c(mesh, clamped);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(message({vertex(1, 1)}).find("not on the mesh boundary"), std::string::npos);
  EXPECT_NE(message({vertex(0, 1)}).find("no clamped neighbour"), std::string::npos);
  // Column 0 and row 0 meet at the corner (0, 0): no direction into the shell there.
  std::vector<int> l_shape = firstColumn();
  for (int i = 1; i <= kNx; ++i) l_shape.push_back(vertex(i, 0));
  EXPECT_NE(message(l_shape).find("no unique direction"), std::string::npos);
  EXPECT_NE(message({99}).find("out of range"), std::string::npos);
  // Half of the edge x = 0: its last point keeps a free boundary edge.
  EXPECT_NE(message({vertex(0, 0), vertex(0, 1)}).find("partway"), std::string::npos);
  EXPECT_TRUE(ClampedEdges(mesh, {}).empty());
  // A ring one quad tall with both rims clamped: each clamped point's neighbour is clamped too.
  QuadMesh ring;
  constexpr int n = 8;
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < n; ++i)
      ring.vertices.push_back(
          Vec3(std::cos(2 * M_PI * i / n), std::sin(2 * M_PI * i / n), 0.3 * j));
  for (int i = 0; i < n; ++i) ring.quads.push_back({i, (i + 1) % n, n + (i + 1) % n, n + i});
  std::vector<int> rims(2 * n);
  for (int i = 0; i < 2 * n; ++i) rims[i] = i;
  try {
    ClampedEdges c(ring, rims);
    ADD_FAILURE() << "a ring clamped on both rims was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("is clamped too"), std::string::npos) << e.what();
  }
}

// The clamp's net force is what B, G and the constraint force on N add up to:
// r_B + r_G - J_B^T r_B - J_G^T r_G, whatever the residuals.
TEST(ClampedEdges, ReactionIsTheSumOfTheConstraintForces) {
  const ClampedEdges clamps(sheet(), firstColumn());
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  double largest = 0.0;
  for (const auto& c : clamps.clamps()) {
    const Vec3 rb(u(rng), u(rng), u(rng)), rg(u(rng), u(rng), u(rng));
    const Vec3 on_neighbour = -clamps.foldedForce(c, rb, rg);
    largest = std::max(largest, (clamps.reaction(c, rb, rg) - (rb + rg + on_neighbour)).norm());
  }
  std::printf("[figure] clamped edges: reaction against the summed constraint forces %.2e\n",
              largest);
  EXPECT_LT(largest, 1e-15);
}

}  // namespace
}  // namespace chs
