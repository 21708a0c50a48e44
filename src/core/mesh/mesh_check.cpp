#include "cloth_hair_sim/core/mesh/mesh_check.h"

#include <algorithm>
#include <map>
#include <sstream>
#include <string>
#include <utility>

#include <Eigen/Geometry>

#include "cloth_hair_sim/core/common/input_error.h"

namespace chs {

namespace {

// Area vector of a (possibly warped) quad: half the cross product of its diagonals.
Eigen::Vector3d areaVector(const QuadMesh& m, const std::array<int, 4>& q) {
  const auto& p = m.vertices;
  return 0.5 * (p[q[2]] - p[q[0]]).cross(p[q[3]] - p[q[1]]);
}

std::string edgeName(int a, int b) {
  return "edge " + std::to_string(a) + "-" + std::to_string(b);
}

// One use of an undirected edge by a quad; forward says whether the quad runs min -> max.
struct EdgeUse {
  int quad;
  bool forward;
};

// The quad in conflict with most neighbours is the inverted one (a single flipped quad
// disagrees with all its neighbours, each neighbour only with it); ties go to the lower index.
[[noreturn]] void reportInverted(const std::map<int, std::vector<std::pair<int, std::string>>>& bad,
                                 const std::string& why) {
  auto worst = bad.begin();
  for (auto it = bad.begin(); it != bad.end(); ++it)
    if (it->second.size() > worst->second.size()) worst = it;
  const auto& [other, edge] = worst->second.front();
  throw InputError("mesh: quad " + std::to_string(worst->first) + " is inverted: " + why +
                   " neighbouring quad " + std::to_string(other) + " across " + edge);
}

}  // namespace

void checkMesh(const QuadMesh& mesh) {
  const int nv = mesh.numVertices();
  const int nq = mesh.numQuads();
  if (nv == 0 || nq == 0)
    throw InputError("mesh is empty: " + std::to_string(nv) + " vertices, " + std::to_string(nq) +
                     " quads");

  for (int v = 0; v < nv; ++v)
    if (!mesh.vertices[v].allFinite()) {
      std::ostringstream s;
      s << "mesh: vertex " << v << " has a non-finite coordinate (" << mesh.vertices[v].transpose()
        << ")";
      throw InputError(s.str());
    }

  std::vector<char> used(nv, 0);
  for (int q = 0; q < nq; ++q) {
    const auto& c = mesh.quads[q];
    for (int k = 0; k < 4; ++k) {
      if (c[k] < 0 || c[k] >= nv)
        throw InputError("mesh: quad " + std::to_string(q) + " names vertex " +
                         std::to_string(c[k]) + ", but the mesh has " + std::to_string(nv) +
                         " vertices");
      for (int l = 0; l < k; ++l)
        if (c[l] == c[k])
          throw InputError("mesh: quad " + std::to_string(q) + " repeats vertex " +
                           std::to_string(c[k]));
      used[c[k]] = 1;
    }
  }
  // A vertex on no quad has no stiffness and no mass: the solvers' matrices would be singular.
  for (int v = 0; v < nv; ++v)
    if (!used[v]) throw InputError("mesh: vertex " + std::to_string(v) + " belongs to no quad");

  // Degenerate quads, relative to the mesh's own scale so that any unit system works.
  double mean_area = 0.0, mean_edge = 0.0;
  std::vector<Eigen::Vector3d> area(nq);
  for (int q = 0; q < nq; ++q) {
    area[q] = areaVector(mesh, mesh.quads[q]);
    mean_area += area[q].norm() / nq;
    for (int k = 0; k < 4; ++k)
      mean_edge +=
          (mesh.vertices[mesh.quads[q][(k + 1) % 4]] - mesh.vertices[mesh.quads[q][k]]).norm() /
          (4.0 * nq);
  }
  for (int q = 0; q < nq; ++q) {
    const auto& c = mesh.quads[q];
    for (int k = 0; k < 4; ++k) {
      const double len = (mesh.vertices[c[(k + 1) % 4]] - mesh.vertices[c[k]]).norm();
      if (!(len > 1e-12 * mean_edge))
        throw InputError("mesh: quad " + std::to_string(q) +
                         " is degenerate: " + edgeName(c[k], c[(k + 1) % 4]) + " has zero length");
    }
    if (!(area[q].norm() > 1e-12 * mean_area)) {
      std::ostringstream s;
      s << "mesh: quad " << q << " is degenerate: area " << area[q].norm() << " vs mean "
        << mean_area;
      throw InputError(s.str());
    }
    // A corner whose triangle faces away from the quad means a concave or self-folded quad:
    // its bilinear map has a negative Jacobian there.
    for (int k = 0; k < 4; ++k) {
      const auto& p = mesh.vertices;
      const Eigen::Vector3d corner =
          (p[c[(k + 1) % 4]] - p[c[k]]).cross(p[c[(k + 3) % 4]] - p[c[k]]);
      if (corner.dot(area[q]) <= 0.0)
        throw InputError("mesh: quad " + std::to_string(q) + " is degenerate: concave or folded " +
                         "at vertex " + std::to_string(c[k]));
    }
  }

  std::map<std::pair<int, int>, std::vector<EdgeUse>> edges;
  for (int q = 0; q < nq; ++q)
    for (int k = 0; k < 4; ++k) {
      const int a = mesh.quads[q][k], b = mesh.quads[q][(k + 1) % 4];
      edges[{std::min(a, b), std::max(a, b)}].push_back({q, a < b});
    }
  for (const auto& [e, uses] : edges)
    if (uses.size() > 2) {
      std::string list;
      for (const auto& u : uses) list += (list.empty() ? "" : ", ") + std::to_string(u.quad);
      throw InputError("mesh: " + edgeName(e.first, e.second) + " is non-manifold: shared by " +
                       std::to_string(uses.size()) + " quads (" + list + ")");
    }

  // Topological orientation: neighbours must run along a shared edge in opposite directions.
  std::map<int, std::vector<std::pair<int, std::string>>> conflicts;
  for (const auto& [e, uses] : edges)
    if (uses.size() == 2 && uses[0].forward == uses[1].forward) {
      const std::string name = edgeName(e.first, e.second);
      conflicts[uses[0].quad].push_back({uses[1].quad, name});
      conflicts[uses[1].quad].push_back({uses[0].quad, name});
    }
  if (!conflicts.empty())
    reportInverted(conflicts, "it runs along a shared edge in the same direction as");

  // Geometric orientation: consistently numbered neighbours whose normals are nearly opposite
  // (in a flat region, a quad turned over onto its neighbour) cannot be a stress-free state.
  for (const auto& [e, uses] : edges)
    if (uses.size() == 2) {
      const Eigen::Vector3d n0 = area[uses[0].quad].normalized();
      const Eigen::Vector3d n1 = area[uses[1].quad].normalized();
      if (n0.dot(n1) < -0.9) {
        const std::string name = edgeName(e.first, e.second);
        conflicts[uses[0].quad].push_back({uses[1].quad, name});
        conflicts[uses[1].quad].push_back({uses[0].quad, name});
      }
    }
  if (!conflicts.empty()) reportInverted(conflicts, "its normal is opposite to that of");
}

}  // namespace chs
