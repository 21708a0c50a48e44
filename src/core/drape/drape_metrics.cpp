#include "cloth_hair_sim/core/drape/drape_metrics.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>

#include <Eigen/Geometry>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/io/collider_spec.h"
#include "cloth_hair_sim/core/mesh/boundary_edges.h"

namespace chs {
namespace {

constexpr double kPi = 3.14159265358979323846;

// The two triangles each quad is split into (the same split for area and shadow).
constexpr std::array<std::array<int, 3>, 2> kQuadTriangles = {{{0, 1, 2}, {0, 2, 3}}};

double cross2(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

void checkPositions(const QuadMesh& mesh, const std::vector<Eigen::Vector3d>& positions) {
  if (positions.size() != mesh.vertices.size())
    throw InputError("drape metrics: " + std::to_string(positions.size()) + " positions for " +
                     std::to_string(mesh.vertices.size()) + " mesh vertices");
  for (const auto& q : mesh.quads)
    for (int v : q)
      if (v < 0 || v >= mesh.numVertices())
        throw InputError("drape metrics: quad vertex " + std::to_string(v) + " out of range");
}

// Circular moving average over 2 half + 1 samples.
std::vector<double> circularMean(const std::vector<double>& s, int half) {
  const int n = static_cast<int>(s.size());
  if (half <= 0 || n == 0) return s;
  std::vector<double> out(n);
  for (int i = 0; i < n; ++i) {
    double sum = 0.0;
    for (int k = -half; k <= half; ++k) sum += s[((i + k) % n + n) % n];
    out[i] = sum / (2 * half + 1);
  }
  return out;
}

}  // namespace

DrapeSupport supportOf(const ColliderSpec& c) {
  DrapeSupport s;
  switch (c.type) {
    case ColliderSpec::Type::kCylinder:
      s.axis_xy = c.axis_xy;
      s.area = kPi * c.radius * c.radius;
      return s;
    case ColliderSpec::Type::kBox:
      s.axis_xy = 0.5 * (c.lo + c.hi).head<2>();
      s.area = (c.hi.x() - c.lo.x()) * (c.hi.y() - c.lo.y());
      return s;
    default:
      throw InputError("drape metrics: a " + c.label + " has no top face to drape from");
  }
}

double surfaceArea(const QuadMesh& mesh, const std::vector<Eigen::Vector3d>& positions) {
  checkPositions(mesh, positions);
  double area = 0.0;
  for (const auto& q : mesh.quads)
    for (const auto& t : kQuadTriangles)
      area += 0.5 * (positions[q[t[1]]] - positions[q[t[0]]])
                        .cross(positions[q[t[2]]] - positions[q[t[0]]])
                        .norm();
  return area;
}

double shadowArea(const QuadMesh& mesh, const std::vector<Eigen::Vector3d>& positions,
                  int raster_cells, double* error_bound) {
  checkPositions(mesh, positions);
  if (raster_cells < 16) throw InputError("drape metrics: raster_cells must be >= 16");
  if (mesh.quads.empty()) return 0.0;
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::max());
  Eigen::Vector2d hi = -lo;
  for (const auto& q : mesh.quads)
    for (int v : q) {
      lo = lo.cwiseMin(positions[v].head<2>());
      hi = hi.cwiseMax(positions[v].head<2>());
    }
  const int n = raster_cells;
  const double h = std::max((hi - lo).maxCoeff(), 1e-12) / n;
  std::vector<unsigned char> covered(static_cast<size_t>(n) * n, 0);
  auto cell = [&](double x, double o) { return (x - o) / h - 0.5; };  // centre i at o + (i+.5)h
  for (const auto& q : mesh.quads)
    for (const auto& t : kQuadTriangles) {
      Eigen::Vector2d p[3];
      for (int k = 0; k < 3; ++k) p[k] = positions[q[t[k]]].head<2>();
      double twice_area = cross2(p[1] - p[0], p[2] - p[0]);
      if (twice_area == 0.0) continue;  // seen edge-on: no area
      if (twice_area < 0.0) std::swap(p[1], p[2]);
      const Eigen::Vector2d tlo = p[0].cwiseMin(p[1]).cwiseMin(p[2]);
      const Eigen::Vector2d thi = p[0].cwiseMax(p[1]).cwiseMax(p[2]);
      const int i0 = std::max(0, static_cast<int>(std::ceil(cell(tlo.x(), lo.x()))));
      const int i1 = std::min(n - 1, static_cast<int>(std::floor(cell(thi.x(), lo.x()))));
      const int j0 = std::max(0, static_cast<int>(std::ceil(cell(tlo.y(), lo.y()))));
      const int j1 = std::min(n - 1, static_cast<int>(std::floor(cell(thi.y(), lo.y()))));
      for (int j = j0; j <= j1; ++j) {
        const double y = lo.y() + (j + 0.5) * h;
        for (int i = i0; i <= i1; ++i) {
          const Eigen::Vector2d c(lo.x() + (i + 0.5) * h, y);
          if (cross2(p[1] - p[0], c - p[0]) >= 0.0 && cross2(p[2] - p[1], c - p[1]) >= 0.0 &&
              cross2(p[0] - p[2], c - p[2]) >= 0.0)
            covered[static_cast<size_t>(j) * n + i] = 1;
        }
      }
    }
  size_t count = 0;
  for (unsigned char c : covered) count += c;
  if (error_bound) {
    // The outline is taken as the projected boundary; folds seen from above can only shorten it.
    double perimeter = 0.0;
    for (const auto& [a, b] : boundaryEdges(mesh))
      perimeter += (positions[a] - positions[b]).head<2>().norm();
    *error_bound = std::sqrt(2.0) * perimeter * h;
  }
  return static_cast<double>(count) * h * h;
}

std::vector<int> periodicPeaks(const std::vector<double>& s, double min_prominence) {
  const int n = static_cast<int>(s.size());
  std::vector<int> peaks;
  if (n < 3) return peaks;
  auto at = [&](int i) { return s[((i % n) + n) % n]; };
  const double global_min = *std::min_element(s.begin(), s.end());
  for (int i = 0; i < n; ++i) {
    // Strictly above the left neighbour, not below the right one: a plateau counts once.
    if (!(s[i] > at(i - 1) && s[i] >= at(i + 1))) continue;
    // Walk each way until a higher sample; the lowest point on the way is that side's saddle.
    double saddle[2];
    bool higher[2] = {false, false};
    for (int side = 0; side < 2; ++side) {
      const int dir = side == 0 ? -1 : 1;
      double lowest = s[i];
      for (int k = 1; k < n; ++k) {
        const double v = at(i + dir * k);
        if (v > s[i]) {
          higher[side] = true;
          break;
        }
        lowest = std::min(lowest, v);
      }
      saddle[side] = lowest;
    }
    // No higher peak anywhere: the highest peak, whose prominence is its height above the minimum.
    const double base = higher[0] || higher[1] ? std::max(saddle[0], saddle[1]) : global_min;
    if (s[i] - base >= min_prominence) peaks.push_back(i);
  }
  return peaks;
}

DrapeMetrics measureDrape(const QuadMesh& mesh, const std::vector<Eigen::Vector3d>& positions,
                          const DrapeSupport& support, const DrapeMetricsSettings& settings) {
  checkPositions(mesh, positions);
  if (settings.angular_bins < 8) throw InputError("drape metrics: angular_bins must be >= 8");
  DrapeMetrics m;
  m.flat_area = surfaceArea(mesh, mesh.vertices);
  m.support_area = support.area;
  m.shadow_area = shadowArea(mesh, positions, settings.raster_cells, &m.shadow_area_error_bound);
  m.drape_coefficient = (m.shadow_area - m.support_area) / (m.flat_area - m.support_area);

  m.lowest_z = std::numeric_limits<double>::max();
  m.highest_z = std::numeric_limits<double>::lowest();
  for (const auto& p : positions) {
    m.lowest_z = std::min(m.lowest_z, p.z());
    m.highest_z = std::max(m.highest_z, p.z());
    m.max_radius = std::max(m.max_radius, (p.head<2>() - support.axis_xy).norm());
  }

  // Outline r(theta): the boundary edges, sampled finely enough that every bin they sweep gets a
  // sample, binned by polar angle keeping the largest radius (the outer envelope seen from above,
  // single-valued even where a fold's edge doubles back in angle).
  const int nb = settings.angular_bins;
  const double bin = 2.0 * kPi / nb;
  std::vector<double> r(nb, -1.0);
  auto polar = [&](const Eigen::Vector3d& p) {
    const Eigen::Vector2d d = p.head<2>() - support.axis_xy;
    return std::make_pair(std::atan2(d.y(), d.x()), d.norm());
  };
  for (const auto& [a, b] : boundaryEdges(mesh)) {
    const double ta = polar(positions[a]).first, tb = polar(positions[b]).first;
    double sweep = std::abs(tb - ta);
    sweep = std::min(sweep, 2.0 * kPi - sweep);
    const int pieces = std::min(10000, 1 + static_cast<int>(std::ceil(2.0 * sweep / bin)));
    for (int k = 0; k <= pieces; ++k) {
      const double t = static_cast<double>(k) / pieces;
      const auto [theta, radius] = polar((1.0 - t) * positions[a] + t * positions[b]);
      const int i = std::clamp(static_cast<int>(std::floor((theta + kPi) / bin)), 0, nb - 1);
      r[i] = std::max(r[i], radius);
    }
  }
  // Bins no edge reached (only with a very coarse boundary): interpolate between neighbours.
  std::vector<int> filled;
  for (int i = 0; i < nb; ++i)
    if (r[i] >= 0.0) filled.push_back(i);
  if (filled.empty()) return m;
  for (size_t k = 0; k < filled.size(); ++k) {
    const int i0 = filled[k], i1 = filled[(k + 1) % filled.size()];
    const int gap = ((i1 - i0) % nb + nb) % nb;
    for (int g = 1; g < gap; ++g)
      r[(i0 + g) % nb] = r[i0] + (r[i1] - r[i0]) * g / static_cast<double>(gap);
  }
  const int half = static_cast<int>(std::lround(0.5 * settings.smoothing_deg * kPi / 180.0 / bin));
  m.outline_radius = circularMean(circularMean(r, half), half);
  const auto& s = m.outline_radius;
  m.min_outline_radius = *std::min_element(s.begin(), s.end());
  m.max_outline_radius = *std::max_element(s.begin(), s.end());
  for (double v : s) m.mean_outline_radius += v / nb;
  const double prominence =
      std::max(settings.min_prominence, settings.relative_prominence * m.mean_outline_radius);
  for (int i : periodicPeaks(s, prominence)) m.fold_angles.push_back(-kPi + (i + 0.5) * bin);
  m.folds = static_cast<int>(m.fold_angles.size());
  return m;
}

double maxPenetration(const std::vector<Eigen::Vector3d>& positions,
                      const RigidSurfaces& colliders) {
  double depth = 0.0;
  for (const auto& c : colliders)
    for (const auto& p : positions) depth = std::max(depth, -c->project(p).gap);
  return depth;
}

}  // namespace chs
