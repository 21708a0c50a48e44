#pragma once
#include <array>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "cloth_hair_sim/core/drape/drape_problem.h"
#include "cloth_hair_sim/core/solid_shell/solid_shell_element.h"

namespace chs {

// The elements of a solid shell over a set of nodes: the problem's quads, or the active mesh of
// an adaptive background mesh (quads and the triangles of its macro-transition elements; nodes no
// element uses carry no unknowns).
struct SolidShellMesh {
  std::vector<Eigen::Vector3d> X, Xn;        // reference mid-surface nodes, unit directors
  std::vector<std::array<int, 4>> elements;  // counter-clockwise; a triangle's fourth node is -1
  BoundaryConditions bc;                     // on these nodes
};

// The problem's own quads, with the area-weighted vertex normals as directors.
SolidShellMesh solidShellMesh(const DrapeProblem& problem);

// Rigidities of an isotropic ShellMaterial for the solid shell (plane-stress enforcement: the
// thickness stretch gets E h, uncoupled from the in-plane strains).
SolidShellRigidity isotropicRigidity(const ShellMaterial& material);

// The assembled solid shell of a drape problem (seed 001 eqs. (9), (16), (19)): 6 unknowns per
// node (mid-surface position x_o, director x_n), constrained ones removed; gravity as lumped
// nodal weights; node-on-surface penalty contact of the mid-surface with the colliders (the
// smoothed penalty of the FEM shell); the lumped mass of the trapezoidal rule through the
// thickness, m for x_o and m h^2 / 4 for x_n.
class SolidShellModel {
 public:
  // centred_band: the penalty's rounding band straddles the surface (static solves) rather than
  // lying inside it (dynamics).
  SolidShellModel(const DrapeProblem& problem, ThicknessStrain thickness_strain, double mu,
                  double contact_stiffness, bool centred_band = true);
  // Material, gravity and colliders of the problem on another mesh (the adaptive mesh).
  SolidShellModel(const DrapeProblem& problem, SolidShellMesh mesh,
                  ThicknessStrain thickness_strain, double mu, double contact_stiffness,
                  bool centred_band = true);

  int size() const { return num_free_; }
  // Out-of-balance force R = P - F(D) - F_contact on the free unknowns and, if asked, the
  // tangent K = dF/dD (+ contact). Returns the strain energy.
  double assemble(Eigen::VectorXd& residual, Eigen::SparseMatrix<double>* tangent);
  // Total potential energy: strain energy, less load_factor times the work of the nodal weights
  // and loads, plus the penalty potential; its gradient is -residual (at load factor 1).
  double potentialEnergy(double load_factor) const;
  // The nodal weights and loads P on the free unknowns (the residual's load part).
  Eigen::VectorXd loadVector() const;
  // D += dD on the free unknowns (D: the displacements U_o, U_n).
  void increment(const Eigen::VectorXd& dD);
  // The largest move of a node's mid-surface point and of its director in an increment dD.
  std::pair<double, double> largestIncrement(const Eigen::VectorXd& dD) const;
  Eigen::VectorXd freeState() const;
  void setFreeState(const Eigen::VectorXd& D);
  // True for a free unknown of a mid-surface position (false: a director component).
  bool isTranslation(int i) const { return translation_[i]; }
  // Lumped mass of each free unknown (before mass scaling).
  const Eigen::VectorXd& mass() const { return mass_; }
  double loadNorm() const { return load_norm_; }  // |P|
  double lengthScale() const { return length_scale_; }
  int activeContacts() const { return active_contacts_; }

  std::vector<Eigen::Vector3d> positions() const;  // X_o + U_o
  std::vector<Eigen::Vector3d> directors() const;  // X_n + U_n
  // The nodal displacements U_o, U_n of every node (a node without element keeps its values).
  const std::vector<Eigen::Vector3d>& displacements() const { return u_; }
  const std::vector<Eigen::Vector3d>& directorDisplacements() const { return un_; }
  void setDisplacements(const std::vector<Eigen::Vector3d>& u,
                        const std::vector<Eigen::Vector3d>& un);
  // Whether an element uses the node.
  bool isActive(int node) const { return active_[node]; }
  const std::vector<SolidShellElement>& elements() const { return elements_; }
  SolidShellState elementState(int e) const;
  // Directors below the deformed mid-surface, summed over the elements' corners.
  int reversedDirectors() const;
  std::vector<ContactReaction> reactions() const;

 private:
  const DrapeProblem& problem_;
  std::vector<SolidShellElement> elements_;
  std::vector<Eigen::Vector3d> X_, Xn_;  // reference X_o, X_n
  std::vector<Eigen::Vector3d> u_, un_;  // displacements U_o, U_n
  std::vector<Eigen::Vector3d> weight_;
  std::vector<bool> active_;
  std::vector<int> dof_;  // 6 per node, -1 when constrained
  int num_free_ = 0;
  Eigen::VectorXd mass_;
  std::vector<bool> translation_;
  double load_norm_ = 0.0, length_scale_ = 1.0, k_contact_ = 0.0, smoothing_ = 0.0;
  int active_contacts_ = 0;
  bool centred_band_ = true;
  struct Penalty {
    double force, stiffness;
  };
  Penalty penalty(double gap) const;
  double penaltyEnergy(double gap) const;  // the integral of penalty(gap).force over penetration

  // Fixed sparsity of K and where each element entry lands (-1: constrained).
  Eigen::SparseMatrix<double> pattern_;
  std::vector<std::array<int, 576>> slots_;
  std::vector<std::array<int, 9>> node_slots_;  // the x_o block of each node (contact)
  std::vector<SolidShellVector> fe_;
  std::vector<SolidShellMatrix> Ke_;
  std::vector<double> ue_;
};

}  // namespace chs
