#include "cloth_hair_sim/core/fem_shell/shell_element.h"

#include <cmath>
#include <limits>

#include <Eigen/Geometry>

namespace chs {

namespace {

using Vec24 = Eigen::Matrix<double, 24, 1>;
using Mat24 = Eigen::Matrix<double, 24, 24>;
using StrainB =
    Eigen::Matrix<double, 8, 24>;  // rows: eps11 eps22 2eps12 | gam1 gam2 | k11 k22 2k12
using Strain8 = Eigen::Matrix<double, 8, 1>;

constexpr double kNodeXi[4] = {-1.0, 1.0, 1.0, -1.0};
constexpr double kNodeEta[4] = {-1.0, -1.0, 1.0, 1.0};
const double kGauss = 1.0 / std::sqrt(3.0);
constexpr double kGaussXi[4] = {-1.0, 1.0, 1.0, -1.0};  // times kGauss
constexpr double kGaussEta[4] = {-1.0, -1.0, 1.0, 1.0};
// Assumed-strain sampling points: A(0,-1) C(0,1) carry eps11, gam1; D(-1,0) B(1,0) carry eps22,
// gam2; the centre carries 2 eps12.
constexpr double kSampleXi[5] = {0.0, 0.0, -1.0, 1.0, 0.0};
constexpr double kSampleEta[5] = {-1.0, 1.0, 0.0, 0.0, 0.0};
enum Sample { kA = 0, kC = 1, kD = 2, kB = 3, kCentre = 4 };

// Bilinear shape functions (A.44) and their parent derivatives.
struct Shape {
  double N[4];
  double dN[2][4];
};

Shape shapeAt(double xi, double eta) {
  Shape s;
  for (int I = 0; I < 4; ++I) {
    s.N[I] = 0.25 * (1 + xi * kNodeXi[I]) * (1 + eta * kNodeEta[I]);
    s.dN[0][I] = 0.25 * kNodeXi[I] * (1 + eta * kNodeEta[I]);
    s.dN[1][I] = 0.25 * kNodeEta[I] * (1 + xi * kNodeXi[I]);
  }
  return s;
}

// Mid-surface base vectors a_alpha (A.45), interpolated director and its derivatives.
struct Kinematics {
  Eigen::Vector3d a[2], t, dt[2];
};

Kinematics kinematicsAt(const Shape& s, const std::array<Eigen::Vector3d, 4>& x,
                        const std::array<Eigen::Vector3d, 4>& d) {
  Kinematics k;
  for (int al = 0; al < 2; ++al) k.a[al].setZero(), k.dt[al].setZero();
  k.t.setZero();
  for (int I = 0; I < 4; ++I) {
    k.t += s.N[I] * d[I];
    for (int al = 0; al < 2; ++al) {
      k.a[al] += s.dN[al][I] * x[I];
      k.dt[al] += s.dN[al][I] * d[I];
    }
  }
  return k;
}

// The strain measures (3)-(5) before subtracting the reference, Voigt order of StrainB.
Strain8 measuresAt(const Kinematics& k) {
  Strain8 m;
  m << 0.5 * k.a[0].squaredNorm(), 0.5 * k.a[1].squaredNorm(), k.a[0].dot(k.a[1]), k.a[0].dot(k.t),
      k.a[1].dot(k.t), k.a[0].dot(k.dt[0]), k.a[1].dot(k.dt[1]),
      k.a[0].dot(k.dt[1]) + k.a[1].dot(k.dt[0]);
  return m;
}

// First variation of the measures with respect to the 24 ambient unknowns (phi_I, t_I):
// the B matrices (A.65)-(A.68) before the director projection.
StrainB variationAt(const Shape& s, const Kinematics& k) {
  StrainB B = StrainB::Zero();
  for (int I = 0; I < 4; ++I) {
    const int p = 6 * I, q = 6 * I + 3;
    const double N = s.N[I], N1 = s.dN[0][I], N2 = s.dN[1][I];
    B.block<1, 3>(0, p) = N1 * k.a[0].transpose();
    B.block<1, 3>(1, p) = N2 * k.a[1].transpose();
    B.block<1, 3>(2, p) = (N1 * k.a[1] + N2 * k.a[0]).transpose();
    B.block<1, 3>(3, p) = N1 * k.t.transpose();
    B.block<1, 3>(3, q) = N * k.a[0].transpose();
    B.block<1, 3>(4, p) = N2 * k.t.transpose();
    B.block<1, 3>(4, q) = N * k.a[1].transpose();
    B.block<1, 3>(5, p) = N1 * k.dt[0].transpose();
    B.block<1, 3>(5, q) = N1 * k.a[0].transpose();
    B.block<1, 3>(6, p) = N2 * k.dt[1].transpose();
    B.block<1, 3>(6, q) = N2 * k.a[1].transpose();
    B.block<1, 3>(7, p) = (N1 * k.dt[1] + N2 * k.dt[0]).transpose();
    B.block<1, 3>(7, q) = (N2 * k.a[0] + N1 * k.a[1]).transpose();
  }
  return B;
}

// Adds sum_r c_r * (second variation of measure r) at a point (A.70)-(A.72). The measures are
// quadratic in (phi, t), so this depends on the shape functions only.
void addSecondVariation(const Shape& s, const Strain8& c, Mat24& K) {
  for (int I = 0; I < 4; ++I)
    for (int J = 0; J < 4; ++J) {
      const double I1 = s.dN[0][I], I2 = s.dN[1][I], J1 = s.dN[0][J], J2 = s.dN[1][J];
      const double pp = c[0] * I1 * J1 + c[1] * I2 * J2 + c[2] * (I1 * J2 + I2 * J1);
      const double pt = c[3] * I1 * s.N[J] + c[4] * I2 * s.N[J] + c[5] * I1 * J1 + c[6] * I2 * J2 +
                        c[7] * (I1 * J2 + I2 * J1);
      for (int k = 0; k < 3; ++k) {
        K(6 * I + k, 6 * J + k) += pp;
        K(6 * I + k, 6 * J + 3 + k) += pt;
        K(6 * J + 3 + k, 6 * I + k) += pt;
      }
    }
}

// Voigt transform of covariant strain components (engineering shear) to a Cartesian frame
// e_i: eps_ij = eps_ab c_ai c_bj with c_ai = A^a . e_i.
Eigen::Matrix3d voigtTransform(const Eigen::Matrix2d& c) {
  Eigen::Matrix3d T;
  T << c(0, 0) * c(0, 0), c(1, 0) * c(1, 0), c(0, 0) * c(1, 0),  //
      c(0, 1) * c(0, 1), c(1, 1) * c(1, 1), c(0, 1) * c(1, 1),   //
      2 * c(0, 0) * c(0, 1), 2 * c(1, 0) * c(1, 1), c(0, 0) * c(1, 1) + c(1, 0) * c(0, 1);
  return T;
}

}  // namespace

ShellElement::ShellElement(const std::array<int, 4>& nodes, const std::array<Eigen::Vector3d, 4>& X,
                           const std::array<Eigen::Vector3d, 4>& T, const ShellMaterial& material)
    : nodes_(nodes), X_(X), T_(T), material_(material) {
  for (int g = 0; g < 4; ++g) {
    const Shape s = shapeAt(kGauss * kGaussXi[g], kGauss * kGaussEta[g]);
    const Kinematics k = kinematicsAt(s, X_, T_);
    const Strain8 m = measuresAt(k);
    for (int r = 0; r < 3; ++r) gauss_ref_[g].aa[r] = m[r], gauss_ref_[g].ak[r] = m[5 + r];
    for (int r = 0; r < 2; ++r) gauss_ref_[g].at[r] = m[3 + r];
    const Eigen::Vector3d n = k.a[0].cross(k.a[1]);
    const double j = n.norm();
    if (!(j > 0.0) || n.dot(k.t) <= 0.0) valid_ = false;
    gauss_weight_[g] = j;
    area_ += j;
    for (int I = 0; I < 4; ++I) nodal_area_[I] += s.N[I] * j;
    // Local Cartesian frame of the reference surface: e1 along A_1, e2 in the tangent plane.
    const Eigen::Vector3d e1 = k.a[0].normalized();
    const Eigen::Vector3d e2 = n.normalized().cross(e1);
    Eigen::Matrix2d metric;
    metric << k.a[0].dot(k.a[0]), k.a[0].dot(k.a[1]), k.a[1].dot(k.a[0]), k.a[1].dot(k.a[1]);
    const Eigen::Matrix2d inv =
        valid_ ? Eigen::Matrix2d(metric.inverse()) : Eigen::Matrix2d::Identity();
    const Eigen::Vector3d A_up[2] = {inv(0, 0) * k.a[0] + inv(0, 1) * k.a[1],
                                     inv(1, 0) * k.a[0] + inv(1, 1) * k.a[1]};  // (A.6)
    Eigen::Matrix2d c;
    for (int al = 0; al < 2; ++al) c(al, 0) = A_up[al].dot(e1), c(al, 1) = A_up[al].dot(e2);
    strain_to_cartesian_[g] = voigtTransform(c);
    shear_to_cartesian_[g] = c.transpose();
  }
  for (int p = 0; p < 5; ++p) {
    const Strain8 m = measuresAt(kinematicsAt(shapeAt(kSampleXi[p], kSampleEta[p]), X_, T_));
    for (int r = 0; r < 3; ++r) sample_ref_[p].aa[r] = m[r], sample_ref_[p].ak[r] = m[5 + r];
    for (int r = 0; r < 2; ++r) sample_ref_[p].at[r] = m[3 + r];
  }
}

__attribute__((target_clones("arch=x86-64-v3", "default"), flatten)) void ShellElement::evaluate(
    const std::array<const ShellNode*, 4>& state, ElementVector& force,
    ElementMatrix* tangent) const {
  std::array<Eigen::Vector3d, 4> x, d;
  for (int I = 0; I < 4; ++I) x[I] = state[I]->position, d[I] = state[I]->frame.director();

  // Measures and their variations at the assumed-strain sampling points.
  Strain8 sample_strain[5];
  StrainB sample_B[5];
  Shape sample_shape[5];
  for (int p = 0; p < 5; ++p) {
    sample_shape[p] = shapeAt(kSampleXi[p], kSampleEta[p]);
    const Kinematics k = kinematicsAt(sample_shape[p], x, d);
    sample_strain[p] = measuresAt(k);
    for (int r = 0; r < 3; ++r) sample_strain[p][r] -= sample_ref_[p].aa[r];
    for (int r = 0; r < 2; ++r) sample_strain[p][3 + r] -= sample_ref_[p].at[r];
    sample_B[p] = variationAt(sample_shape[p], k);
  }

  const ShellMaterial& mat = material_;
  const double nu = mat.poisson, h = mat.thickness;
  Eigen::Matrix3d plane_stress;  // C/E in a Cartesian frame, eq. (11) with a^0 = I
  plane_stress << 1, nu, 0, nu, 1, 0, 0, 0, 0.5 * (1 - nu);
  plane_stress /= 1 - nu * nu;
  const double shear_stiffness = mat.shear_correction * mat.shearModulus() * h;  // (10), (12)

  Vec24 f = Vec24::Zero();
  Mat24 K = Mat24::Zero();
  // The material part (A.64), sum over the Gauss points of B^T (dA D) B, as one product of the
  // four points' B stacked (32 x 24) with their D B: its entries are dot products of 32 (four
  // vector registers) where one point at a time made them of 8 and paid a horizontal sum for
  // each. Only its upper triangle where D is symmetric (Kawabata's tangent (A.60)-(A.62) is not).
  Eigen::Matrix<double, 32, 24> B_stack, DB_stack;
  const bool symmetric_material = !material_.kawabata;
  Strain8 sample_coeff[5];
  for (auto& c : sample_coeff) c.setZero();

  for (int g = 0; g < 4; ++g) {
    const double xi = kGauss * kGaussXi[g], eta = kGauss * kGaussEta[g];
    const Shape s = shapeAt(xi, eta);
    const Kinematics k = kinematicsAt(s, x, d);
    const Strain8 m = measuresAt(k);
    const StrainB Bg = variationAt(s, k);
    // Assumed-strain interpolation weights of the sampling points at this Gauss point.
    const double wA = 0.5 * (1 - eta), wC = 0.5 * (1 + eta), wD = 0.5 * (1 - xi),
                 wB = 0.5 * (1 + xi);
    Strain8 e;
    StrainB B;
    e[0] = wA * sample_strain[kA][0] + wC * sample_strain[kC][0];
    B.row(0) = wA * sample_B[kA].row(0) + wC * sample_B[kC].row(0);
    e[1] = wD * sample_strain[kD][1] + wB * sample_strain[kB][1];
    B.row(1) = wD * sample_B[kD].row(1) + wB * sample_B[kB].row(1);
    e[2] = sample_strain[kCentre][2];
    B.row(2) = sample_B[kCentre].row(2);
    e[3] = wA * sample_strain[kA][3] + wC * sample_strain[kC][3];
    B.row(3) = wA * sample_B[kA].row(3) + wC * sample_B[kC].row(3);
    e[4] = wD * sample_strain[kD][4] + wB * sample_strain[kB][4];
    B.row(4) = wD * sample_B[kD].row(4) + wB * sample_B[kB].row(4);
    for (int r = 0; r < 3; ++r) e[5 + r] = m[5 + r] - gauss_ref_[g].ak[r];
    B.bottomRows<3>() = Bg.bottomRows<3>();

    // Resultants (8)-(10) in the Cartesian frame, pulled back to the covariant strain measures.
    const Eigen::Matrix3d& Tm = strain_to_cartesian_[g];
    const Eigen::Matrix2d& Ts = shear_to_cartesian_[g];
    Eigen::Matrix<double, 8, 8> D = Eigen::Matrix<double, 8, 8>::Zero();
    Strain8 sigma;
    const Eigen::Matrix3d Dm = mat.young * h * plane_stress;
    D.topLeftCorner<3, 3>() = Tm.transpose() * Dm * Tm;
    D.block<2, 2>(3, 3) = shear_stiffness * Ts.transpose() * Ts;
    const Eigen::Vector3d kc = Tm * e.tail<3>();  // Cartesian curvatures, engineering twist
    if (mat.kawabata) {
      // Seed 000 (A.32)-(A.34): m = (C/E) f(kappa) componentwise; tangent (A.60)-(A.62).
      const Eigen::Vector3d fk(mat.kawabata->moment(kc[0]), mat.kawabata->moment(kc[1]),
                               mat.kawabata->moment(kc[2]));
      const Eigen::Vector3d dfk(mat.kawabata->stiffness(kc[0]), mat.kawabata->stiffness(kc[1]),
                                mat.kawabata->stiffness(kc[2]));
      sigma.tail<3>() = Tm.transpose() * (plane_stress * fk);
      D.bottomRightCorner<3, 3>() = Tm.transpose() * plane_stress * dfk.asDiagonal() * Tm;
    } else {
      const Eigen::Matrix3d Db = mat.young * h * h * h / 12.0 * plane_stress;  // (9)
      D.bottomRightCorner<3, 3>() = Tm.transpose() * Db * Tm;
      sigma.tail<3>() = D.bottomRightCorner<3, 3>() * e.tail<3>();
    }
    sigma.head<5>() = D.topLeftCorner<5, 5>() * e.head<5>();

    const double dA = gauss_weight_[g];
    f.noalias() += dA * B.transpose() * sigma;  // (A.75)
    if (tangent) {
      // D is block diagonal (membrane, transverse shear, bending).
      B_stack.middleRows<8>(8 * g) = B;
      auto DB = DB_stack.middleRows<8>(8 * g);
      DB.topRows<3>().noalias() = (dA * D.topLeftCorner<3, 3>()).lazyProduct(B.topRows<3>());
      DB.middleRows<2>(3).noalias() = (dA * D.block<2, 2>(3, 3)).lazyProduct(B.middleRows<2>(3));
      DB.bottomRows<3>().noalias() =
          (dA * D.bottomRightCorner<3, 3>()).lazyProduct(B.bottomRows<3>());
      // Geometric part (A.69): the resultants weight the second variations at the points
      // where each strain is sampled.
      const Strain8 c = dA * sigma;
      sample_coeff[kA][0] += wA * c[0], sample_coeff[kC][0] += wC * c[0];
      sample_coeff[kD][1] += wD * c[1], sample_coeff[kB][1] += wB * c[1];
      sample_coeff[kCentre][2] += c[2];
      sample_coeff[kA][3] += wA * c[3], sample_coeff[kC][3] += wC * c[3];
      sample_coeff[kD][4] += wD * c[4], sample_coeff[kB][4] += wB * c[4];
      Strain8 bending = Strain8::Zero();
      bending.tail<3>() = c.tail<3>();
      addSecondVariation(s, bending, K);
    }
  }
  if (tangent) {
    for (int p = 0; p < 5; ++p) addSecondVariation(sample_shape[p], sample_coeff[p], K);
    // As dot products: Eigen's product sends the 24 x 32 x 24 through its packed GEMM kernel,
    // slower at this size.
    for (int j = 0; j < 24; ++j)
      for (int i = 0; i < (symmetric_material ? j + 1 : 24); ++i) {
        const double k = B_stack.col(i).dot(DB_stack.col(j));
        K(i, j) += k;
        if (symmetric_material && i != j) K(j, i) += k;
      }
  }

  // Project the director unknowns onto Lambda-bar: delta t_I = Lambda-bar_I delta T_I (A.48).
  for (int I = 0; I < 4; ++I) {
    const Eigen::Matrix<double, 3, 2> L = state[I]->frame.basis();
    force.segment<3>(5 * I) = f.segment<3>(6 * I);
    force.segment<2>(5 * I + 3) = L.transpose() * f.segment<3>(6 * I + 3);
  }
  if (!tangent) return;
  ElementMatrix& Kr = *tangent;
  for (int I = 0; I < 4; ++I) {
    const Eigen::Matrix<double, 3, 2> LI = state[I]->frame.basis();
    for (int J = 0; J < 4; ++J) {
      const Eigen::Matrix<double, 3, 2> LJ = state[J]->frame.basis();
      Kr.block<3, 3>(5 * I, 5 * J) = K.block<3, 3>(6 * I, 6 * J);
      Kr.block<3, 2>(5 * I, 5 * J + 3) = K.block<3, 3>(6 * I, 6 * J + 3) * LJ;
      Kr.block<2, 3>(5 * I + 3, 5 * J) = LI.transpose() * K.block<3, 3>(6 * I + 3, 6 * J);
      Kr.block<2, 2>(5 * I + 3, 5 * J + 3) =
          LI.transpose() * K.block<3, 3>(6 * I + 3, 6 * J + 3) * LJ;
    }
    // Exponential map, second order: d2 t / dT_a dT_b = -delta_ab t (step 4.5, eq. (A.40)).
    Kr.block<2, 2>(5 * I + 3, 5 * I + 3) -=
        f.segment<3>(6 * I + 3).dot(d[I]) * Eigen::Matrix2d::Identity();
  }
}

__attribute__((target_clones("arch=x86-64-v3", "default"), flatten)) double ShellElement::energy(
    const std::array<const ShellNode*, 4>& state) const {
  if (material_.kawabata) return std::numeric_limits<double>::quiet_NaN();
  std::array<Eigen::Vector3d, 4> x, d;
  for (int I = 0; I < 4; ++I) x[I] = state[I]->position, d[I] = state[I]->frame.director();
  Strain8 sample_strain[5];
  for (int p = 0; p < 5; ++p) {
    sample_strain[p] = measuresAt(kinematicsAt(shapeAt(kSampleXi[p], kSampleEta[p]), x, d));
    for (int r = 0; r < 3; ++r) sample_strain[p][r] -= sample_ref_[p].aa[r];
    for (int r = 0; r < 2; ++r) sample_strain[p][3 + r] -= sample_ref_[p].at[r];
  }
  const ShellMaterial& mat = material_;
  const double nu = mat.poisson, h = mat.thickness;
  Eigen::Matrix3d plane_stress;
  plane_stress << 1, nu, 0, nu, 1, 0, 0, 0, 0.5 * (1 - nu);
  plane_stress /= 1 - nu * nu;
  const double shear_stiffness = mat.shear_correction * mat.shearModulus() * h;
  double W = 0.0;
  for (int g = 0; g < 4; ++g) {
    const double xi = kGauss * kGaussXi[g], eta = kGauss * kGaussEta[g];
    const Strain8 m = measuresAt(kinematicsAt(shapeAt(xi, eta), x, d));
    const double wA = 0.5 * (1 - eta), wC = 0.5 * (1 + eta), wD = 0.5 * (1 - xi),
                 wB = 0.5 * (1 + xi);
    // The same assumed strains as evaluate(): W = 1/2 e . D e, whose gradient is (A.75).
    const Eigen::Vector3d membrane(wA * sample_strain[kA][0] + wC * sample_strain[kC][0],
                                   wD * sample_strain[kD][1] + wB * sample_strain[kB][1],
                                   sample_strain[kCentre][2]);
    const Eigen::Vector2d shear(wA * sample_strain[kA][3] + wC * sample_strain[kC][3],
                                wD * sample_strain[kD][4] + wB * sample_strain[kB][4]);
    Eigen::Vector3d bending;
    for (int r = 0; r < 3; ++r) bending[r] = m[5 + r] - gauss_ref_[g].ak[r];
    const Eigen::Vector3d em = strain_to_cartesian_[g] * membrane;
    const Eigen::Vector3d kc = strain_to_cartesian_[g] * bending;
    const Eigen::Vector2d gc = shear_to_cartesian_[g] * shear;
    W += 0.5 * gauss_weight_[g] * mat.young * h *
         (em.dot(plane_stress * em) + h * h / 12.0 * kc.dot(plane_stress * kc) +
          shear_stiffness / (mat.young * h) * gc.squaredNorm());
  }
  return W;
}

}  // namespace chs
