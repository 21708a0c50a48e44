#pragma once
#include <array>

#include <Eigen/Core>

namespace chs {

// Rigidities of seed 001 eq. (7) in an element's material frame (x along the warp, or along the
// first element edge for an isotropic material), Voigt order (xx, yy, xy), engineering shear.
struct SolidShellRigidity {
  Eigen::Matrix3d membrane = Eigen::Matrix3d::Zero();  // C_m [N/m]
  Eigen::Matrix3d bending = Eigen::Matrix3d::Zero();   // C_b [N m]
  Eigen::Matrix2d shear = Eigen::Matrix2d::Zero();     // C_t [N/m], (gamma_zx, gamma_zy)
  double thickness = 0.0;                              // E_z [N/m] of the thickness stretch
};

// Thickness normal strain sampled at the nodes (eq. (5)): the Green strain of eq. (3),
// (|x_n|^2 - 1) / 2, or the quasi-engineering strain of eq. (24), +-|x_n| - 1, whose sign flips
// where the director points below the deformed mid-surface (n_p . d_p <= -mu).
enum class ThicknessStrain { kGreen, kQuasiEngineering };

// Element unknowns d of seed 001 eq. (1), Fig. 1(b): per node the mid-surface displacement U_o
// and the director displacement U_n (x_n = X_n + U_n, the top-minus-bottom vector over h), node
// after node: 24 entries (a triangle uses the first 18 and leaves the rest zero). Displacements,
// not positions, so that a solve resolves them to their own precision rather than to that of
// the coordinates.
using SolidShellVector = Eigen::Matrix<double, 24, 1>;
using SolidShellMatrix = Eigen::Matrix<double, 24, 24>;
using SolidShellState = std::array<Eigen::Vector3d, 8>;  // U_o1, U_n1, ..., U_o4, U_n4

// 4-node quadrilateral solid-shell element of seed 001 section 2, total Lagrangian:
//  - Green strains (2)-(3) with the z^2 terms of the in-plane and the z terms of the transverse
//    shear strains truncated: membrane, bending (z-linear) and transverse shear parts.
//  - ANS (4): transverse shear sampled at the edge midpoints against shear locking.
//  - ANS (5): thickness strain sampled at the nodes against trapezoidal locking.
//  - Plane-stress enforcement (7): membrane, bending, shear and thickness energies uncoupled, so
//    no Poisson coupling of the thickness stress locks bending (thickness locking).
//  - 2 x 2 Gauss quadrature with the mid-surface Jacobian J_o (8).
// Or the 3-node triangle of eqs. (10)-(15) (the building block of the adaptive mesh's
// macro-transition elements): linear shape functions in the area coordinates, ANS transverse
// shear sampled along the three edges at their midpoints (12), extrapolated to each node from the
// two edges meeting there (13) and interpolated (14); thickness strain sampled at the nodes (15);
// the three-point rule.
// Every strain of (3)-(5) is a quadratic form in the nodal vectors, so force and tangent (9) are
// exact: f = sum w J_o (dE/dd)^T C E, K = sum w J_o [(dE/dd)^T C dE/dd + sum_k (C E)_k d2E_k/dd2].
class SolidShellElement {
 public:
  // X: reference mid-surface nodes, Xn: unit reference directors, material_x: the material's
  // first axis (projected onto the element at each Gauss point).
  SolidShellElement(const std::array<int, 4>& nodes, const std::array<Eigen::Vector3d, 4>& X,
                    const std::array<Eigen::Vector3d, 4>& Xn, const Eigen::Vector3d& material_x,
                    const SolidShellRigidity& rigidity,
                    ThicknessStrain thickness_strain = ThicknessStrain::kGreen, double mu = 0.5);
  // The triangle (nodes counter-clockwise about the directors).
  SolidShellElement(const std::array<int, 3>& nodes, const std::array<Eigen::Vector3d, 3>& X,
                    const std::array<Eigen::Vector3d, 3>& Xn, const Eigen::Vector3d& material_x,
                    const SolidShellRigidity& rigidity,
                    ThicknessStrain thickness_strain = ThicknessStrain::kGreen, double mu = 0.5);

  int corners() const { return corners_; }  // 4 or 3
  // The element's nodes (a triangle's fourth is -1).
  const std::array<int, 4>& nodes() const { return nodes_; }
  // int N_i dA: lumped mid-surface weights.
  const std::array<double, 4>& nodalAreas() const { return nodal_area_; }
  // False if the reference element is degenerate or the material axis is normal to it.
  bool isValid() const { return valid_; }

  // Strain energy U_e; the force f = dU/dd and, if asked, K = df/dd.
  double evaluate(const SolidShellState& state, SolidShellVector* force,
                  SolidShellMatrix* tangent) const;
  // Mean |eps_b| (the bending strain of eq. (6), a curvature [1/m]) over the Gauss points:
  // the refinement indicator of eq. (25).
  double bendingStrainNorm(const SolidShellState& state) const;
  // Directors pointing below the deformed mid-surface (n_p . d_p < 0): interpenetration of the
  // top and bottom element surfaces (seed 001 section 4.3).
  int reversedDirectors(const SolidShellState& state) const;

 private:
  using Form = Eigen::Matrix<double, 8, 8>;  // v^T M v / 2 over the 8 nodal vectors
  struct GaussPoint {
    std::array<Form, 8> strain;  // Cartesian membrane (3), bending (3), transverse shear (2)
    std::array<Eigen::Matrix<double, 8, 3>, 8> reference;  // M V: strain gradients at rest
    std::array<double, 4> N{};
    double weight = 0.0;  // J_o
  };
  std::array<int, 4> nodes_;
  std::array<GaussPoint, 4> gauss_;
  Eigen::Matrix<double, 8, 3> reference_;  // X_o1, X_n1, ..., X_n4
  std::array<Eigen::Vector3d, 4> Xn_;
  SolidShellRigidity C_;
  ThicknessStrain thickness_strain_;
  double mu_;
  std::array<double, 4> nodal_area_{};
  bool valid_ = true;
  int corners_ = 4, num_gauss_ = 4;

  // Fills a quadrature point from its shape functions, mid-surface basis, rule weight and
  // Cartesian strain forms; false if the reference is degenerate there (J_o <= 0).
  bool setGaussPoint(GaussPoint& gp, const double N[4], const Eigen::Vector3d& G1,
                     const Eigen::Vector3d& G2, const Eigen::Vector3d& Gn, double rule_weight,
                     const std::array<Form, 8>& strains);

  // Deformed mid-surface edge from node p to node q.
  Eigen::Vector3d edge(const SolidShellState& s, int p, int q) const;
  // Nodal thickness strain e_p, its gradient and Hessian in x_n of node p.
  double thicknessStrain(const SolidShellState& s, int p, Eigen::Vector3d& grad,
                         Eigen::Matrix3d& hess) const;
};

}  // namespace chs
