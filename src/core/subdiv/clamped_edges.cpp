#include "cloth_hair_sim/core/subdiv/clamped_edges.h"

#include <algorithm>
#include <array>
#include <set>
#include <string>
#include <utility>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/mesh/boundary_edges.h"
#include "cloth_hair_sim/core/mesh/mesh_check.h"

namespace chs {
namespace {

using Vec3 = Eigen::Vector3d;

// Each vertex's edge neighbours, and which edges lie on the boundary (as (min, max)).
struct EdgeTable {
  std::vector<std::array<int, 2>> boundary;  // as their quads run them
  std::set<std::pair<int, int>> on_boundary;
  std::vector<std::set<int>> neighbours;

  explicit EdgeTable(const QuadMesh& mesh)
      : boundary(boundaryEdges(mesh)), neighbours(mesh.numVertices()) {
    for (const auto& [a, b] : boundary) on_boundary.insert(std::minmax(a, b));
    for (const auto& q : mesh.quads)
      for (int k = 0; k < 4; ++k) {
        neighbours[q[k]].insert(q[(k + 1) % 4]);
        neighbours[q[(k + 1) % 4]].insert(q[k]);
      }
  }
  bool isBoundary(int a, int b) const { return on_boundary.count(std::minmax(a, b)) > 0; }
};

std::string vertexName(int v) {
  return "clamped edges: vertex " + std::to_string(v);
}

}  // namespace

ClampedEdges::ClampedEdges(const QuadMesh& mesh, const std::vector<int>& clamped)
    : extended_(mesh), mesh_vertices_(mesh.numVertices()), mesh_faces_(mesh.numQuads()) {
  std::vector<int> ghost_of(mesh_vertices_, -1);
  for (int v : clamped) {
    if (v < 0 || v >= mesh_vertices_)
      throw InputError(vertexName(v) + " is out of range (" + std::to_string(mesh_vertices_) +
                       " vertices)");
    ghost_of[v] = 0;  // marks "clamped"; ghost indices follow below
  }
  if (clamped.empty()) {
    slaved_.assign(mesh_vertices_, 0);
    return;
  }
  const EdgeTable edges(mesh);
  for (int v = 0; v < mesh_vertices_; ++v) {
    if (ghost_of[v] < 0) continue;
    int interior = -1, free_boundary = -1, interior_count = 0, free_boundary_count = 0;
    bool on_boundary = false, clamped_neighbour = false;
    for (int u : edges.neighbours[v]) {
      const bool boundary = edges.isBoundary(v, u);
      on_boundary |= boundary;
      if (boundary && ghost_of[u] >= 0) clamped_neighbour = true;
      if (!boundary) interior = u, ++interior_count;
      if (boundary && ghost_of[u] < 0) free_boundary = u, ++free_boundary_count;
    }
    if (!on_boundary) throw InputError(vertexName(v) + " is clamped but not on the mesh boundary");
    if (!clamped_neighbour)
      throw InputError(vertexName(v) +
                       " has no clamped neighbour along the boundary: a clamp holds an edge, "
                       "at least two adjacent boundary vertices");
    // A boundary vertex of valence 3 has one edge into the shell; a corner (valence 2) has
    // none, and then the unclamped boundary edge leads into the shell.
    // A clamp that stops partway along an edge would leave its last point with a free boundary
    // edge, an interior edge and a ghost face: an irregular boundary vertex whose limit point
    // is no longer held and whose reference surface changes.
    if (interior_count == 1 && free_boundary_count > 0)
      throw InputError(vertexName(v) +
                       " ends a clamp partway along a boundary edge: a clamp must run to mesh "
                       "corners (clamp the whole edge)");
    Clamp c;
    c.boundary = v;
    if (interior_count == 1)
      c.interior = interior;
    else if (interior_count == 0 && free_boundary_count == 1)
      c.interior = free_boundary;
    else
      throw InputError(vertexName(v) + " has " + std::to_string(interior_count) +
                       " edges into the shell and " + std::to_string(free_boundary_count) +
                       " unclamped boundary edges: no unique direction to clamp (two clamped "
                       "edges meeting at a corner, or an irregular boundary vertex)");
    if (ghost_of[c.interior] >= 0)
      throw InputError(vertexName(v) + "'s neighbour into the shell, vertex " +
                       std::to_string(c.interior) +
                       ", is clamped too: a clamped edge needs a free row next to it");
    c.ghost = extended_.numVertices();
    c.point = mesh.vertices[v];
    const Vec3 d = mesh.vertices[c.interior] - c.point;
    if (!(d.norm() > 0.0)) throw InputError(vertexName(v) + " coincides with its neighbour");
    c.direction = d.normalized();
    ghost_of[v] = c.ghost;
    extended_.vertices.push_back(2.0 * c.point - mesh.vertices[c.interior]);
    clamps_.push_back(c);
  }
  // One ghost face across each clamped boundary edge a -> b (as its face runs), oriented
  // consistently with it: b -> a -> G_a -> G_b.
  for (const auto& [a, b] : edges.boundary)
    if (ghost_of[a] >= 0 && ghost_of[b] >= 0)
      extended_.quads.push_back({b, a, ghost_of[a], ghost_of[b]});
  try {
    checkMesh(extended_);
  } catch (const InputError& e) {
    throw InputError(std::string("clamped edges: the mesh with ghost faces across its clamped "
                                 "edges is broken (") +
                     e.what() + ")");
  }
  slaved_.assign(extended_.numVertices(), 0);
  for (const Clamp& c : clamps_) slaved_[c.boundary] = slaved_[c.ghost] = 1;
}

void ClampedEdges::placePositions(std::vector<Vec3>& x) const {
  for (const Clamp& c : clamps_) {
    const Vec3 d = x[c.interior] - c.point;
    const Vec3 along = c.direction * c.direction.dot(d);
    x[c.ghost] = c.point + d - 2.0 * along;
    x[c.boundary] = c.point - 0.5 * (d - along);
  }
}

void ClampedEdges::placeVelocities(std::vector<Vec3>& v) const {
  for (const Clamp& c : clamps_) {
    const Vec3 vn = v[c.interior];
    const Vec3 along = c.direction * c.direction.dot(vn);
    v[c.ghost] = vn - 2.0 * along;
    v[c.boundary] = -0.5 * (vn - along);
  }
}

Vec3 ClampedEdges::foldedForce(const Clamp& c, const Vec3& f_boundary, const Vec3& f_ghost) const {
  const Vec3& t = c.direction;
  return -0.5 * (f_boundary - t * t.dot(f_boundary)) + f_ghost - 2.0 * t * t.dot(f_ghost);
}

Vec3 ClampedEdges::reaction(const Clamp& c, const Vec3& r_boundary, const Vec3& r_ghost) const {
  const Vec3& t = c.direction;
  // (I + (I - t t^T) / 2) r_B + (I - R) r_G
  return r_boundary + 0.5 * (r_boundary - t * t.dot(r_boundary)) + 2.0 * t * t.dot(r_ghost);
}

}  // namespace chs
