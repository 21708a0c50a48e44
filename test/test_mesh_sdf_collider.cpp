// Mesh colliders through an OpenVDB signed distance field (MeshSdfSurface): a triangulated sphere
// and box against their closed-form distances, the field moved by a pose, the far field, bad
// input, and the ColliderShape cache that builds one field per shape for every pose.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include <unistd.h>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/contact/collider_shape.h"
#include "cloth_hair_sim/core/contact/mesh_sdf_surface.h"
#include "cloth_hair_sim/core/contact/posed_surface.h"
#include "cloth_hair_sim/core/io/triangle_mesh_reader.h"

namespace chs {
namespace {

namespace fs = std::filesystem;

// Icosahedron refined `levels` times, vertices pushed onto the sphere: 20 * 4^levels triangles,
// wound counter-clockwise seen from outside.
TriangleMesh icosphere(double radius, int levels) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  TriangleMesh m;
  for (const auto& v :
       {Eigen::Vector3d(-1, t, 0), Eigen::Vector3d(1, t, 0), Eigen::Vector3d(-1, -t, 0),
        Eigen::Vector3d(1, -t, 0), Eigen::Vector3d(0, -1, t), Eigen::Vector3d(0, 1, t),
        Eigen::Vector3d(0, -1, -t), Eigen::Vector3d(0, 1, -t), Eigen::Vector3d(t, 0, -1),
        Eigen::Vector3d(t, 0, 1), Eigen::Vector3d(-t, 0, -1), Eigen::Vector3d(-t, 0, 1)})
    m.vertices.push_back(v.normalized());
  m.triangles = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                 {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                 {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                 {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<int, int>, int> middle;
    auto mid = [&](int a, int b) {
      const auto key = std::make_pair(std::min(a, b), std::max(a, b));
      const auto it = middle.find(key);
      if (it != middle.end()) return it->second;
      m.vertices.push_back((m.vertices[a] + m.vertices[b]).normalized());
      return middle[key] = m.numVertices() - 1;
    };
    std::vector<std::array<int, 3>> finer;
    for (const auto& f : m.triangles) {
      const int ab = mid(f[0], f[1]), bc = mid(f[1], f[2]), ca = mid(f[2], f[0]);
      finer.insert(finer.end(), {{f[0], ab, ca}, {f[1], bc, ab}, {f[2], ca, bc}, {ab, bc, ca}});
    }
    m.triangles = std::move(finer);
  }
  for (auto& v : m.vertices) v *= radius;
  return m;
}

// An axis-aligned box centred on the origin, 12 triangles.
TriangleMesh boxMesh(const Eigen::Vector3d& size) {
  TriangleMesh m;
  for (int i = 0; i < 8; ++i)
    m.vertices.push_back(
        0.5 * size.cwiseProduct(Eigen::Vector3d(i & 1 ? 1 : -1, i & 2 ? 1 : -1, i & 4 ? 1 : -1)));
  m.triangles = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                 {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
  return m;
}

// How far the flat facets of a mesh inscribed in a sphere of radius R (centred on the origin)
// stray from it: the deepest facet plane (its depth below the sphere) and the largest tilt of a
// face normal from the radial direction at the face's corners (asin of circumradius / R).
struct FacetBounds {
  double depth = 0.0, tilt_deg = 0.0;
};

FacetBounds facetBounds(const TriangleMesh& m, double radius) {
  FacetBounds b;
  for (const auto& t : m.triangles) {
    const Eigen::Vector3d &p = m.vertices[t[0]], &q = m.vertices[t[1]], &r = m.vertices[t[2]];
    const Eigen::Vector3d n = (q - p).cross(r - p).normalized();
    const double plane = std::abs(n.dot(p));  // distance of the face plane from the centre
    b.depth = std::max(b.depth, radius - plane);
    b.tilt_deg = std::max(
        b.tilt_deg, std::asin(std::sqrt(radius * radius - plane * plane) / radius) * 180.0 / M_PI);
  }
  return b;
}

void writeObj(const TriangleMesh& m, const fs::path& path, double unit = 1.0) {
  std::ofstream out(path);
  out.precision(17);
  for (const auto& v : m.vertices)
    out << "v " << unit * v.x() << ' ' << unit * v.y() << ' ' << unit * v.z() << '\n';
  for (const auto& t : m.triangles)
    out << "f " << t[0] + 1 << ' ' << t[1] + 1 << ' ' << t[2] + 1 << '\n';
}

// ASCII STL stores every corner per facet: the reader must weld them to close the surface.
void writeStl(const TriangleMesh& m, const fs::path& path, double unit) {
  std::ofstream out(path);
  out.precision(17);
  out << "solid box\n";
  for (const auto& t : m.triangles) {
    out << "facet normal 0 0 0\nouter loop\n";
    for (int k : t)
      out << "vertex " << unit * m.vertices[k].x() << ' ' << unit * m.vertices[k].y() << ' '
          << unit * m.vertices[k].z() << '\n';
    out << "endloop\nendfacet\n";
  }
  out << "endsolid box\n";
}

double angleDeg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b)) * 180.0 / M_PI;
}

Eigen::Isometry3d pose(const Eigen::Vector3d& t, double angle, const Eigen::Vector3d& axis) {
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  p.translate(t);
  p.rotate(Eigen::AngleAxisd(angle, axis.normalized()));
  return p;
}

class TempDir {
 public:
  TempDir() : dir_(fs::temp_directory_path() / ("chs_test_mesh_sdf_" + std::to_string(getpid()))) {
    fs::create_directories(dir_);
  }
  ~TempDir() { fs::remove_all(dir_); }
  fs::path operator/(const std::string& name) const { return dir_ / name; }

 private:
  fs::path dir_;
};

constexpr double kRadius = 0.1;

// Random point at a distance from the sphere surface drawn uniformly in [lo, hi].
Eigen::Vector3d nearSphere(std::mt19937& rng, double lo, double hi) {
  std::normal_distribution<double> gauss;
  std::uniform_real_distribution<double> depth(lo, hi);
  const Eigen::Vector3d dir = Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng)).normalized();
  return (kRadius + depth(rng)) * dir;
}

TEST(MeshSdfSurface, SphereMatchesTheAnalyticDistanceNearItsSurface) {
  const TriangleMesh sphere = icosphere(kRadius, 5);
  const MeshSdfSurface field(sphere);
  const double h = field.voxelSize();
  std::printf(
      "[figure] icosphere R = %.3f m, %d triangles: default voxel %.3f mm (L/128), "
      "band %.2f voxels out, %.2f in, %ld active voxels\n",
      kRadius, field.mesh().numTriangles(), 1e3 * h, field.exteriorBand() / h,
      field.interiorBand() / h, field.activeVoxels());
  EXPECT_NEAR(h, 2.0 * kRadius / 128.0, 1e-9);  // the documented default
  // The field is that of the facets, not of the sphere: tolerances add the facets' own
  // deviation to that of the field. Gap: facet depth + 0.05 voxel (float grid, trilinear
  // interpolation). Normal: a blend of face normals, each within the facet tilt of the radial
  // direction where it lies, and those faces lie within the reach of the gradient stencil (the
  // corner central differences of the cell reach 2 voxels along each axis, 2 sqrt(3) h along a
  // diagonal), over which the radial direction turns by up to 2 sqrt(3) h / R.
  const FacetBounds facets = facetBounds(sphere, kRadius);
  const double gap_tolerance = facets.depth + 0.05 * h;
  const double angle_tolerance =
      facets.tilt_deg + 2.0 * std::sqrt(3.0) * h / kRadius * 180.0 / M_PI;
  std::mt19937 rng(7);
  double max_gap_error = 0.0, max_angle = 0.0, curvature_sum = 0.0;
  const int n = 4000;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d x = nearSphere(rng, -2.0 * h, 2.0 * h);
    const SurfaceProjection p = field.project(x);
    max_gap_error = std::max(max_gap_error, std::abs(p.gap - (x.norm() - kRadius)));
    max_angle = std::max(max_angle, angleDeg(p.normal, x.normalized()));
    // Mean curvature of the level set through x: trace of the normal gradient = 2 / |x|. On
    // facets it is zero and at their edges concentrated, so only its average is the sphere's.
    curvature_sum += p.normal_gradient.trace() * x.norm();
    EXPECT_LT((p.normal_gradient - p.normal_gradient.transpose()).norm(), 1e-9);
    EXPECT_LT((p.normal_gradient * p.normal).norm(), 1e-9);
  }
  const double mean_curvature = curvature_sum / n;
  std::printf(
      "[figure] sphere within 2 voxels of its surface (%d points): max |gap error| = "
      "%.4f voxel (tolerance %.4f: facet depth %.4f + 0.05), max normal angle = %.3f deg "
      "(tolerance %.3f: facet tilt %.3f + stencil reach), mean trace(dn/dx) |x| = %.3f "
      "(sphere 2, tolerance 0.2)\n",
      n, max_gap_error / h, gap_tolerance / h, facets.depth / h, max_angle, angle_tolerance,
      facets.tilt_deg, mean_curvature);
  EXPECT_LT(max_gap_error, gap_tolerance);
  EXPECT_LT(max_angle, angle_tolerance);
  EXPECT_NEAR(mean_curvature, 2.0, 0.2);
}

TEST(MeshSdfSurface, NormalIsTheGradientOfTheGap) {
  const MeshSdfSurface field(icosphere(kRadius, 4));
  const double h = field.voxelSize(), e = 1e-3 * h;
  std::mt19937 rng(3);
  double max_error = 0.0;
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d x = nearSphere(rng, -1.5 * h, 1.5 * h);
    Eigen::Vector3d grad;
    for (int k = 0; k < 3; ++k) {
      Eigen::Vector3d d = Eigen::Vector3d::Zero();
      d[k] = e;
      grad[k] = (field.project(x + d).gap - field.project(x - d).gap) / (2 * e);
    }
    max_error = std::max(max_error, angleDeg(grad, field.project(x).normal));
  }
  // The gap is trilinear and the normal the interpolated central difference: they agree to
  // the second-order difference error, a few degrees at most on this coarser sphere.
  std::printf(
      "[figure] angle between the normal and the finite-difference gradient of the gap: "
      "max %.3f deg (tolerance 3)\n",
      max_error);
  EXPECT_LT(max_error, 3.0);
}

TEST(MeshSdfSurface, FarPointsArePositiveAndDeepPointsNegative) {
  const MeshSdfSurface field(icosphere(kRadius, 4));
  const double h = field.voxelSize();
  std::mt19937 rng(11);
  double worst_ratio = 1.0;  // reported gap / true distance, far outside
  for (int i = 0; i < 1000; ++i) {
    const Eigen::Vector3d x = nearSphere(rng, 4.0 * h, 10.0 * kRadius);
    const SurfaceProjection p = field.project(x);
    const double truth = x.norm() - kRadius;
    ASSERT_GE(p.gap, field.exteriorBand()) << "at distance " << truth;
    ASSERT_LE(p.gap, truth + 0.1 * h) << "a lower bound of the distance";
    ASSERT_NEAR(p.normal.norm(), 1.0, 1e-12);
    ASSERT_GT(p.normal.dot(x.normalized()), 0.0) << "points away from the body";
    worst_ratio = std::min(worst_ratio, p.gap / truth);
  }
  // The whole solid is in the band by default: the centre has the true depth.
  const SurfaceProjection centre = field.project(Eigen::Vector3d(0.01, 0.02, -0.015));
  const double depth_error =
      std::abs(centre.gap - (Eigen::Vector3d(0.01, 0.02, -0.015).norm() - kRadius));
  std::printf(
      "[figure] far outside (4 voxels to 10 R): smallest gap / distance = %.3f (positive "
      "required); point near the centre: depth error %.4f voxel (tolerance 0.1)\n",
      worst_ratio, depth_error / h);
  EXPECT_LT(depth_error, 0.1 * h);
  // A bounded interior band clamps deeper points to -band, still inside and pointing out.
  MeshSdfResolution thin;
  thin.interior_band = 3.0 * h;
  const MeshSdfSurface shallow(icosphere(kRadius, 4), thin);
  const SurfaceProjection deep = shallow.project(Eigen::Vector3d(0.02, 0.01, 0.0));
  EXPECT_NEAR(deep.gap, -shallow.interiorBand(), 1e-6);
  EXPECT_GT(deep.normal.dot(Eigen::Vector3d(0.02, 0.01, 0.0).normalized()), 0.99);
}

TEST(MeshSdfSurface, PosedFieldMatchesThePosedAnalyticSphere) {
  const TriangleMesh sphere = icosphere(kRadius, 5);
  auto field = std::make_shared<const MeshSdfSurface>(sphere);
  const double h = field->voxelSize();
  const FacetBounds facets = facetBounds(sphere, kRadius);  // tolerances as for the sphere above
  const double gap_tolerance = facets.depth + 0.05 * h;
  const double angle_tolerance =
      facets.tilt_deg + 2.0 * std::sqrt(3.0) * h / kRadius * 180.0 / M_PI;
  const Eigen::Vector3d centre_offset(0.0, 0.0, 0.0);
  const Eigen::Isometry3d t = pose({0.7, -0.4, 1.2}, 0.9, {1.0, -2.0, 0.5});
  const PosedSurface posed(field, t);
  const SphereSurface analytic(t * centre_offset, kRadius);
  std::mt19937 rng(5);
  double max_gap_error = 0.0, max_angle = 0.0;
  for (int i = 0; i < 1000; ++i) {
    const Eigen::Vector3d local = nearSphere(rng, -2.0 * h, 2.0 * h);
    const SurfaceProjection a = analytic.project(t * local), b = posed.project(t * local);
    max_gap_error = std::max(max_gap_error, std::abs(a.gap - b.gap));
    max_angle = std::max(max_angle, angleDeg(a.normal, b.normal));
    // The pose moves the query, not the field: bit for bit the local answer, rotated.
    const SurfaceProjection l = field->project(local);
    ASSERT_NEAR(l.gap, b.gap, 1e-12);
    ASSERT_LT((t.linear() * l.normal - b.normal).norm(), 1e-12);
  }
  std::printf(
      "[figure] posed sphere (turned 0.9 rad, moved 1.4 m): max |gap error| = %.4f voxel "
      "(tolerance %.4f), max normal angle = %.3f deg (tolerance %.3f)\n",
      max_gap_error / h, gap_tolerance / h, max_angle, angle_tolerance);
  EXPECT_LT(max_gap_error, gap_tolerance);
  EXPECT_LT(max_angle, angle_tolerance);
}

TEST(MeshSdfSurface, BoxMeshMatchesBoxSurfaceAwayFromEdges) {
  const Eigen::Vector3d size(0.3, 0.2, 0.1);
  // Read from an STL in millimetres: exercises the weld of per-facet corners and the scale.
  TempDir dir;
  writeStl(boxMesh(size), dir / "box_mm.stl", 1000.0);
  const auto field =
      MeshSdfSurface::fromFile((dir / "box_mm.stl").string(), Eigen::Vector3d::Constant(0.001));
  EXPECT_EQ(field->mesh().numVertices(), 8);
  const BoxSurface box(-0.5 * size, 0.5 * size);
  const double h = field->voxelSize();
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  double max_gap_error = 0.0, max_angle = 0.0;
  int count = 0;
  for (int i = 0; i < 3000; ++i) {
    // Points within 2 voxels of a face, at least 4 voxels from its edges.
    const Eigen::Vector3d x = (0.5 * size + Eigen::Vector3d::Constant(2.0 * h))
                                  .cwiseProduct(Eigen::Vector3d(unit(rng), unit(rng), unit(rng)));
    const Eigen::Vector3d from_face = (x.cwiseAbs() - 0.5 * size);
    int axis;
    const double d = from_face.maxCoeff(&axis);
    bool clear = std::abs(d) < 2.0 * h;
    for (int k = 0; k < 3; ++k)
      if (k != axis) clear = clear && from_face[k] < -4.0 * h;
    if (!clear) continue;
    ++count;
    const SurfaceProjection a = box.project(x), b = field->project(x);
    max_gap_error = std::max(max_gap_error, std::abs(a.gap - b.gap));
    max_angle = std::max(max_angle, angleDeg(a.normal, b.normal));
    EXPECT_LT(b.normal_gradient.norm(), 1e-3 / h);  // flat faces
  }
  ASSERT_GT(count, 100);
  // Flat faces: distances at the voxels are exact and trilinear interpolation of a linear field
  // is exact, so only float rounding remains.
  std::printf(
      "[figure] box mesh (from mm STL) vs BoxSurface, %d points near faces: max |gap "
      "error| = %.2e voxel (tolerance 1e-3), max normal angle = %.2e deg (tolerance "
      "0.01)\n",
      count, max_gap_error / h, max_angle);
  EXPECT_LT(max_gap_error, 1e-3 * h);
  EXPECT_LT(max_angle, 0.01);
}

void expectInputError(const std::function<void()>& f, const std::string& needle) {
  try {
    f();
    ADD_FAILURE() << "no InputError; expected one naming '" << needle << "'";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
  }
}

TEST(MeshSdfSurface, RefusesBadInput) {
  TempDir dir;
  expectInputError([&] { MeshSdfSurface::fromFile((dir / "nothing.obj").string()); },
                   "no such mesh file");
  TriangleMesh open = icosphere(kRadius, 2);
  open.triangles.pop_back();
  writeObj(open, dir / "open.obj");
  expectInputError([&] { MeshSdfSurface::fromFile((dir / "open.obj").string()); }, "not closed");
  writeObj(icosphere(kRadius, 2), dir / "sphere.obj");
  expectInputError(
      [&] {
        MeshSdfSurface::fromFile((dir / "sphere.obj").string(),
                                 Eigen::Vector3d::Constant(std::nan("")));
      },
      "scale must be positive and finite");
  expectInputError([&] { MeshSdfSurface m{TriangleMesh{}}; }, "empty");
  TriangleMesh nan = icosphere(kRadius, 1);
  nan.vertices[3].y() = std::nan("");
  expectInputError([&] { MeshSdfSurface m(nan); }, "vertex 3 has a non-finite coordinate");
  MeshSdfResolution bad;
  bad.voxel_size = std::nan("");
  expectInputError([&] { MeshSdfSurface m(icosphere(kRadius, 1), bad); }, "voxel size");
  const MeshSdfSurface sphere(icosphere(kRadius, 1));
  expectInputError([&] { sphere.project(Eigen::Vector3d(0.0, std::nan(""), 0.0)); }, "not finite");
}

TEST(ColliderShape, MeshBuildsItsFieldOnceForEveryPose) {
  TempDir dir;
  const TriangleMesh sphere = icosphere(kRadius, 4);
  writeObj(sphere, dir / "sphere_cm.obj", 100.0);  // written in centimetres
  ColliderShape shape;
  shape.type = parseColliderType("mesh");
  EXPECT_EQ(colliderTypeName(shape.type), "mesh");
  expectInputError([&] { shape.validate(); }, "needs a mesh file");
  shape.mesh_file = (dir / "missing.obj").string();
  expectInputError([&] { shape.meshField(); }, "no such mesh file");
  shape.mesh_file = (dir / "sphere_cm.obj").string();
  shape.mesh_scale = Eigen::Vector3d::Constant(0.01);
  shape.dimensions = {0.1};
  expectInputError([&] { shape.validate(); }, "needs 0 dimensions");
  shape.dimensions.clear();
  shape.mesh_scale.y() = -0.01;
  expectInputError([&] { shape.validate(); }, "scale must be positive");
  shape.mesh_scale.y() = 0.01;
  shape.offset.translate(Eigen::Vector3d(0.0, 0.0, 0.2));  // sphere centre 0.2 m above the frame
  EXPECT_NO_THROW(shape.validate());

  const long before = MeshSdfSurface::buildCount();
  const auto first = shape.meshField();
  EXPECT_EQ(MeshSdfSurface::buildCount(), before + 1);
  const ColliderShape copy = shape;  // as the node keeps it in its tracked colliders
  double max_gap_error = 0.0;
  for (int i = 0; i < 100; ++i) {
    const Eigen::Isometry3d world_from_frame =
        pose({0.01 * i, 0.5, -0.02 * i}, 0.03 * i, {0.0, 1.0, 1.0});
    const auto surface = (i % 2 ? copy : shape).makeSurface(world_from_frame);
    const Eigen::Vector3d centre = world_from_frame * Eigen::Vector3d(0.0, 0.0, 0.2);
    const Eigen::Vector3d x = centre + Eigen::Vector3d(0.0, 0.0, kRadius + 0.002);
    max_gap_error = std::max(max_gap_error, std::abs(surface->project(x).gap - 0.002));
  }
  EXPECT_EQ(MeshSdfSurface::buildCount(), before + 1) << "100 poses must reuse the one field";
  EXPECT_EQ(shape.meshField().get(), first.get());
  EXPECT_EQ(copy.meshField().get(), first.get());
  const double tolerance = facetBounds(sphere, kRadius).depth + 0.05 * first->voxelSize();
  std::printf(
      "[figure] mesh collider: %ld field build(s) for 100 poses of a shape and its copy; "
      "gap 2 mm above the posed sphere: max error %.2e m (tolerance facet depth + 0.05 "
      "voxel = %.2e m)\n",
      MeshSdfSurface::buildCount() - before, max_gap_error, tolerance);
  EXPECT_LT(max_gap_error, tolerance);
  shape.mesh_scale = Eigen::Vector3d::Constant(0.02);  // a new scale is a new field
  EXPECT_NE(shape.meshField().get(), first.get());
  EXPECT_EQ(MeshSdfSurface::buildCount(), before + 2);
}

TEST(MeshSdfSurface, BuildAndQueryTimesForInformation) {
  for (int levels : {4, 5})
    for (bool whole_interior : {true, false}) {
      const TriangleMesh mesh = icosphere(kRadius, levels);
      MeshSdfResolution resolution;
      if (!whole_interior) resolution.interior_band = 3.0 * 2.0 * kRadius / 128.0;
      const auto start = std::chrono::steady_clock::now();
      const MeshSdfSurface field(mesh, resolution);
      const auto built = std::chrono::steady_clock::now();
      std::mt19937 rng(1);
      double sum = 0.0;
      const int queries = 100000;
      for (int i = 0; i < queries; ++i) sum += field.project(nearSphere(rng, -0.003, 0.003)).gap;
      const auto queried = std::chrono::steady_clock::now();
      std::printf(
          "[figure] (information) %d triangles, voxel %.2f mm, interior band %s: build "
          "%.3f s, %ld active voxels, query %.2f us per point (mean gap %.2e m)\n",
          mesh.numTriangles(), 1e3 * field.voxelSize(), whole_interior ? "whole solid" : "3 voxels",
          std::chrono::duration<double>(built - start).count(), field.activeVoxels(),
          1e6 * std::chrono::duration<double>(queried - built).count() / queries, sum / queries);
      EXPECT_GT(field.activeVoxels(), 0);
    }
}

}  // namespace
}  // namespace chs
