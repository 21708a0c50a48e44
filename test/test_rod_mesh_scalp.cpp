// A groom on a triangle mesh's scalp region (core/rod/groom.h, groomMesh): on a triangulated
// sphere the roots lie on the mesh, inside the patch's cone, uniform in area (the share within a
// smaller cone is its share of the spherical cap's area), each strand leaves along the sphere's
// normal whatever the triangles' winding, the draw is the seed's, and bad input is refused.
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/rod/groom.h"

namespace chs::rod {
namespace {

using Vec3 = Eigen::Vector3d;
constexpr double kRadius = 0.1;

// A UV sphere of radius kRadius about the origin (one vertex at each pole), wound outwards (or
// inwards).
TriangleMesh uvSphere(int rings, int sectors, bool inwards = false) {
  TriangleMesh m;
  m.vertices.push_back(kRadius * Vec3::UnitZ());
  for (int i = 1; i < rings; ++i)
    for (int j = 0; j < sectors; ++j) {
      const double theta = M_PI * i / rings, phi = 2.0 * M_PI * j / sectors;
      m.vertices.push_back(kRadius * Vec3(std::sin(theta) * std::cos(phi),
                                          std::sin(theta) * std::sin(phi), std::cos(theta)));
    }
  m.vertices.push_back(-kRadius * Vec3::UnitZ());
  const int south = m.numVertices() - 1;
  auto at = [&](int i, int j) {
    return i == 0 ? 0 : i == rings ? south : 1 + (i - 1) * sectors + (j % sectors);
  };
  auto add = [&](int a, int b, int c) {
    if (a == b || b == c || c == a) return;
    m.triangles.push_back(inwards ? std::array<int, 3>{a, c, b} : std::array<int, 3>{a, b, c});
  };
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < sectors; ++j) {
      add(at(i, j), at(i + 1, j), at(i + 1, j + 1));
      add(at(i, j), at(i + 1, j + 1), at(i, j + 1));
    }
  return m;
}

GroomSettings patch(double cone_angle, int strands) {
  GroomSettings s;
  s.scalp.direction = Vec3::UnitZ();
  s.scalp.cone_angle = cone_angle;
  s.strands = strands;
  s.length = 0.05;
  s.segments = 5;
  return s;
}

TEST(MeshScalp, RootsLieOnTheRegionUniformInAreaAndStrandsLeaveAlongTheNormal) {
  const TriangleMesh sphere = uvSphere(60, 120);
  const double cone = M_PI / 3;
  const int n = 8000;
  for (bool inwards : {false, true}) {
    const Polylines strands = groomMesh(uvSphere(60, 120, inwards), patch(cone, n));
    ASSERT_EQ(static_cast<int>(strands.size()), n);
    double worst_radius = 0.0, worst_tilt = 0.0, worst_angle = 0.0, worst_length = 0.0;
    int inner = 0;
    for (const auto& x : strands) {
      const Vec3& root = x.front();
      // Inside the sphere by at most the facets' sag across a 3 x 3 deg cell's diagonal,
      // R (1 - cos(2.1 deg)) = 6.9e-5 m.
      worst_radius = std::max(worst_radius, std::abs(root.norm() - kRadius));
      worst_tilt = std::max(
          worst_tilt, std::acos(std::min(1.0, (x[1] - x[0]).normalized().dot(root.normalized()))));
      worst_angle = std::max(worst_angle, std::acos(root.normalized().z()));
      double length = 0.0;
      for (std::size_t i = 1; i < x.size(); ++i) length += (x[i] - x[i - 1]).norm();
      worst_length = std::max(worst_length, std::abs(length - 0.05));
      inner += std::acos(root.normalized().z()) <= M_PI / 6;
    }
    // Uniform in area: the cap within 30 deg holds (1 - cos 30) / (1 - cos 60) of the region's.
    const double share = static_cast<double>(inner) / n, expected = (1 - std::cos(M_PI / 6)) / 0.5;
    const double sigma = std::sqrt(expected * (1 - expected) / n);
    std::printf(
        "[figure] mesh scalp (%s triangles), %d strands in a 60 deg cone: roots %.1e m off the "
        "sphere at most, within %.2f deg of the axis (faces' centroids within 60), strands "
        "%.2f deg off the normal, length error %.1e m; share within 30 deg %.4f vs area share "
        "%.4f (sigma %.4f)\n",
        inwards ? "inward" : "outward", n, worst_radius, worst_angle * 180 / M_PI,
        worst_tilt * 180 / M_PI, worst_length, share, expected, sigma);
    EXPECT_LT(worst_radius, 7e-5);
    EXPECT_LT(worst_angle, cone + 2 * M_PI / 60);  // a centroid within it, the face beyond by less
    EXPECT_LT(worst_tilt * 180 / M_PI, 3.0);       // area-weighted normals: within a 3 deg cell
    EXPECT_LT(worst_length, 1e-12);
    EXPECT_NEAR(share, expected, 4 * sigma);
  }
  // The same seed draws the same roots; another seed others.
  const Polylines a = groomMesh(sphere, patch(cone, 50)), b = groomMesh(sphere, patch(cone, 50));
  GroomSettings other = patch(cone, 50);
  other.seed = 7;
  const Polylines c = groomMesh(sphere, other);
  EXPECT_EQ(a, b);
  EXPECT_NE(a.front().front(), c.front().front());
}

TEST(MeshScalp, CurlsTurnAboutTheNormal) {
  GroomSettings s = patch(0.5, 20);
  s.curl_radius = 0.005;
  s.curl_pitch = 0.01;
  s.segments = 40;
  for (const auto& x : groomMesh(uvSphere(30, 60), s)) {
    // A helix about the normal: every vertex within the curl radius of the axis through the root.
    const Vec3 axis = x.front().normalized();
    double worst = 0.0;
    for (const Vec3& v : x) {
      const Vec3 r = v - x.front();
      worst = std::max(worst, (r - r.dot(axis) * axis).norm());
    }
    EXPECT_LT(worst, 2 * s.curl_radius + 1e-3);  // the axis is the interpolated normal
  }
}

TEST(MeshScalp, RefusesBadInput) {
  const TriangleMesh sphere = uvSphere(10, 20);
  auto refuses = [](const TriangleMesh& m, const GroomSettings& s, const char* what) {
    try {
      groomMesh(m, s);
      ADD_FAILURE() << "accepted: " << what;
    } catch (const InputError& e) {
      std::printf("refused (%s): %s\n", what, e.what());
    }
  };
  refuses(TriangleMesh{}, patch(1.0, 10), "empty mesh");
  TriangleMesh nan = sphere;
  nan.vertices[3].x() = std::nan("");
  refuses(nan, patch(1.0, 10), "NaN vertex");
  TriangleMesh out_of_range = sphere;
  out_of_range.triangles[0][1] = 100000;
  refuses(out_of_range, patch(1.0, 10), "corner out of range");
  GroomSettings aside = patch(0.2, 10);
  aside.scalp.centre = Vec3(1.0, 0.0, 0.0);  // the cone from there misses the sphere
  refuses(sphere, aside, "no triangle in the cone");
  refuses(sphere, patch(0.0, 10), "zero cone angle");
  refuses(sphere, patch(1.0, 0), "no strands");
  GroomSettings flat_curl = patch(1.0, 10);
  flat_curl.curl_radius = 0.01;
  refuses(sphere, flat_curl, "curl without pitch");
}

}  // namespace
}  // namespace chs::rod
