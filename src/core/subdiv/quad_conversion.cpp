#include "cloth_hair_sim/core/subdiv/quad_conversion.h"

#include <string>

#include <opensubdiv/far/primvarRefiner.h>

#include "catmark_refiner.h"
#include "cloth_hair_sim/core/common/input_error.h"

namespace chs {

namespace Far = OpenSubdiv::Far;

namespace {

// A position in the form OpenSubdiv's PrimvarRefiner combines.
struct Point {
  Eigen::Vector3d x;
  void Clear() { x.setZero(); }
  void AddWithWeight(const Point& src, double weight) { x += weight * src.x; }
};

}  // namespace

QuadMesh toQuadControlMesh(const PolygonMesh& mesh) {
  std::vector<int> sizes, corners;
  sizes.reserve(mesh.faces.size());
  for (const auto& f : mesh.faces) {
    sizes.push_back(static_cast<int>(f.size()));
    corners.insert(corners.end(), f.begin(), f.end());
  }
  const int nv = static_cast<int>(mesh.vertices.size());
  auto refiner = makeCatmarkRefiner(nv, sizes, corners);
  for (int v = 0; v < nv; ++v)
    if (!mesh.vertices[v].allFinite())
      throw InputError("polygon mesh: vertex " + std::to_string(v) +
                       " has a non-finite coordinate");

  bool all_quads = true;
  for (int n : sizes) all_quads = all_quads && n == 4;
  QuadMesh quads;
  if (all_quads) {
    quads.vertices = mesh.vertices;
    for (const auto& f : mesh.faces) quads.quads.push_back({f[0], f[1], f[2], f[3]});
    return quads;
  }

  refiner->RefineUniform(Far::TopologyRefiner::UniformOptions(1));
  const Far::TopologyLevel& fine = refiner->GetLevel(1);
  std::vector<Point> coarse_points(nv), fine_points(fine.GetNumVertices());
  for (int v = 0; v < nv; ++v) coarse_points[v].x = mesh.vertices[v];
  Far::PrimvarRefinerReal<double>(*refiner).Interpolate(1, coarse_points, fine_points);

  quads.vertices.reserve(fine_points.size());
  for (const auto& p : fine_points) quads.vertices.push_back(p.x);
  for (int f = 0; f < fine.GetNumFaces(); ++f) {
    const Far::ConstIndexArray c = fine.GetFaceVertices(f);
    quads.quads.push_back({c[0], c[1], c[2], c[3]});
  }
  return quads;
}

}  // namespace chs
