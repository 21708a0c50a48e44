#include "cloth_hair_sim/core/contact/mesh_sdf_surface.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <sstream>
#include <vector>

#include <openvdb/openvdb.h>
#include <openvdb/tools/MeshToVolume.h>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/io/triangle_mesh_reader.h"

namespace chs {

namespace {
std::atomic<long> builds{0};
}  // namespace

struct MeshSdfSurface::Grid {
  openvdb::FloatGrid::Ptr sdf;
};

MeshSdfSurface::MeshSdfSurface(const TriangleMesh& mesh, const MeshSdfResolution& resolution)
    : mesh_(mesh) {
  checkClosedSurface(mesh_);
  for (double v : {resolution.voxel_size, resolution.exterior_band, resolution.interior_band})
    if (!(v >= 0.0) || !std::isfinite(v))
      throw InputError("mesh distance field: voxel size and band widths must be >= 0 and finite");
  for (const auto& p : mesh_.vertices) bounds_.extend(p);
  const Eigen::Vector3d sides = bounds_.sizes();
  const double longest = sides.maxCoeff(), shortest = sides.minCoeff();
  if (!(longest > 0.0)) throw InputError("mesh distance field: the mesh has no extent");
  voxel_ = resolution.voxel_size > 0.0
               ? resolution.voxel_size
               : std::max(longest / 512.0, std::min(longest / 128.0, shortest / 4.0));
  exterior_ = resolution.exterior_band > 0.0 ? resolution.exterior_band : 3.0 * voxel_;
  // No point of the solid lies deeper than half its shortest side: one voxel more fills it.
  interior_ = resolution.interior_band > 0.0 ? resolution.interior_band : 0.5 * shortest + voxel_;
  // OpenVDB needs a band of at least one voxel to find the surface.
  exterior_ = std::max(exterior_, voxel_);
  interior_ = std::max(interior_, voxel_);

  std::vector<openvdb::Vec3s> points;
  points.reserve(mesh_.vertices.size());
  for (const auto& p : mesh_.vertices)
    points.emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()),
                        static_cast<float>(p.z()));
  std::vector<openvdb::Vec3I> triangles;
  triangles.reserve(mesh_.triangles.size());
  for (const auto& t : mesh_.triangles)
    triangles.emplace_back(static_cast<openvdb::Index32>(t[0]), static_cast<openvdb::Index32>(t[1]),
                           static_cast<openvdb::Index32>(t[2]));
  // Voxel (i, j, k) sits at (i, j, k) * voxel in the mesh frame.
  const openvdb::math::Transform::Ptr xform =
      openvdb::math::Transform::createLinearTransform(voxel_);
  auto grid = std::make_unique<Grid>();
  grid->sdf = openvdb::tools::meshToSignedDistanceField<openvdb::FloatGrid>(
      *xform, points, triangles, {}, static_cast<float>(exterior_ / voxel_),
      static_cast<float>(interior_ / voxel_));
  grid_ = std::move(grid);
  ++builds;
}

MeshSdfSurface::~MeshSdfSurface() = default;

std::shared_ptr<const MeshSdfSurface> MeshSdfSurface::fromFile(
    const std::string& path, const Eigen::Vector3d& scale, const MeshSdfResolution& resolution,
    const std::vector<std::string>& parts) {
  const TriangleMesh mesh = readTriangleMesh(path, scale, parts);
  try {
    return std::make_shared<const MeshSdfSurface>(mesh, resolution);
  } catch (const InputError& e) {
    throw InputError(path + ": " + e.what());
  }
}

long MeshSdfSurface::activeVoxels() const {
  return static_cast<long>(grid_->sdf->activeVoxelCount());
}

long MeshSdfSurface::buildCount() {
  return builds.load();
}

SurfaceProjection MeshSdfSurface::boundedByBox(const Eigen::Vector3d& x,
                                               SurfaceProjection p) const {
  const Eigen::Vector3d away = x - x.cwiseMax(bounds_.min()).cwiseMin(bounds_.max());
  const double box_distance = away.norm();
  if (box_distance > 0.0 && box_distance >= p.gap) {
    p.gap = box_distance;
    p.normal = away / box_distance;
    p.normal_gradient.setZero();
  }
  return p;
}

Eigen::Vector3d MeshSdfSurface::awayFromCentre(const Eigen::Vector3d& x) const {
  const Eigen::Vector3d away = x - bounds_.center();
  return away.norm() > 0.0 ? Eigen::Vector3d(away.normalized()) : Eigen::Vector3d::UnitZ();
}

SurfaceProjection MeshSdfSurface::project(const Eigen::Vector3d& x) const {
  if (!x.allFinite()) throw InputError("mesh distance field: query point is not finite");
  SurfaceProjection p;
  // Well beyond the box every voxel around x is outside the band: skip the grid (this also
  // keeps voxel indices of far points within int range).
  const Eigen::Vector3d beyond_box =
      (bounds_.min() - x).cwiseMax(x - bounds_.max()).cwiseMax(Eigen::Vector3d::Zero());
  if (beyond_box.norm() > exterior_ + 2.0 * voxel_) {
    p.gap = exterior_;
    return boundedByBox(x, p);
  }
  // One unregistered accessor per query: const reads of the tree are thread-safe, and an
  // accessor registered with the tree would serialise the threads on its registry.
  openvdb::tree::ValueAccessor<const openvdb::FloatTree, false> acc(grid_->sdf->tree());
  const Eigen::Vector3d u = x / voxel_;  // index-space position
  const Eigen::Vector3d base = u.array().floor();
  const Eigen::Vector3d f = u - base;
  const int i0 = static_cast<int>(base.x()) - 1, j0 = static_cast<int>(base.y()) - 1,
            k0 = static_cast<int>(base.z()) - 1;
  // The 4^3 stencil of the cell's 8 corners and their neighbours. A voxel outside the band holds
  // only the clamped background; read it as the band's edge on its side, which keeps the field
  // continuous and monotone into the band.
  float v[4][4][4];
  bool any_active = false;
  for (int a = 0; a < 4; ++a)
    for (int b = 0; b < 4; ++b)
      for (int c = 0; c < 4; ++c) {
        float value = 0.0f;
        const bool on = acc.probeValue(openvdb::Coord(i0 + a, j0 + b, k0 + c), value);
        if (!on) value = static_cast<float>(value > 0.0f ? exterior_ : -interior_);
        const bool corner = a >= 1 && a <= 2 && b >= 1 && b <= 2 && c >= 1 && c <= 2;
        any_active = any_active || (on && corner);
        v[a][b][c] = value;
      }
  if (!any_active) {
    p.gap = v[1][1][1] > 0.0f ? exterior_ : -interior_;
    p.normal = awayFromCentre(x);
    return boundedByBox(x, p);
  }

  Eigen::Vector3d g = Eigen::Vector3d::Zero();
  Eigen::Matrix3d jacobian = Eigen::Matrix3d::Zero();  // d g / d x
  for (int a = 0; a < 2; ++a)
    for (int b = 0; b < 2; ++b)
      for (int c = 0; c < 2; ++c) {
        const int ia = a + 1, ib = b + 1, ic = c + 1;
        const Eigen::Vector3d w(a ? f.x() : 1.0 - f.x(), b ? f.y() : 1.0 - f.y(),
                                c ? f.z() : 1.0 - f.z());
        const double weight = w.x() * w.y() * w.z();
        const Eigen::Vector3d dweight =
            Eigen::Vector3d((a ? 1.0 : -1.0) * w.y() * w.z(), (b ? 1.0 : -1.0) * w.x() * w.z(),
                            (c ? 1.0 : -1.0) * w.x() * w.y()) /
            voxel_;
        // Central-difference gradient of the distance at this corner.
        const Eigen::Vector3d corner_gradient =
            Eigen::Vector3d(v[ia + 1][ib][ic] - v[ia - 1][ib][ic],
                            v[ia][ib + 1][ic] - v[ia][ib - 1][ic],
                            v[ia][ib][ic + 1] - v[ia][ib][ic - 1]) /
            (2.0 * voxel_);
        p.gap += weight * v[ia][ib][ic];
        g += weight * corner_gradient;
        jacobian += corner_gradient * dweight.transpose();
      }
  const double g_norm = g.norm();
  // A distance gradient has unit length; one far shorter is a ridge of the distance (the medial
  // axis) or the flattened clamp at the band edge, where it gives no direction.
  if (!(g_norm > 1e-3)) {
    p.normal = awayFromCentre(x);
    return boundedByBox(x, p);
  }
  p.normal = g / g_norm;
  const Eigen::Matrix3d tangent = Eigen::Matrix3d::Identity() - p.normal * p.normal.transpose();
  // d(g/|g|)/dx = (I - n n^T) J / |g|; symmetrised within the tangent plane, as the Hessian of a
  // distance is symmetric with n in its null space.
  p.normal_gradient = tangent * (0.5 * (jacobian + jacobian.transpose())) * tangent / g_norm;
  return boundedByBox(x, p);
}

std::string MeshSdfSurface::describe() const {
  std::ostringstream s;
  s << "mesh distance field of " << mesh_.numTriangles() << " triangles, voxel " << voxel_
    << " m, band " << exterior_ << " m out / " << interior_ << " m in, box ["
    << bounds_.min().transpose() << "] - [" << bounds_.max().transpose() << "]";
  return s.str();
}

}  // namespace chs
