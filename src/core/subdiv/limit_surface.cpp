#include "cloth_hair_sim/core/subdiv/limit_surface.h"

#include <algorithm>
#include <map>
#include <string>
#include <utility>

#include <opensubdiv/bfr/refinerSurfaceFactory.h>
#include <opensubdiv/bfr/surface.h>

#include "catmark_refiner.h"
#include "cloth_hair_sim/core/common/input_error.h"

namespace chs {

namespace Bfr = OpenSubdiv::Bfr;

struct LimitSurface::Faces {
  std::vector<std::array<int, 4>> quads;
  int num_control_points = 0;
  std::vector<Bfr::Surface<double>> surfaces;  // one per quad, immutable after construction
};

LimitSurface::LimitSurface(const QuadMesh& control, int extraordinary_level) {
  if (extraordinary_level < 1 || extraordinary_level > 10)
    throw InputError("limit surface: extraordinary_level " + std::to_string(extraordinary_level) +
                     " is outside [1, 10]");
  std::vector<int> sizes(control.quads.size(), 4), corners;
  corners.reserve(4 * control.quads.size());
  for (const auto& q : control.quads) corners.insert(corners.end(), q.begin(), q.end());
  const auto refiner = makeCatmarkRefiner(control.numVertices(), sizes, corners);

  // Bfr refines irregular features on infinitely sharp edges (our boundaries) to the "sharp"
  // depth and the others to the "smooth" depth: one depth for both keeps the exact region the
  // same at boundary and interior extraordinary vertices.
  Bfr::SurfaceFactory::Options options;
  options.SetApproxLevelSmooth(extraordinary_level).SetApproxLevelSharp(extraordinary_level);
  const Bfr::RefinerSurfaceFactory<> factory(*refiner, options);

  auto faces = std::make_unique<Faces>();
  faces->quads = control.quads;
  faces->num_control_points = control.numVertices();
  faces->surfaces.resize(control.quads.size());
  for (int f = 0; f < control.numQuads(); ++f)
    if (!factory.InitVertexSurface<double>(f, &faces->surfaces[f]))
      throw InputError("limit surface: OpenSubdiv found no limit surface for quad " +
                       std::to_string(f));
  faces_ = std::move(faces);
}

LimitSurface::~LimitSurface() = default;
LimitSurface::LimitSurface(LimitSurface&&) noexcept = default;
LimitSurface& LimitSurface::operator=(LimitSurface&&) noexcept = default;

int LimitSurface::numFaces() const {
  return static_cast<int>(faces_->quads.size());
}
int LimitSurface::numControlPoints() const {
  return faces_->num_control_points;
}

bool LimitSurface::isRegular(int face) const {
  if (face < 0 || face >= numFaces())
    throw InputError("limit surface: face " + std::to_string(face) + " out of range [0, " +
                     std::to_string(numFaces()) + ")");
  return faces_->surfaces[face].IsRegular();
}

SurfaceStencil LimitSurface::stencil(int face, double u, double v) const {
  if (face < 0 || face >= numFaces())
    throw InputError("limit surface: face " + std::to_string(face) + " out of range [0, " +
                     std::to_string(numFaces()) + ")");
  if (!(u >= 0.0 && u <= 1.0 && v >= 0.0 && v <= 1.0))
    throw InputError("limit surface: (u, v) = (" + std::to_string(u) + ", " + std::to_string(v) +
                     ") of face " + std::to_string(face) + " is outside [0, 1]^2");
  const Bfr::Surface<double>& surface = faces_->surfaces[face];
  const int n = surface.GetNumControlPoints();
  std::vector<int> index(n);
  surface.GetControlPointIndices(index.data());
  std::vector<double> w(n), du(n), dv(n), duu(n), duv(n), dvv(n);
  const double uv[2] = {u, v};
  surface.EvaluateStencil(uv, w.data(), du.data(), dv.data(), duu.data(), duv.data(), dvv.data());

  // The 4x4 ring of a patch can wrap onto itself on small closed meshes (a control point
  // then appears twice); the shell assembly wants one entry per control point.
  std::map<int, int> slot;
  SurfaceStencil s;
  for (int k = 0; k < n; ++k) {
    const auto [it, is_new] = slot.emplace(index[k], s.size());
    if (is_new) {
      s.points.push_back(index[k]);
      s.w.push_back(w[k]);
      s.du.push_back(du[k]);
      s.dv.push_back(dv[k]);
      s.duu.push_back(duu[k]);
      s.duv.push_back(duv[k]);
      s.dvv.push_back(dvv[k]);
    } else {
      const int j = it->second;
      s.w[j] += w[k];
      s.du[j] += du[k];
      s.dv[j] += dv[k];
      s.duu[j] += duu[k];
      s.duv[j] += duv[k];
      s.dvv[j] += dvv[k];
    }
  }
  return s;
}

LimitTessellation LimitSurface::tessellate(int segments_per_edge, int num_faces) const {
  const int n = segments_per_edge;
  if (n < 1)
    throw InputError("limit surface: tessellation needs at least 1 segment per edge, got " +
                     std::to_string(n));
  if (num_faces < 0 || num_faces > numFaces())
    throw InputError("limit surface: cannot tessellate " + std::to_string(num_faces) + " of " +
                     std::to_string(numFaces()) + " faces");
  LimitTessellation t;
  // Samples shared between faces: corners by control vertex, edge samples by the undirected
  // edge and their step counted from its lower-numbered end.
  std::map<int, int> corner_sample;
  std::map<std::array<int, 3>, int> edge_sample;
  const auto add = [&t, n](int face, int i, int j) {
    t.samples.push_back({face, static_cast<double>(i) / n, static_cast<double>(j) / n});
    return static_cast<int>(t.samples.size()) - 1;
  };

  for (int f = 0; f < num_faces; ++f) {
    const auto& c = faces_->quads[f];
    // Grid point (i, j) of this face in the corner / edge frame: corner k sits at
    // (i, j) = n * corner_uv[k]; edge k runs from corner k to corner k + 1.
    static constexpr int corner_uv[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    const auto sampleAt = [&](int i, int j) {
      for (int k = 0; k < 4; ++k)
        if (i == n * corner_uv[k][0] && j == n * corner_uv[k][1]) {
          const auto [it, is_new] = corner_sample.emplace(c[k], 0);
          if (is_new) it->second = add(f, i, j);
          return it->second;
        }
      // Step along edge k from corner k, 1..n-1.
      int k = -1, step = 0;
      if (j == 0) k = 0, step = i;
      if (i == n) k = 1, step = j;
      if (j == n) k = 2, step = n - i;
      if (i == 0) k = 3, step = n - j;
      if (k < 0) return add(f, i, j);
      const int a = c[k], b = c[(k + 1) % 4];
      const std::array<int, 3> key = {std::min(a, b), std::max(a, b), a < b ? step : n - step};
      const auto [it, is_new] = edge_sample.emplace(key, 0);
      if (is_new) it->second = add(f, i, j);
      return it->second;
    };
    std::vector<int> grid((n + 1) * (n + 1));
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) grid[j * (n + 1) + i] = sampleAt(i, j);
    // Counter-clockwise in (u, v), hence oriented like the quad.
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const int s00 = grid[j * (n + 1) + i], s10 = grid[j * (n + 1) + i + 1];
        const int s01 = grid[(j + 1) * (n + 1) + i], s11 = grid[(j + 1) * (n + 1) + i + 1];
        t.triangles.push_back({s00, s10, s11});
        t.triangles.push_back({s00, s11, s01});
      }
  }
  return t;
}

std::vector<SurfaceStencil> vertexStencils(const QuadMesh& mesh, const LimitSurface& surface) {
  static constexpr double kCornerUV[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  std::vector<SurfaceStencil> s(mesh.numVertices());
  std::vector<char> done(mesh.numVertices(), 0);
  for (int f = 0; f < mesh.numQuads(); ++f)
    for (int k = 0; k < 4; ++k) {
      const int v = mesh.quads[f][k];
      if (done[v]) continue;
      s[v] = surface.stencil(f, kCornerUV[k][0], kCornerUV[k][1]);
      done[v] = 1;
    }
  return s;
}

std::vector<Eigen::Vector3d> evaluate(const std::vector<SurfaceStencil>& stencils,
                                      const std::vector<Eigen::Vector3d>& control_positions) {
  std::vector<Eigen::Vector3d> x;
  x.reserve(stencils.size());
  for (const auto& s : stencils) {
    for (int p : s.points)
      if (p < 0 || p >= static_cast<int>(control_positions.size()))
        throw InputError("evaluate: stencil names control point " + std::to_string(p) + ", but " +
                         std::to_string(control_positions.size()) + " were given");
    x.push_back(s.position(control_positions));
  }
  return x;
}

}  // namespace chs
