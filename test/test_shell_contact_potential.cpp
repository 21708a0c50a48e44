// The continuum frictional contact model of Han section 5.3.3-5.3.4 against finite differences,
// its closed form and the Coulomb condition (5.27).
#include <cmath>
#include <cstdio>
#include <random>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/shell/contact_potential.h"

using namespace chs;

namespace {

ContactMaterial material() {
  ContactMaterial m;
  m.shear_stiffness = 300.0;
  m.normal_stiffness = 2000.0;
  m.friction = 0.4;
  return m;
}

}  // namespace

TEST(ContactPotential, GradientMatchesFiniteDifferences) {
  const ContactMaterial mat = material();
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-0.3, 0.3);
  double worst = 0.0;
  for (int trial = 0; trial < 20; ++trial) {
    Eigen::Vector3d a[3] = {Eigen::Vector3d(1.0 + u(rng), u(rng), u(rng)),
                            Eigen::Vector3d(u(rng), 0.8 + u(rng), u(rng)),
                            Eigen::Vector3d(u(rng), u(rng), 0.6 + u(rng))};
    const ContactEnergy e = contactEnergy(a[0], a[1], a[2], mat);
    const Eigen::Vector3d grads[3] = {e.d_a1, e.d_a2, e.d_a3};
    const double h = 1e-6;
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k < 3; ++k) {
        Eigen::Vector3d ap[3] = {a[0], a[1], a[2]}, am[3] = {a[0], a[1], a[2]};
        ap[c][k] += h;
        am[c][k] -= h;
        const double fd = (contactEnergy(ap[0], ap[1], ap[2], mat).chi -
                           contactEnergy(am[0], am[1], am[2], mat).chi) /
                          (2.0 * h);
        worst = std::max(worst, std::abs(fd - grads[c][k]) / (1.0 + std::abs(fd)));
      }
  }
  std::printf("[figure] contact energy gradient vs central differences: max rel error %.2e\n",
              worst);
  EXPECT_LT(worst, 1e-6);
}

TEST(ContactPotential, ClosedFormCompressionAndShear) {
  const ContactMaterial mat = material();
  const Eigen::Vector3d a1(2.0, 0.0, 0.0), a2(0.0, 0.5, 0.0);  // n = e_z whatever the stretch
  // Compressed to s3 = 0.7 with shear 0.1: chi = gamma/2 0.01 + k/3 0.3^3.
  const ContactEnergy e = contactEnergy(a1, a2, Eigen::Vector3d(0.1, 0.0, 0.7), mat);
  const double expected = 0.5 * 300.0 * 0.01 + 2000.0 / 3.0 * 0.027;
  std::printf("[figure] chi = %.6f (closed form %.6f)\n", e.chi, expected);
  EXPECT_NEAR(e.chi, expected, 1e-12 * expected);
  // Separation stores no normal energy.
  EXPECT_DOUBLE_EQ(contactEnergy(a1, a2, Eigen::Vector3d(0.0, 0.0, 1.3), mat).chi, 0.0);
  // The normal traction of (5.26) is f'(s3) s3 (compressive), the shear traction gamma s3 s_t.
  const Eigen::Matrix3d tau = contactKirchhoffStress(a1, a2, Eigen::Vector3d(0.1, 0.0, 0.7), mat);
  EXPECT_NEAR(tau(2, 2), -2000.0 * 0.09 * 0.7, 1e-9);
  EXPECT_NEAR(tau(0, 2), 300.0 * 0.7 * 0.1, 1e-9);
}

TEST(ContactPotential, ReturnMappingSatisfiesCoulomb) {
  const ContactMaterial mat = material();
  const Eigen::Vector3d a1(1.0, 0.0, 0.1), a2(0.0, 1.2, -0.2);
  const Eigen::Vector3d n = a1.cross(a2).normalized();
  const Eigen::Vector3d t = a1.normalized();
  double worst = 0.0;
  for (double s3 : {0.95, 0.8, 0.5}) {
    for (double shear : {1e-4, 0.05, 0.5}) {
      const Eigen::Vector3d trial = s3 * n + shear * t;
      bool yielded = false;
      const Eigen::Vector3d a3 = projectContactFibre(a1, a2, trial, mat, &yielded);
      const double bound = mat.friction * mat.normal_stiffness * (1 - s3) * (1 - s3) /
                           mat.shear_stiffness;  // Han (5.28)
      EXPECT_NEAR(a3.dot(n), s3, 1e-14);         // (5.29): s3 kept
      EXPECT_EQ(yielded, shear > bound);
      // Coulomb (5.27) on the Kirchhoff traction across the normal: |t_S| <= -c_F sigma_n.
      const Eigen::Vector3d traction = contactKirchhoffStress(a1, a2, a3, mat) * n;
      const double tn = traction.dot(n), ts = (traction - tn * n).norm();
      const double excess = ts + mat.friction * tn;  // <= 0, = 0 on the cone
      worst = std::max(worst, excess / std::abs(tn));
      if (yielded) {
        EXPECT_NEAR(excess / std::abs(tn), 0.0, 1e-12);
      }
    }
  }
  std::printf(
      "[figure] Coulomb condition after return mapping: max (|t_S| + c_F sigma_n)/|sigma_n|"
      " = %.2e (<= 0 inside, 0 on the cone)\n",
      worst);
  EXPECT_LE(worst, 1e-12);
  // Separating fibres are reset to the normal (5.29).
  const Eigen::Vector3d reset = projectContactFibre(a1, a2, 1.4 * n + 0.3 * t, mat);
  EXPECT_LT((reset - n).norm(), 1e-15);
}

TEST(ContactPotential, RejectsNonsenseMaterial) {
  ContactMaterial m = material();
  m.normal_stiffness = -1.0;
  EXPECT_THROW(m.validate(), InputError);
  m = material();
  m.friction = std::nan("");
  EXPECT_THROW(m.validate(), InputError);
  m = material();
  m.shear_stiffness = 0.0;
  EXPECT_THROW(m.validate(), InputError);
  EXPECT_NO_THROW(material().validate());
}
