#include "cloth_hair_sim/core/mesh/grid_generators.h"

#include <cmath>
#include <functional>
#include <limits>
#include <string>

#include <Eigen/Geometry>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/mesh/mesh_weld.h"

namespace chs {

namespace {

// Appends an nu x nv block whose vertex (i, j) lies at map(i / nu, j / nv); quads are numbered
// so that their normal points to +z whatever the orientation of the map.
void appendBlock(QuadMesh& mesh, int nu, int nv,
                 const std::function<Eigen::Vector3d(double, double)>& map) {
  const int base = mesh.numVertices();
  for (int j = 0; j <= nv; ++j)
    for (int i = 0; i <= nu; ++i)
      mesh.vertices.push_back(map(static_cast<double>(i) / nu, static_cast<double>(j) / nv));
  auto id = [&](int i, int j) { return base + j * (nu + 1) + i; };
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      std::array<int, 4> q{id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)};
      const auto& p = mesh.vertices;
      if ((p[q[2]] - p[q[0]]).cross(p[q[3]] - p[q[1]]).z() < 0.0) std::swap(q[1], q[3]);
      mesh.quads.push_back(q);
    }
}

}  // namespace

QuadMesh makeRectangleMesh(double lx, double ly, int nx, int ny, const Eigen::Vector3d& centre) {
  if (!(lx > 0.0) || !(ly > 0.0) || !std::isfinite(lx) || !std::isfinite(ly))
    throw InputError("rectangle: size must be positive, got " + std::to_string(lx) + " x " +
                     std::to_string(ly));
  if (nx < 1 || ny < 1)
    throw InputError("rectangle: needs at least one cell each way, got " + std::to_string(nx) +
                     " x " + std::to_string(ny));
  if (!centre.allFinite()) throw InputError("rectangle: centre must be finite");
  QuadMesh mesh;
  appendBlock(mesh, nx, ny, [&](double u, double v) {
    return Eigen::Vector3d(centre.x() + (u - 0.5) * lx, centre.y() + (v - 0.5) * ly, centre.z());
  });
  return mesh;
}

namespace {

// O-grid with k cells radially in each ring block and m = cells_across - 2k along each side.
QuadMesh discBlocks(double radius, int cells_across, int k, const Eigen::Vector3d& centre) {
  const int m = cells_across - 2 * k;
  const double a = 0.525 * radius;  // half-side of the central square
  const Eigen::Vector2d c = centre.head<2>();
  const double z = centre.z();
  // Inner boundary of ring block `side` (0: +x, then counter-clockwise), t in [-1, 1]: the
  // square's side bulged halfway towards the circle through the square's corners. The bulge
  // widens the ring blocks' corner cells, which a straight square leaves too small.
  const double bulge = 0.5;
  auto rotate = [](int side, const Eigen::Vector2d& p) {
    return Eigen::Vector2d(Eigen::Rotation2Dd(side * M_PI / 2) * p);
  };
  auto inner = [&](int side, double t) {
    const Eigen::Vector2d square(a, a * t);
    const Eigen::Vector2d arc =
        std::sqrt(2.0) * a * Eigen::Vector2d(std::cos(t * M_PI / 4), std::sin(t * M_PI / 4));
    return rotate(side, (1 - bulge) * square + bulge * arc);
  };
  auto at = [&](const Eigen::Vector2d& p) {
    return Eigen::Vector3d(c.x() + p.x(), c.y() + p.y(), z);
  };
  QuadMesh mesh;
  // Central block: Coons patch of the four bulged sides.
  appendBlock(mesh, m, m, [&](double u, double v) {
    const Eigen::Vector2d bottom = inner(3, 2 * u - 1), top = inner(1, 1 - 2 * u);
    const Eigen::Vector2d left = inner(2, 1 - 2 * v), right = inner(0, 2 * v - 1);
    const Eigen::Vector2d bilinear = a * Eigen::Vector2d((1 - u) * -1 + u, (1 - v) * -1 + v);
    return at((1 - v) * bottom + v * top + (1 - u) * left + u * right - bilinear);
  });
  // Ring blocks: straight lines from the bulged side (uniform in t) to the arc (uniform in
  // angle).
  for (int side = 0; side < 4; ++side)
    appendBlock(mesh, m, k, [&](double u, double s) {
      const double t = 2 * u - 1;
      const Eigen::Vector2d outer =
          rotate(side, radius * Eigen::Vector2d(std::cos(t * M_PI / 4), std::sin(t * M_PI / 4)));
      return at((1 - s) * inner(side, t) + s * outer);
    });
  weldVertices(mesh, 1e-9 * radius);
  return mesh;
}

double edgeRatio(const QuadMesh& mesh) {
  double lo = std::numeric_limits<double>::infinity(), hi = 0.0;
  for (const auto& q : mesh.quads)
    for (int k = 0; k < 4; ++k) {
      const double e = (mesh.vertices[q[(k + 1) % 4]] - mesh.vertices[q[k]]).norm();
      lo = std::min(lo, e), hi = std::max(hi, e);
    }
  return hi / lo;
}

}  // namespace

QuadMesh makeDiscMesh(double radius, int cells_across, const Eigen::Vector3d& centre) {
  if (!(radius > 0.0) || !std::isfinite(radius))
    throw InputError("disc: radius must be positive, got " + std::to_string(radius));
  if (cells_across < 3)
    throw InputError("disc: needs at least 3 cells across, got " + std::to_string(cells_across));
  if (!centre.allFinite()) throw InputError("disc: centre must be finite");
  // The split between square and ring that makes the edges most uniform; the square's size
  // (0.525 R) and its bulge were tuned the same way (longest / shortest edge 1.5-1.7).
  QuadMesh best;
  double best_ratio = std::numeric_limits<double>::infinity();
  for (int k = 1; 2 * k < cells_across; ++k) {
    QuadMesh mesh = discBlocks(radius, cells_across, k, centre);
    const double ratio = edgeRatio(mesh);
    if (ratio < best_ratio) best_ratio = ratio, best = std::move(mesh);
  }
  return best;
}

}  // namespace chs
