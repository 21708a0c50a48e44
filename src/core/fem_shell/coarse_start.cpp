#include "cloth_hair_sim/core/fem_shell/coarse_start.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>

namespace chs {

std::optional<GridCoarsening> GridCoarsening::of(const DrapeProblem& fine, int min_cells,
                                                 std::string* why) {
  const auto none = [why](const std::string& reason) {
    if (why) *why = reason;
    return std::nullopt;
  };
  const QuadMesh& mesh = fine.mesh;
  if (!fine.seams.empty()) return none("the garment has seams");
  if (!fine.bc.loads.empty()) return none("the garment has nodal loads");
  const auto not_grid = [&] { return none("the mesh is not a rectangle's regular grid"); };
  if (mesh.quads.empty()) return not_grid();
  // makeRectangleMesh's first quad is {0, 1, nx + 2, nx + 1} (up to orientation).
  const auto& q0 = mesh.quads[0];
  const int nx = *std::max_element(q0.begin(), q0.end()) - 2;
  if (nx < 1 || mesh.numQuads() % nx != 0) return not_grid();
  const int ny = mesh.numQuads() / nx;
  if (mesh.numVertices() != (nx + 1) * (ny + 1)) return not_grid();
  const auto id = [nx](int i, int j) { return j * (nx + 1) + i; };
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      std::array<int, 4> want{id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)};
      std::array<int, 4> have = mesh.quads[j * nx + i];
      std::sort(want.begin(), want.end());
      std::sort(have.begin(), have.end());
      if (want != have) return not_grid();
    }
  const std::string cells = std::to_string(nx) + " x " + std::to_string(ny) + " cells";
  if (nx % 2 != 0 || ny % 2 != 0) return none(cells + ", not even both ways");
  if (nx < 2 * min_cells || ny < 2 * min_cells)
    return none(cells + ": the coarse grid would have fewer than " + std::to_string(min_cells) +
                " along a side");

  // The coarse grid must resolve the folds: its cells no longer than 3/4 of the bending length
  // (D / (rho_A g))^(1/3) of the sheet under its own weight. At a whole bending length the
  // coarse drape is another one and the fine Newton's path from it long (the 48 x 48 pedestal
  // from 12 x 12 by way of 24 x 24: 239 + 56 iterations against 78 from the flat sheet);
  // docs/BENCHMARKS.md, 2026-12-08, has the measurements.
  const double weight = fine.material.areal_density * fine.gravity.norm();
  if (fine.material.kawabata) return none("Kawabata bending has no bending length");
  if (!(weight > 0.0)) return none("without weight the sheet has no bending length");
  const double bending_length = std::cbrt(fine.material.bendingStiffness() / weight);
  double coarse_cell = 0.0;
  for (int j = 0; j + 2 <= ny; j += 2)
    for (int i = 0; i + 2 <= nx; i += 2) {
      const Eigen::Vector3d& x = mesh.vertices[id(i, j)];
      coarse_cell = std::max({coarse_cell, (mesh.vertices[id(i + 2, j)] - x).norm(),
                              (mesh.vertices[id(i, j + 2)] - x).norm()});
    }
  if (coarse_cell > 0.75 * bending_length) {
    std::ostringstream reason;
    reason.precision(3);
    reason << "the coarse grid's cells of " << 1e3 * coarse_cell
           << " mm would exceed 3/4 of the bending length, " << 1e3 * bending_length << " mm";
    return none(reason.str());
  }

  GridCoarsening g;
  g.nx_ = nx;
  g.ny_ = ny;
  const int cx = nx / 2, cy = ny / 2;
  const auto coarse_id = [cx](int i, int j) { return j * (cx + 1) + i; };
  DrapeProblem& c = g.coarse_;
  c.material = fine.material;
  c.fabric = fine.fabric;
  c.gravity = fine.gravity;
  c.colliders = fine.colliders;
  for (int j = 0; j <= cy; ++j)
    for (int i = 0; i <= cx; ++i) c.mesh.vertices.push_back(mesh.vertices[id(2 * i, 2 * j)]);
  for (int j = 0; j < cy; ++j)
    for (int i = 0; i < cx; ++i) {
      std::array<int, 4> q{coarse_id(i, j), coarse_id(i + 1, j), coarse_id(i + 1, j + 1),
                           coarse_id(i, j + 1)};
      // The orientation of the fine quad at the coarse quad's first corner.
      const auto& f = mesh.quads[2 * j * nx + 2 * i];
      if (f[1] != id(2 * i + 1, 2 * j)) std::swap(q[1], q[3]);
      c.mesh.quads.push_back(q);
    }
  // The coarse vertex nearest to a fine one (odd grid lines round down).
  const auto nearest = [&](int v) { return coarse_id((v % (nx + 1)) / 2, (v / (nx + 1)) / 2); };
  for (int v : fine.bc.clamped) c.bc.clamped.push_back(nearest(v));
  for (int v : fine.bc.pinned) c.bc.pinned.push_back(nearest(v));
  for (const auto& f : fine.bc.fixed_components)
    c.bc.fixed_components.push_back({nearest(f.vertex), f.axis});
  return g;
}

std::vector<ShellNode> GridCoarsening::prolong(const std::vector<Eigen::Vector3d>& positions,
                                               const std::vector<Eigen::Vector3d>& directors,
                                               const std::vector<ShellNode>& reference,
                                               const DrapeProblem& fine) const {
  const int cx = nx_ / 2;
  std::vector<ShellNode> nodes = reference;
  for (int j = 0; j <= ny_; ++j)
    for (int i = 0; i <= nx_; ++i) {
      // The coarse nodes around fine vertex (i, j): one, two or four, equally weighted.
      Eigen::Vector3d x = Eigen::Vector3d::Zero(), t = Eigen::Vector3d::Zero();
      int n = 0;
      for (int b = j / 2; b <= (j + 1) / 2; ++b)
        for (int a = i / 2; a <= (i + 1) / 2; ++a) {
          x += positions[b * (cx + 1) + a];
          t += directors[b * (cx + 1) + a];
          ++n;
        }
      x /= n;
      for (const auto& surface : fine.colliders) {
        const SurfaceProjection p = surface->project(x);
        if (p.gap < 0.0) x -= p.gap * p.normal;
      }
      ShellNode& node = nodes[j * (nx_ + 1) + i];
      node.position = x;
      if (t.norm() > 0.0) node.frame = DirectorFrame(t.normalized());
    }
  for (int v : fine.bc.clamped) nodes[v] = reference[v];
  for (int v : fine.bc.pinned) nodes[v].position = reference[v].position;
  for (const auto& f : fine.bc.fixed_components)
    nodes[f.vertex].position[f.axis] = reference[f.vertex].position[f.axis];
  return nodes;
}

}  // namespace chs
