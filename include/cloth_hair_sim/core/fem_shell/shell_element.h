#pragma once
#include <array>

#include <Eigen/Core>

#include "cloth_hair_sim/core/fem_shell/director_frame.h"
#include "cloth_hair_sim/core/material/shell_material.h"

namespace chs {

// Nodal unknowns of the geometrically exact shell (seed 000 eq. (1)): mid-surface position phi
// and unit director t, carried in its frame.
struct ShellNode {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  DirectorFrame frame;
};

// Element vectors and matrices in the 5 nodal unknowns (3 translations, 2 director increments
// through Lambda-bar): 20 per element.
using ElementVector = Eigen::Matrix<double, 20, 1>;
using ElementMatrix = Eigen::Matrix<double, 20, 20>;

// 4-node Simo-Fox shell quadrilateral (seed 000 Appendix A.4), 2x2 Gauss quadrature.
//  - Strains (3)-(5) with bilinear interpolation of positions and (unnormalised) directors.
//  - Transverse shear: assumed natural strain sampled at the edge midpoints (Bathe-Dvorkin /
//    MITC4, the assumed strain of Simo, Fox and Rifai 1989) against shear locking.
//  - Membrane: assumed natural strain too (eps_11 at the eta-edge midpoints, eps_22 at the
//    xi-edge midpoints, eps_12 at the centre). It has the same five strain parameters as the
//    five deformation modes of a flat element (no spurious modes) and frees the in-plane and
//    inextensional bending modes that lock a displacement-based bilinear membrane; this stands
//    in for the mixed membrane interpolation of Simo-Fox-Rifai.
//  - Resultants (8)-(14) in a local Cartesian frame of the reference surface; bending linear (9)
//    or Kawabata (A.25-A.34), the latter with its non-symmetric tangent (A.60-A.62).
//  - Tangent = material part (A.51-A.68) + geometric part (A.69-A.73) + the director term
//    -(f_t . t) I_2 that the exponential map contributes: exact linearisation of the force.
// evaluate() and energy() have a build for AVX2 and FMA chosen at run time (GCC's
// target_clones), the default build for any x86-64: the tablecloth's linearisation with its
// tangent took 1.60 ms instead of 1.87-1.96 (docs/BENCHMARKS.md, 2026-12-08).
class ShellElement {
 public:
  ShellElement(const std::array<int, 4>& nodes, const std::array<Eigen::Vector3d, 4>& X,
               const std::array<Eigen::Vector3d, 4>& T, const ShellMaterial& material);

  const std::array<int, 4>& nodes() const { return nodes_; }
  double area() const { return area_; }
  // Consistent nodal weights int N_I dA (gravity load).
  const std::array<double, 4>& nodalAreas() const { return nodal_area_; }

  // Internal force P (A.75) and tangent K; K is skipped if null.
  void evaluate(const std::array<const ShellNode*, 4>& state, ElementVector& force,
                ElementMatrix* tangent) const;
  // Strain energy, whose gradient is the internal force; NaN with Kawabata bending, whose
  // componentwise moment law (A.32)-(A.34) has none (its tangent is not symmetric).
  double energy(const std::array<const ShellNode*, 4>& state) const;

  // Largest |Jacobian ratio| distortion check: false if the reference element is degenerate.
  bool isValid() const { return valid_; }

 private:
  struct Reference;  // reference strains at Gauss and sampling points
  std::array<int, 4> nodes_;
  std::array<Eigen::Vector3d, 4> X_, T_;
  ShellMaterial material_;
  double area_ = 0.0;
  std::array<double, 4> nodal_area_{};
  bool valid_ = true;

  // Reference strain measures at the 4 Gauss and 5 sampling points, and the Cartesian transforms.
  struct PointRef {
    double aa[3];  // a1.a1, a2.a2, a1.a2
    double at[2];  // a_alpha . t
    double ak[3];  // a1.t,1, a2.t,2, a1.t,2 + a2.t,1
  };
  std::array<PointRef, 4> gauss_ref_;
  std::array<PointRef, 5> sample_ref_;    // A(0,-1) C(0,1) D(-1,0) B(1,0) centre(0,0)
  std::array<double, 4> gauss_weight_{};  // dA at each Gauss point
  std::array<Eigen::Matrix3d, 4> strain_to_cartesian_;
  std::array<Eigen::Matrix2d, 4> shear_to_cartesian_;
};

}  // namespace chs
