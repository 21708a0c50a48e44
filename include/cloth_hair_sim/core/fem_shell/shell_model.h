#pragma once
#include <string>
#include <vector>

#include "cloth_hair_sim/core/drape/drape_problem.h"
#include "cloth_hair_sim/core/fem_shell/shell_element.h"
#include "cloth_hair_sim/core/solver/continuation_problem.h"

namespace chs {

// The assembled FEM shell of a drape problem: Simo-Fox elements, boundary conditions, the
// reference load (gravity, nodal forces and moments) and node-on-surface penalty contact with
// the rigid colliders (seed 000 eqs. (27)-(35)), as a ContinuationProblem for the path-following
// solver. Unknowns: 5 per node (3 translations + 2 director increments), constrained ones removed.
class ShellModel : public ContinuationProblem {
 public:
  // edge_contact: penalty contact also where an element edge meets a collider between its
  // nodes (a table edge or pedestal rim), see edgeContacts().
  // join_seams: the vertices that problem.seams sew together (SeamGroups) share their three
  // translational unknowns, a tie that keeps their offsets (setNodes); their directors stay
  // their own, so a seam is a hinge line as a sewn seam with its allowance folded inside.
  ShellModel(const DrapeProblem& problem, double contact_stiffness, bool edge_contact = true,
             bool join_seams = false);

  int size() const override { return num_free_; }
  void linearize(double lambda, Eigen::VectorXd& R, Eigen::VectorXd& F0,
                 Eigen::SparseMatrix<double>* K) override;
  void increment(const Eigen::VectorXd& dq) override;
  void save() override { saved_ = anchor_ = nodes_; }
  void restore() override { nodes_ = saved_; }
  void setStabilization(double factor) override;
  void anchorHere() override { anchor_ = nodes_; }
  // Strain energy + penalty energy - lambda (dead load) . displacement (+ the viscous term's
  // own potential); NaN with Kawabata bending or nodal moments, which have none.
  double energy(double lambda) override;
  // At most two mean element edges of translation and half a radian of director turn.
  double stepBound(const Eigen::VectorXd& dq) const override;
  // Imperfections that let a perfectly flat sheet choose its folds (FemShellSettings): a seeded
  // random displacement in [0, a] of the free nodes along their directors, or n waves round the
  // centroid, a (1 + cos n theta) / 2 (r / r_max)^2.
  void perturbRandom(double amplitude, unsigned seed);
  void perturbWaves(double amplitude, int waves);
  double loadNorm() const override { return load_norm_; }
  double lengthScale() const override { return length_scale_; }
  int activeContacts() const override { return active_contacts_; }

  const std::vector<ShellNode>& nodes() const { return nodes_; }
  // Continues from these nodes (of the same problem). With join_seams the members of a sewn
  // group share their increments, so they keep the offsets from one another they are given here:
  // zero once the seam is closed.
  void setNodes(const std::vector<ShellNode>& nodes);
  // Rigid-body motions that neither the constrained unknowns nor the contacts active at the
  // current state restrain, in words ("" when there are none): the cause of a singular tangent.
  std::string unrestrainedRigidModes() const;

  // Contact forces the colliders exert at the current state.
  std::vector<ContactReaction> reactions() const;
  double contactStiffness() const { return k_contact_; }

 private:
  const DrapeProblem& problem_;
  std::vector<ShellElement> elements_;
  std::vector<ShellNode> nodes_, saved_, anchor_;
  std::vector<int> dof_;                       // 5 per vertex, -1 when constrained
  std::vector<std::vector<int>> seam_groups_;  // with join_seams: vertices tied together
  std::vector<Eigen::Vector3d> f_dead_;        // reference forces (gravity + nodal forces)
  std::vector<Eigen::Vector3d> moment_;        // reference nodal moments
  int num_free_ = 0;
  double load_norm_ = 0.0, length_scale_ = 1.0, k_contact_ = 0.0;
  int active_contacts_ = 0;
  struct Penalty {
    double force, stiffness;  // magnitude along the normal and its derivative
  };
  Penalty penalty(double gap) const;
  double penaltyEnergy(double gap) const;  // its potential: -d/dgap = force

  // Contact along the element edges (with edge_contact, for tables and pedestals, in place of
  // the node-on-surface penalty): the potential of each edge x(s) = (1 - s) x_a + s x_b is int_0^1
  // phi(g(x(s))) ds, so a table edge or pedestal rim that crosses a cloth edge between its nodes
  // meets it where it is. The integrand is nonzero only where the gap is below the band; for a
  // convex collider g(s) is convex, and Gauss quadrature on either side of its least value
  // integrates it smoothly. Force and tangent are added to R and K (or the energy to *energy) for
  // the free unknowns; reactions, per node.
  struct Edge {
    int a, b;     // vertices
    int element;  // an element holding both, and their local indices in it
    int la, lb;
  };
  std::vector<Edge> edges_;
  std::vector<bool> edge_surface_;  // per collider: met along the edges (else at the nodes)
  int edgeContacts(Eigen::VectorXd* R, double* kv, double* energy,
                   std::vector<ContactReaction>* reactions) const;
  std::vector<double> element_energy_;

  // Fixed sparsity pattern of K and, per element and per node, where each entry lands in it
  // (-1 for constrained unknowns): assembly adds in place instead of sorting triplets.
  void buildPattern();
  Eigen::SparseMatrix<double> pattern_;
  std::vector<std::array<int, 400>> element_slots_;
  std::vector<std::array<int, 25>> node_slots_;

  // Element results, kept between calls so that each iteration does not allocate them anew.
  std::vector<ElementVector> element_force_;
  std::vector<ElementMatrix> element_tangent_;

  std::vector<double> nodal_mass_;
  double contact_smoothing_ = 0.0;
  double mean_edge_ = 1.0, stabilization_ = 0.0;
};

}  // namespace chs
