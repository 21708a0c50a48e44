#pragma once
#include <vector>

#include <Eigen/Core>

#include "cloth_hair_sim/core/material/shell_material.h"
#include "cloth_hair_sim/core/mesh/quad_mesh.h"

namespace chs {

// The free parameters of the network (seed 000 eqs. 38 and 43). D' and B' scale the springs
// only when they are shortened ("D' < 1 for repulsion", "B' < 1 for the shorter diagonal"), so
// 1 keeps every spring linear; values below 1 let the cloth buckle in compression more easily.
struct ParticleNetworkOptions {
  double stretch_compression = 1.0;  // D' for a compressed edge
  double shear_compression = 1.0;    // B' for a compressed diagonal
};

// A two-node linear spring: an edge (stretching) or a quad diagonal (shearing).
struct ParticleSpring {
  int a = -1, b = -1;
  double rest_length = 0.0;
  double stiffness = 0.0;           // force per unit length change, in tension
  double compression_factor = 1.0;  // D' or B' in compression
};

// Two consecutive edges a-v-c of one grid line; the bending moment acts on the angle between
// them (seed 000 eqs. 44-47). A clamped vertex at the end of a grid line gets a hinge whose
// first node is a ghost held at x_v - ghost_offset, which keeps the clamped direction.
struct ParticleHinge {
  int a = -1;  // -1: ghost node
  int v = -1, c = -1;
  Eigen::Vector3d ghost_offset = Eigen::Vector3d::Zero();
  double rest_angle = 0.0;          // unsigned angle between the reference edges
  double width = 0.0;               // width of cloth the grid line stands for
  double length = 0.0;              // length of grid line the hinge stands for (Voronoi length)
  double edge1 = 0.0, edge2 = 0.0;  // reference lengths of a-v and v-c
};

// The particle network of seed 000 section 3.1 built on a quad mesh: stretching springs on the
// edges (36-38), shearing springs on the quad diagonals (39-43) and bending hinges along both
// grid directions (44-47). Forces derive from an energy, so they sum to zero and conserve
// momentum; the dynamic model reuses them unchanged.
class ParticleNetwork {
 public:
  // clamped: vertices whose grid-line direction is held (ghost hinges at the line ends).
  ParticleNetwork(const QuadMesh& mesh, const ShellMaterial& material,
                  const std::vector<int>& clamped, const ParticleNetworkOptions& options = {});

  int numVertices() const { return static_cast<int>(tributary_area_.size()); }
  const std::vector<ParticleSpring>& stretchSprings() const { return stretch_; }
  const std::vector<ParticleSpring>& shearSprings() const { return shear_; }
  const std::vector<ParticleHinge>& hinges() const { return hinges_; }
  // Area of cloth each vertex stands for: a quarter of each adjacent quad.
  const std::vector<double>& tributaryArea() const { return tributary_area_; }
  // Mean reference edge length: the b of the convergence test (seed 000 section 3.2.3).
  double referenceEdgeLength() const { return mean_edge_; }
  // Edge neighbours of each vertex (for force couples).
  const std::vector<std::vector<int>>& neighbours() const { return neighbours_; }

  // Adds the internal forces F_stretch + F_shear + F_bend at positions x to f.
  void addForces(const std::vector<Eigen::Vector3d>& x, std::vector<Eigen::Vector3d>& f) const;
  double elasticEnergy(const std::vector<Eigen::Vector3d>& x) const;
  // Gershgorin bound of each vertex's row of the stiffness matrix at the reference state: the
  // largest force per unit displacement the vertex can feel. Sets the stable relaxation step.
  std::vector<double> stiffnessBound() const;

 private:
  double bendingMoment(const ParticleHinge& h, double dphi) const;  // moment M, eq. (45)
  double bendingEnergy(const ParticleHinge& h, double dphi) const;
  double bendingTangent() const;  // largest dM/dkappa per width

  ShellMaterial material_;
  std::vector<ParticleSpring> stretch_, shear_;
  std::vector<ParticleHinge> hinges_;
  std::vector<double> tributary_area_;
  std::vector<std::vector<int>> neighbours_;
  double mean_edge_ = 0.0;
};

}  // namespace chs
