#include "cloth_hair_sim/core/fem_shell/coarse_start.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>

namespace chs {

namespace {

enum Role : char { kUnknown = 0, kCorner, kMid, kCentre };

// Each quad's corners as a coarse corner, an edge midpoint, a face centre and an edge midpoint
// in cyclic order, from the start quad's corner `first` taken as a coarse corner and spread from
// quad to quad over shared corners and face centres (two quads that share an edge share one of
// those); empty if the roles contradict somewhere, a quad is not reached or a face centre is not
// among four quads.
std::vector<char> roles(const QuadMesh& mesh, const std::vector<std::vector<int>>& quads_of,
                        int first) {
  std::vector<char> role(mesh.numVertices(), kUnknown);
  std::vector<char> done(mesh.numQuads(), 0);
  // Gives quad q the roles that put role r at its corner k; false on a contradiction.
  const auto assign = [&](int q, int k, char r) {
    static constexpr char kCycle[4] = {kCorner, kMid, kCentre, kMid};
    const int offset = r == kCorner ? 0 : 2;  // r is kCorner or kCentre
    for (int i = 0; i < 4; ++i) {
      const char want = kCycle[(offset + i) % 4];
      char& have = role[mesh.quads[q][(k + i) % 4]];
      if (have != kUnknown && have != want) return false;
      have = want;
    }
    done[q] = 1;
    return true;
  };
  std::vector<int> queue;
  if (!assign(0, first, kCorner)) return {};
  queue.push_back(0);
  while (!queue.empty()) {
    const int q = queue.back();
    queue.pop_back();
    for (int v : mesh.quads[q]) {
      if (role[v] == kMid) continue;
      for (int n : quads_of[v]) {
        if (done[n]) continue;
        const int k = static_cast<int>(std::find(mesh.quads[n].begin(), mesh.quads[n].end(), v) -
                                       mesh.quads[n].begin());
        if (!assign(n, k, role[v])) return {};
        queue.push_back(n);
      }
    }
  }
  if (std::find(done.begin(), done.end(), 0) != done.end()) return {};
  // A face centre is inside its coarse quad, among four fine ones (the roles shifted by one grid
  // line agree quad by quad too, and fail here, at the boundary).
  for (int v = 0; v < mesh.numVertices(); ++v)
    if (role[v] == kCentre && quads_of[v].size() != 4) return {};
  return role;
}

}  // namespace

std::optional<GridCoarsening> GridCoarsening::of(const DrapeProblem& fine, int min_quads,
                                                 std::string* why) {
  const auto none = [why](const std::string& reason) {
    if (why) *why = reason;
    return std::nullopt;
  };
  const QuadMesh& mesh = fine.mesh;
  if (!fine.seams.empty()) return none("the garment has seams");
  if (!fine.bc.loads.empty()) return none("the garment has nodal loads");
  const int nv = mesh.numVertices();
  std::vector<std::vector<int>> quads_of(nv);
  for (int q = 0; q < mesh.numQuads(); ++q)
    for (int v : mesh.quads[q]) quads_of[v].push_back(q);
  std::vector<char> role;
  for (int first = 0; first < 4 && role.empty() && mesh.numQuads() > 0; ++first)
    role = roles(mesh, quads_of, first);
  if (role.empty()) return none("the mesh is not a 2 x 2 refinement of a coarser one");

  GridCoarsening g;
  DrapeProblem& c = g.coarse_;
  std::vector<int> coarse_of(nv, -1);
  for (int v = 0; v < nv; ++v)
    if (role[v] == kCorner) {
      coarse_of[v] = c.mesh.numVertices();
      c.mesh.vertices.push_back(mesh.vertices[v]);
    }
  g.parents_.resize(nv);
  for (int v = 0; v < nv; ++v) {
    if (role[v] != kCentre) continue;
    // A face centre: its four quads round it, each with a coarse corner opposite it; walked the
    // way the quads run (from the centre, the corner two on), so the coarse quad runs so too.
    std::array<int, 4> quad{};
    int q = quads_of[v].front();
    for (int i = 0; i < 4; ++i) {
      const auto& f = mesh.quads[q];
      const int k = static_cast<int>(std::find(f.begin(), f.end(), v) - f.begin());
      quad[i] = coarse_of[f[(k + 2) % 4]];
      const int next_mid = f[(k + 3) % 4];
      const auto it = std::find_if(quads_of[v].begin(), quads_of[v].end(), [&](int n) {
        return n != q && std::count(mesh.quads[n].begin(), mesh.quads[n].end(), next_mid) > 0;
      });
      if (it == quads_of[v].end())
        return none("the mesh is not a 2 x 2 refinement of a coarser one");
      q = *it;
    }
    c.mesh.quads.push_back(quad);
    g.parents_[v].assign(quad.begin(), quad.end());
  }
  for (int v = 0; v < nv; ++v) {
    if (role[v] == kCorner) g.parents_[v] = {coarse_of[v]};
    if (role[v] != kMid) continue;
    // An edge midpoint: the two coarse corners it joins along fine edges.
    for (int q : quads_of[v]) {
      const auto& f = mesh.quads[q];
      const int k = static_cast<int>(std::find(f.begin(), f.end(), v) - f.begin());
      for (int n : {f[(k + 1) % 4], f[(k + 3) % 4]})
        if (role[n] == kCorner && std::find(g.parents_[v].begin(), g.parents_[v].end(),
                                            coarse_of[n]) == g.parents_[v].end())
          g.parents_[v].push_back(coarse_of[n]);
    }
    if (g.parents_[v].size() != 2)
      return none("the mesh is not a 2 x 2 refinement of a coarser one");
  }
  if (c.mesh.numQuads() < min_quads)
    return none("the coarser mesh would have " + std::to_string(c.mesh.numQuads()) +
                " quads, fewer than " + std::to_string(min_quads));

  // The coarse mesh must resolve the folds: its edges on average no longer than 3/4 of the
  // bending length
  // (D / (rho_A g))^(1/3) of the sheet under its own weight. At a whole bending length the
  // coarse drape is another one and the fine Newton's path from it long (the 48 x 48 pedestal
  // from 12 x 12 by way of 24 x 24: 239 + 56 iterations against 78 from the flat sheet);
  // docs/BENCHMARKS.md, 2026-12-08, has the measurements.
  const double weight = fine.material.areal_density * fine.gravity.norm();
  if (fine.material.kawabata) return none("Kawabata bending has no bending length");
  if (!(weight > 0.0)) return none("without weight the sheet has no bending length");
  const double bending_length = std::cbrt(fine.material.bendingStiffness() / weight);
  double edges = 0.0;
  for (const auto& q : c.mesh.quads)
    for (int i = 0; i < 4; ++i)
      edges += (c.mesh.vertices[q[i]] - c.mesh.vertices[q[(i + 1) % 4]]).norm();
  const double mean_edge = edges / (4.0 * c.mesh.numQuads());
  if (mean_edge > 0.75 * bending_length) {
    std::ostringstream reason;
    reason.precision(3);
    reason << "the coarser mesh's edges of " << 1e3 * mean_edge
           << " mm (mean) would exceed 3/4 of the bending length, " << 1e3 * bending_length
           << " mm";
    return none(reason.str());
  }

  c.material = fine.material;
  c.fabric = fine.fabric;
  c.gravity = fine.gravity;
  c.colliders = fine.colliders;
  const auto next_to = [&g](int v) { return g.parents_[v].front(); };
  for (int v : fine.bc.clamped) c.bc.clamped.push_back(next_to(v));
  for (int v : fine.bc.pinned) c.bc.pinned.push_back(next_to(v));
  for (const auto& f : fine.bc.fixed_components)
    c.bc.fixed_components.push_back({next_to(f.vertex), f.axis});
  return g;
}

std::vector<ShellNode> GridCoarsening::prolong(const std::vector<Eigen::Vector3d>& positions,
                                               const std::vector<Eigen::Vector3d>& directors,
                                               const std::vector<ShellNode>& reference,
                                               const DrapeProblem& fine) const {
  std::vector<ShellNode> nodes = reference;
  for (std::size_t v = 0; v < nodes.size(); ++v) {
    Eigen::Vector3d u = Eigen::Vector3d::Zero(), t = Eigen::Vector3d::Zero();
    for (int p : parents_[v]) {
      u += positions[p] - coarse_.mesh.vertices[p];
      t += directors[p];
    }
    Eigen::Vector3d x = fine.mesh.vertices[v] + u / static_cast<double>(parents_[v].size());
    for (const auto& surface : fine.colliders) {
      const SurfaceProjection pr = surface->project(x);
      if (pr.gap < 0.0) x -= pr.gap * pr.normal;
    }
    nodes[v].position = x;
    if (t.norm() > 0.0) nodes[v].frame = DirectorFrame(t.normalized());
  }
  for (int v : fine.bc.clamped) nodes[v] = reference[v];
  for (int v : fine.bc.pinned) nodes[v].position = reference[v].position;
  for (const auto& f : fine.bc.fixed_components)
    nodes[f.vertex].position[f.axis] = reference[f.vertex].position[f.axis];
  return nodes;
}

}  // namespace chs
