#pragma once
#include <algorithm>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "cloth_hair_sim/core/io/state_stream.h"
#include "cloth_hair_sim/core/rod/rod_material.h"
#include "cloth_hair_sim/core/solver/symmetric_band_matrix.h"

namespace chs::rod {

// One strand as a discrete elastic rod (Bergou, Wardetzky, Robinson, Audoly and Grinspun,
// "Discrete elastic rods", SIGGRAPH 2008; Bergou, Audoly, Vouga, Wardetzky and Grinspun,
// "Discrete viscous threads", SIGGRAPH 2010): a centreline of vertices x_0..x_n and, per edge
// e_j = x_{j+1} - x_j, the angle theta_j of its material frame (m1, m2) about the edge from a
// reference frame (d1, d2). The reference frames move with the rod by time-parallel transport
// (2010, section 4.2): each is the last committed one transported to the edge's new tangent, so
// the twist a frame picks up between vertices, the reference twist, is tracked incrementally.
//
// Generalised coordinates q = (x_0, theta_0, x_1, theta_1, ..., theta_{n-1}, x_n), 4n + 3 of
// them: vertex i at 4i, edge j's angle at 4j + 3, so the 11 unknowns of an interior vertex's
// bending and twisting (x_{i-1}, theta_{i-1}, x_i, theta_i, x_{i+1}) are contiguous and the
// Hessian is banded (half-bandwidth 10).
//
// The elastic energy, with rest values barred (Bergou 2008 (2)-(4), 2010 section 5):
//   stretching  sum_j  EA / 2 (|e_j| / |e_j~| - 1)^2 |e_j~|,
//   bending     sum_i  (B1 (kappa_1i - kappa_1i~)^2 + B2 (kappa_2i - kappa_2i~)^2) / (2 l_i),
//   twisting    sum_i  GJ (m_i - m_i~)^2 / (2 l_i),   m_i = theta_i - theta_{i-1} + ref. twist,
// with l_i = (|e_{i-1}~| + |e_i~|) / 2 the Voronoi length of interior vertex i. The rest shape
// gives kappa~ and m~, so a curved (wavy, helical) rest shape is exactly stress-free.
// Masses are lumped: rho A times the Voronoi length at each vertex, rho (I1 + I2) |e~| per edge
// angle.
class DiscreteElasticRod {
 public:
  // Rest (and initial) centreline; first_director: the material frame's m1 on the first edge
  // at rest (projected normal to it; zero: any normal). The rest frames are the first edge's
  // transported along the curve (space-parallel transport, zero rest reference twist).
  // closed: a ring, its last edge from the last vertex back to the first, every vertex bending
  // and twisting (4n unknowns for n vertices); the rest frames' holonomy round the ring is its
  // rest twist at vertex 0. Throws InputError for fewer than two vertices (three for a ring), a
  // non-finite vertex, a segment shorter than 1e-9 m (duplicate vertices), a segment folded
  // back onto its neighbour, or a bad material.
  DiscreteElasticRod(const std::vector<Eigen::Vector3d>& rest, const RodMaterial& material,
                     const Eigen::Vector3d& first_director = Eigen::Vector3d::Zero(),
                     bool closed = false);

  bool closed() const { return closed_; }
  int numVertices() const { return static_cast<int>(x_.size()); }
  int numEdges() const { return closed_ ? numVertices() : numVertices() - 1; }
  int numDofs() const { return 4 * numEdges() + (closed_ ? 0 : 3); }
  int edgeEnd(int j) const { return j + 1 < numVertices() ? j + 1 : 0; }
  // The vertices that bend and twist: 1..n-2 of a strand, all of a ring.
  int firstBendingVertex() const { return closed_ ? 0 : 1; }
  int endBendingVertex() const { return closed_ ? numVertices() : numVertices() - 1; }
  int previousEdge(int i) const { return i > 0 ? i - 1 : numEdges() - 1; }
  static int vertexDof(int i) { return 4 * i; }
  static int angleDof(int j) { return 4 * j + 3; }

  const RodMaterial& material() const { return material_; }
  const std::vector<Eigen::Vector3d>& positions() const { return x_; }
  const std::vector<double>& angles() const { return theta_; }
  const Eigen::Vector3d& materialDirector1(int j) const { return m1_[j]; }
  const Eigen::Vector3d& materialDirector2(int j) const { return m2_[j]; }
  const Eigen::Vector3d& referenceDirector1(int j) const { return d1_[j]; }
  const Eigen::Vector3d& tangent(int j) const { return t_[j]; }
  double referenceTwist(int i) const { return ref_twist_[i]; }
  double restLength(int j) const { return rest_length_[j]; }
  double length() const;  // rest length of the strand
  double vertexMass(int i) const { return vertex_mass_[i]; }
  double angleInertia(int j) const { return angle_inertia_[j]; }
  // Material curvature (kappa_1, kappa_2) and twist m at bending vertex i, now.
  Eigen::Vector2d curvature(int i) const;
  double twist(int i) const;
  // Replaces the natural curvature and twist the rest shape gave (one value per vertex; those of
  // a strand's end vertices are ignored): a ring of a naturally straight rod, or a twist
  // imposed on it. Throws InputError for sizes that do not match or non-finite values.
  void setNaturalShape(const std::vector<Eigen::Vector2d>& curvature,
                       const std::vector<double>& twist);
  // The rod's state for a state file: positions, angles, the committed reference frames the
  // next step transports from, and the natural shape. readState takes it into a rod built from
  // the same rest shape and material; throws InputError (from the reader) for a record of
  // another vertex count.
  void writeState(StateWriter& out) const;
  void readState(StateReader& in);

  Eigen::VectorXd configuration() const;
  // Moves the rod to q (numDofs() values): reference frames transported from the committed
  // configuration. False (the rod moved anyway) if a segment became shorter than 1e-3 of its
  // rest length or folded back onto its neighbour, where the energy is not defined.
  bool setConfiguration(const Eigen::VectorXd& q);
  // The configuration now becomes the start of the next transport (once per time step).
  void commit();

  double elasticEnergy() const;
  // Adds dE/dq to `gradient` (numDofs()) and d2E/dq2 to `hessian` (of numDofs() and
  // hessianBandwidth() at least); either may be null. With `gauss_newton`, the Hessian's
  // positive semi-definite Gauss-Newton form, so that Newton's steps descend: each vertex's
  // bending and twisting keeps B grad(kappa) grad(kappa)^T and drops (kappa - kappa_rest) times
  // the curvature's (and the twist's) own second derivatives, each edge its tension across the
  // edge when compressed. (It replaced zeroing each block's negative eigenvalues, whose 8 x 8
  // eigensolves were a fifth of a head of hair's frame; test_rod_elasticity's static solves
  // take 10-20 % fewer iterations with it.)
  void addElasticDerivatives(Eigen::VectorXd* gradient, SymmetricBandMatrix* hessian,
                             bool gauss_newton) const;
  // The Hessian's half-bandwidth in the unknowns' order: a vertex's bending couples the
  // unknowns of its two edges (10 apart); a ring's first vertex couples its last edge to its
  // first, across the whole matrix.
  int hessianBandwidth() const { return closed_ ? numDofs() - 1 : std::min(10, numDofs() - 1); }

 private:
  void updateFrames();  // tangents, reference and material frames, curvature binormals

  RodMaterial material_;
  bool closed_ = false;
  double stretch_ = 0.0, bend_1_ = 0.0, bend_2_ = 0.0, twist_stiffness_ = 0.0;
  std::vector<double> rest_length_, voronoi_, vertex_mass_, angle_inertia_;
  std::vector<Eigen::Vector2d> rest_kappa_;
  std::vector<double> rest_twist_;
  // Committed configuration's tangents, reference directors and reference twists.
  std::vector<Eigen::Vector3d> base_t_, base_d1_;
  std::vector<double> base_ref_twist_;
  // Now.
  std::vector<Eigen::Vector3d> x_;
  std::vector<double> theta_;
  std::vector<Eigen::Vector3d> t_, d1_, d2_, m1_, m2_;
  std::vector<double> ref_twist_;
  bool admissible_ = true;
};

}  // namespace chs::rod
