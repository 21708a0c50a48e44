// The broad phase of the shell's fibre contact (mpm/layer_proximity.h): one layer, flat at any
// orientation, bent at a right angle round one cell or folded with its legs farther apart than the
// kernel's reach, has no particle near another layer; a sheet folded with its legs 1-2 cells
// apart has every particle under the folded flap near it, and none beyond the flap's reach.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/mesh/grid_generators.h"
#include "cloth_hair_sim/core/mpm/layer_proximity.h"
#include "cloth_hair_sim/core/mpm/transfers.h"

namespace chs::mpm {
namespace {

using Vec3 = Eigen::Vector3d;
constexpr double kDx = 0.01;
constexpr int kDegree = 2;

struct Layers {
  std::vector<Vec3> rest;  // of the particles, on the flat sheet
  std::vector<char> near;
  int count() const {
    int c = 0;
    for (char n : near) c += n;
    return c;
  }
};

// 2 x 2 particles per face of a flat sheet (as the shell's contact particles), placed by `shape`
// from their rest positions, then the broad phase on a grid of spacing kDx.
Layers findLayers(const QuadMesh& mesh, const std::function<Vec3(const Vec3&)>& shape) {
  Particles particles;
  std::vector<int> face;
  Layers out;
  for (int f = 0; f < mesh.numQuads(); ++f) {
    const auto& q = mesh.quads[f];
    for (double a : {0.25, 0.75})
      for (double b : {0.25, 0.75}) {
        const Vec3 x = (1 - a) * (1 - b) * mesh.vertices[q[0]] + a * (1 - b) * mesh.vertices[q[1]] +
                       a * b * mesh.vertices[q[2]] + (1 - a) * b * mesh.vertices[q[3]];
        out.rest.push_back(x);
        particles.add(shape(x), Vec3::Zero(), 0.0, 1.0);
        face.push_back(f);
      }
  }
  SparseGrid grid(kDx);
  std::vector<SupportNodes> supports;
  particleToGrid({&particles}, grid, kDegree, &supports);
  const LayerProximity layers(mesh, face, std::sqrt(3.0) * (kDegree + 1) * kDx);
  layers.find(grid, supports[0], particles.x, out.near);
  return out;
}

// A sheet 0.4 x 0.1 m (x from -0.2 to 0.2), flat for x <= x0, then bent round a cylinder of
// radius r through `angle` and straight on along its tangent: angle pi folds the part x > x0
// back over the sheet, 2 r above it.
Layers bent(double r, double angle, const Eigen::Matrix3d& rotation = Eigen::Matrix3d::Identity(),
            double x0 = 0.0) {
  const QuadMesh sheet = makeRectangleMesh(0.4, 0.1, 40, 10);
  return findLayers(sheet, [=](const Vec3& x) {
    if (x.x() <= x0) return Vec3(rotation * x);
    const double s = std::min(x.x() - x0, angle * r), rest = x.x() - x0 - s;
    const Vec3 arc(x0 + r * std::sin(s / r), x.y(), r * (1 - std::cos(s / r)));
    const Vec3 tangent(std::cos(s / r), 0.0, std::sin(s / r));
    return Vec3(rotation * (arc + rest * tangent));
  });
}

TEST(LayerProximity, ALoneLayerIsNeverNearAnother) {
  const Eigen::Matrix3d oblique =
      (Eigen::AngleAxisd(0.6155, Vec3::UnitY()) * Eigen::AngleAxisd(M_PI / 4, Vec3::UnitX()))
          .toRotationMatrix();
  const struct {
    const char* name;
    Layers layers;
  } cases[] = {
      {"flat", bent(kDx, 0.0)},
      {"flat, oblique to every grid axis", bent(kDx, 0.0, oblique)},
      {"bent at a right angle round 1 cell", bent(kDx, M_PI / 2)},
      {"bent at a right angle round 1 cell, oblique", bent(kDx, M_PI / 2, oblique)},
      {"folded round 3 cells (legs 6 cells apart)", bent(3 * kDx, M_PI)},
      {"folded round 4 cells (legs 8 cells apart)", bent(4 * kDx, M_PI)},
  };
  for (const auto& c : cases) {
    std::printf("one layer, %s: %d of %zu particles near another layer\n", c.name, c.layers.count(),
                c.layers.near.size());
    EXPECT_EQ(c.layers.count(), 0) << c.name;
  }
}

TEST(LayerProximity, AFoldedSheetIsNearItselfWithinTheKernelReach) {
  for (double gap_cells : {1.0, 2.0}) {
    const double r = 0.5 * gap_cells * kDx;
    const Layers l = bent(r, M_PI, Eigen::Matrix3d::Identity(), 0.1);
    // The flap x > 0.1 covers x in [pi r, 0.1] of the sheet; the sheet's particles there, away
    // from the flap's edge and the bend, must see the flap, and those more than the reach beyond
    // the flap's edge must not.
    const double flap_end = M_PI * r;
    int under = 0, under_near = 0, beyond = 0, beyond_near = 0;
    for (std::size_t p = 0; p < l.rest.size(); ++p) {
      const double x = l.rest[p].x();
      if (x > flap_end + 3 * kDx && x < 0.1 - 3 * kDx) {
        ++under;
        under_near += l.near[p];
      }
      if (x < flap_end - 6 * kDx) {
        ++beyond;
        beyond_near += l.near[p];
      }
    }
    std::printf(
        "folded with the legs %.0f cells apart: %d of %d particles under the flap near "
        "it, %d of %d beyond its reach\n",
        gap_cells, under_near, under, beyond_near, beyond);
    EXPECT_EQ(under_near, under);
    EXPECT_EQ(beyond_near, 0);
  }
}

// A tube of 24 faces round (1 cm faces: radius 3.8 cells) and 30 along, pinched in its middle to
// an ellipse whose flat sides are 1.5 cells apart, as the twisted tube's neck: the facing sides at
// the pinch are 12 faces apart along the surface and share grid nodes, so they are near; the
// round ends, whose opposite sides are 7.6 cells apart, are one layer. (A tube narrower than the
// kernel's reach, 5.2 cells, is near itself everywhere: its opposite sides share nodes.)
TEST(LayerProximity, APinchedTubeIsNearItselfAtThePinch) {
  const int around = 24, along = 30;
  const double r = around * kDx / (2 * M_PI);
  QuadMesh tube;
  for (int j = 0; j <= along; ++j)
    for (int i = 0; i < around; ++i) {
      const double phi = 2 * M_PI * i / around;
      tube.vertices.emplace_back(r * std::cos(phi), r * std::sin(phi), j * kDx);
    }
  for (int j = 0; j < along; ++j)
    for (int i = 0; i < around; ++i) {
      const int a = j * around + i, b = j * around + (i + 1) % around;
      tube.quads.push_back({a, b, b + around, a + around});
    }
  const double middle = 0.5 * along * kDx, squeeze = 0.75 * kDx / r;
  const Layers l = findLayers(tube, [&](const Vec3& x) {
    // y scaled towards `squeeze` within 5 cells of the middle (a smooth bump).
    const double t = std::max(0.0, 1.0 - std::pow((x.z() - middle) / (5 * kDx), 2));
    return Vec3(x.x(), x.y() * (1.0 - (1.0 - squeeze) * t), x.z());
  });
  int pinch = 0, pinch_near = 0, ends = 0, ends_near = 0;
  for (std::size_t p = 0; p < l.rest.size(); ++p) {
    const Vec3& x = l.rest[p];
    const bool facing = std::abs(x.y()) > 0.7 * r;  // the flattened sides
    if (std::abs(x.z() - middle) < 1.5 * kDx && facing) {
      ++pinch;
      pinch_near += l.near[p];
    }
    if (std::abs(x.z() - middle) > 9 * kDx) {
      ++ends;
      ends_near += l.near[p];
    }
  }
  std::printf(
      "tube 24 faces round pinched to 1.5 cells: %d of %d particles of the facing sides at "
      "the pinch near the other side, %d of %d of the round ends\n",
      pinch_near, pinch, ends_near, ends);
  EXPECT_GT(pinch, 0);
  EXPECT_EQ(pinch_near, pinch);
  EXPECT_EQ(ends_near, 0);
}

TEST(LayerProximity, RefusesBadInput) {
  const QuadMesh sheet = makeRectangleMesh(0.1, 0.1, 2, 2);
  EXPECT_THROW(LayerProximity(sheet, {0, 4}, 0.01), InputError);
  EXPECT_THROW(LayerProximity(sheet, {0, 1}, 0.0), InputError);
  EXPECT_THROW(LayerProximity(sheet, {0, 1}, std::nan("")), InputError);
  const LayerProximity layers(sheet, {0, 1}, 0.01);
  SparseGrid grid(kDx);
  std::vector<char> near;
  EXPECT_THROW(layers.find(grid, SupportNodes{}, {Vec3::Zero()}, near), InputError);
}

}  // namespace
}  // namespace chs::mpm
