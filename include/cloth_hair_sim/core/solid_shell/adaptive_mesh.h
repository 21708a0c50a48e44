#pragma once
#include <array>
#include <vector>

#include <Eigen/Core>

#include "cloth_hair_sim/core/drape/drape_problem.h"
#include "cloth_hair_sim/core/mesh/quad_mesh.h"
#include "cloth_hair_sim/core/solid_shell/solid_shell_model.h"

namespace chs {

// Deepest adaptive level: 4 splittings make 256 background quads of each level-0 quad.
constexpr int kMaxAdaptiveLevels = 4;

// Seed 001 section 5: reversible 1-4 subdivision of the user's level-0 quads.
//  - The background mesh: every level-0 quad split n times; its nodes are numbered once,
//    shared along level-0 edges, with X_o bilinear in the level-0 quad (the seed's mid-edge
//    averages and serendipity centres, which coincide with it) and X_n the normalised bilinear
//    blend of the level-0 directors.
//  - The active mesh: the leaves of a quadtree in each level-0 quad, adjacent leaves at most one
//    level apart. A leaf whose neighbour is one level finer sees that neighbour's corner at
//    its edge's midpoint and becomes a macro-transition element (Fig. 16(b)) of quads and as few
//    triangles as possible, using its centre node where needed:
//      one mid-edge node:            2 quads + 1 triangle
//      two, on adjacent edges:       3 quads
//      two, on opposite edges:       2 quads
//      three:                        3 quads + 1 triangle
//      four:                         the 4 quads of its split
//    Quads list their nodes counter-clockwise, as the level-0 quads.
class AdaptiveQuadMesh {
 public:
  // A cell of the quadtree of level-0 quad `quad`. Lattice points of a level-0 quad are (a, b) in
  // [0, 2^n]^2, a along its first edge, b along its last; a cell at level l spans 2^(n-l) of them.
  struct Cell {
    int quad = 0, level = 0, i = 0, j = 0;  // i, j in [0, 2^level)
  };
  struct Element {
    std::array<int, 4> nodes;  // a triangle's fourth is -1
    int leaf = 0;              // index into leaves()
  };

  // Throws InputError if levels lies outside [1, kMaxAdaptiveLevels]. `directors`: unit
  // reference directors of the level-0 vertices.
  AdaptiveQuadMesh(const QuadMesh& level0, const std::vector<Eigen::Vector3d>& directors,
                   int levels);

  // The finest mesh: every node, (2^n)^2 quads per level-0 quad.
  const QuadMesh& background() const { return background_; }
  int numNodes() const { return background_.numVertices(); }
  // Background node of lattice point (a, b) of level-0 quad q.
  int node(int quad, int a, int b) const { return lattice_[quad][a * (size_ + 1) + b]; }

  const std::vector<Cell>& leaves() const { return leaves_; }
  std::array<int, 4> corners(const Cell& c) const;
  int centre(const Cell& c) const;  // -1 at the finest level
  // Mean reference side length of a leaf (L_i of eq. (25)).
  double sideLength(const Cell& c) const;

  // The active mesh's elements, leaf by leaf.
  std::vector<Element> elements() const;
  // Nodes used by some leaf: its corners and the hanging midpoints of its coarser neighbours.
  std::vector<bool> activeNodes() const;
  int numActiveNodes() const;

  // One adaptation of seed 001 section 5.5 (d)-(e): each leaf flagged +1 splits (below level n),
  // each four sibling leaves all flagged -1 merge (unless a neighbour is two levels finer than
  // their parent), then leaves split until neighbours are within one level. `flags`: one per
  // leaf. Returns whether the leaves changed.
  bool adapt(const std::vector<int>& flags);

  // After adapt(): the displacements of the nodes switched on since `was_active` (activeNodes()
  // before), coarse to fine: mid-edge nodes by the discrete Kirchhoff condition along their
  // parent's edge (or, with discrete_kirchhoff false, the mean of its ends: for velocities),
  // centre nodes by the serendipity element of their parent (seed 001 5.4).
  void fillSwitchedOnNodes(const std::vector<bool>& was_active, std::vector<Eigen::Vector3d>& u,
                           std::vector<Eigen::Vector3d>& un, bool discrete_kirchhoff = true) const;

  // Values of the inactive nodes interpolated from the active elements' shape functions (the
  // active mesh's surface, seen on the background mesh).
  void interpolateInactive(std::vector<Eigen::Vector3d>& values) const;

  // Boundary conditions of the level-0 mesh on the background nodes: a node of a level-0 edge
  // inherits what both ends share (clamped, pinned, fixed components); loads stay on level-0
  // vertices.
  BoundaryConditions boundaryConditions(const BoundaryConditions& level0) const;

  // The active solid-shell mesh (reference nodes and directors of the background mesh).
  SolidShellMesh activeMesh(const BoundaryConditions& background_bc) const;

 private:
  int levels_ = 0, size_ = 1;  // size_ = 2^levels
  QuadMesh level0_, background_;
  std::vector<Eigen::Vector3d> directors_;
  std::vector<std::vector<int>> lattice_;         // per level-0 quad, (size+1)^2 node ids
  std::vector<std::array<int, 2>> edge_of_node_;  // level-0 edge ends of a node on one, else -1
  std::vector<Cell> leaves_;

  // Leaf corners: a leaf's edge midpoint among them is a finer neighbour's corner.
  std::vector<bool> leafCorners() const;
  // A leaf's elements as local labels (0-3 corners, 4-7 midpoints, 8 centre).
  std::vector<std::array<int, 4>> pattern(const Cell& c, const std::vector<bool>& corner) const;
  std::array<int, 9> labels(const Cell& c) const;
  bool balance();
};

// Seed 001 section 5.4, eqs. (30)-(34): the displacement and director of a new mid-edge node M of
// the reference edge A-B, E a third corner of the element (the plane EAB), by the discrete
// Kirchhoff condition in the edge's co-rotated frame: the mid-surface follows the thin-beam
// (Hermite) curve whose end slopes the directors give, the director turns with it.
// u, un: displacements U_o, U_n of every node; fills those of M.
void insertMidEdgeNode(const std::vector<Eigen::Vector3d>& X,
                       const std::vector<Eigen::Vector3d>& Xn, int A, int B, int E, int M,
                       std::vector<Eigen::Vector3d>& u, std::vector<Eigen::Vector3d>& un);

// The centre node of a split quad from its corners and mid-edge nodes by the 8-node serendipity
// element (N = -1/4 at the corners, 1/2 at the midpoints).
void insertCentreNode(const std::array<int, 4>& corners, const std::array<int, 4>& midpoints,
                      int centre, std::vector<Eigen::Vector3d>& u,
                      std::vector<Eigen::Vector3d>& un);

}  // namespace chs
