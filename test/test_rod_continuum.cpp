// The strands' frictional contact as a granular continuum on the grid (Han (4.3)-(4.6),
// (4.10)-(4.11)): the cohesionless Drucker-Prager return (core/mpm/drucker_prager.h) against
// Mohr-Coulomb's closed form under triaxial compression, tension-free and elastic cases; then in
// the hair body (core/rod/hair_dynamics.h): bundles flying apart keep their speed exactly (no
// numerical cohesion), bundles flying into each other are stopped and thrown back without
// passing through (the audit of core/collision/segment_crossings.h) with linear momentum kept.
#include <cmath>
#include <cstdio>
#include <memory>
#include <random>

#include <gtest/gtest.h>
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <Eigen/LU>

#include "cloth_hair_sim/core/collision/segment_crossings.h"
#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/mpm/drucker_prager.h"
#include "cloth_hair_sim/core/rod/hair_dynamics.h"
#include "cloth_hair_sim/core/rod/strand_shapes.h"
#include "cloth_hair_sim/core/world/world.h"

namespace chs {
namespace {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

Mat3 randomRotation(std::mt19937& rng) {
  std::normal_distribution<double> n;
  return Eigen::Quaterniond(n(rng), n(rng), n(rng), n(rng)).normalized().toRotationMatrix();
}

// Principal Kirchhoff stresses of F, ascending (most compressive first).
Vec3 principalStresses(const mpm::HenckySolid& m, const Mat3& F) {
  Eigen::SelfAdjointEigenSolver<Mat3> eig(m.kirchhoffStress(F));
  return eig.eigenvalues();
}

TEST(DruckerPrager, TriaxialCompressionMeetsMohrCoulomb) {
  const mpm::HenckySolid material(1000.0, 0.3);
  std::mt19937 rng(7);
  for (double c_f : {0.1, 0.3, 0.6, 1.0}) {
    const mpm::DruckerPrager dp(material, c_f);
    const double s = std::sin(std::atan(c_f));
    const double expected = (1.0 + s) / (1.0 - s);  // sigma_1 / sigma_3 at yield
    // Axial compression well beyond the cone, the two lateral stretches equal.
    const Mat3 U = randomRotation(rng), V = randomRotation(rng);
    const Vec3 eps(-0.8, 0.2, 0.2);
    const Mat3 F = U * eps.array().exp().matrix().asDiagonal() * V.transpose();
    mpm::DruckerPrager::Case c;
    const Mat3 Fr = dp.project(F, &c);
    ASSERT_EQ(c, mpm::DruckerPrager::Case::kSlid);
    const Vec3 sig = principalStresses(material, Fr);
    const double ratio = sig(0) / sig(2);
    const double scale = std::abs(material.kirchhoffStress(Fr).trace());
    const double log_det = std::log(Fr.determinant()), trace_before = eps.sum();
    std::printf(
        "c_F %.1f: sigma_1 / sigma_3 = %.12f, Mohr-Coulomb %.12f (rel. %.1e); yield %.1e "
        "of |tr tau|; ln det kept to %.1e; lateral stresses %.6f / %.6f Pa\n",
        c_f, ratio, expected, ratio / expected - 1.0, dp.yield(Fr) / scale, log_det - trace_before,
        sig(1), sig(2));
    EXPECT_NEAR(ratio / expected, 1.0, 1e-10);
    EXPECT_NEAR(dp.yield(Fr) / scale, 0.0, 1e-12);
    EXPECT_NEAR(log_det, trace_before, 1e-12);  // the compression stays, the shear goes
    EXPECT_NEAR(sig(1), sig(2), 1e-9 * scale);  // the return keeps the stress state's shape
    // The rotations stay: the returned F has F's singular vectors.
    const Mat3 tau = material.kirchhoffStress(Fr), tau_trial = material.kirchhoffStress(F);
    EXPECT_LT((tau * tau_trial - tau_trial * tau).norm(), 1e-9 * tau.norm() * tau_trial.norm());
  }
}

TEST(DruckerPrager, TensionIsFreeAndTheConeElastic) {
  const mpm::HenckySolid material(1000.0, 0.3);
  const mpm::DruckerPrager dp(material, 0.3);
  std::mt19937 rng(11);
  const Mat3 U = randomRotation(rng), V = randomRotation(rng);
  auto F = [&](const Vec3& eps) {
    return Mat3(U * eps.array().exp().matrix().asDiagonal() * V.transpose());
  };
  mpm::DruckerPrager::Case c;
  // Expanded (even with one direction compressed): no stress, the rotation U V^T kept.
  const Mat3 separated = dp.project(F(Vec3(0.05, 0.01, -0.03)), &c);
  EXPECT_EQ(c, mpm::DruckerPrager::Case::kSeparated);
  EXPECT_LT((separated - U * V.transpose()).norm(), 1e-14);
  EXPECT_LT(material.kirchhoffStress(separated).norm(), 1e-10);
  // Compressed with a little shear, inside the cone: unchanged.
  const Mat3 inside = F(Vec3(-0.05, -0.045, -0.04));
  EXPECT_EQ(dp.project(inside, &c), inside);
  EXPECT_EQ(c, mpm::DruckerPrager::Case::kElastic);
  EXPECT_LT(dp.yield(inside), 0.0);
  // Frictionless strands: any shear slides, compression alone is elastic.
  const mpm::DruckerPrager smooth(material, 0.0);
  const Mat3 hydrostatic = F(Vec3(-0.02, -0.02, -0.02));
  EXPECT_LT((smooth.project(hydrostatic, &c) - hydrostatic).norm(), 1e-14);
  const Mat3 slid = smooth.project(F(Vec3(-0.05, -0.02, -0.02)), &c);
  EXPECT_EQ(c, mpm::DruckerPrager::Case::kSlid);
  const Vec3 sig = principalStresses(material, slid);
  EXPECT_NEAR(sig(0), sig(2), 1e-9 * std::abs(sig(0)));  // a pure pressure is left
}

TEST(DruckerPrager, BadInput) {
  const mpm::HenckySolid material(1000.0, 0.3);
  EXPECT_THROW(mpm::DruckerPrager(material, -0.1), InputError);
  EXPECT_THROW(mpm::DruckerPrager(material, std::nan("")), InputError);
  const mpm::DruckerPrager dp(material, 0.3);
  EXPECT_THROW(dp.project(Mat3::Zero()), InputError);
  EXPECT_THROW(dp.project(Vec3(1.0, 1.0, -1.0).asDiagonal().toDenseMatrix()), InputError);
  rod::HairSettings hs;
  hs.continuum.youngs_modulus = -1.0;
  try {
    rod::HairDynamics bad(hs);
    ADD_FAILURE() << "a negative modulus was taken";
  } catch (const InputError& e) {
    std::printf("refused: %s\n", e.what());
    EXPECT_NE(std::string(e.what()).find("strand continuum"), std::string::npos);
  }
  hs.continuum.youngs_modulus = 1000.0;
  hs.continuum.friction = -0.5;
  EXPECT_THROW(rod::HairDynamics{hs}, InputError);
}

// Two bundles of n x n free strands along x (4 cm of human hair, 16 segments, 1 mm apart),
// without gravity, one at z = 0 and one `gap` above it, given vertical speeds v_low and v_high.
struct Bundles {
  std::shared_ptr<rod::HairDynamics> hair;
  World world;
  std::vector<int> offsets{0};
  Bundles(bool continuum, double gap, double v_low, double v_high, double E = 1000.0,
          double dx = 0.01, bool crossed = false, int n = 3, double xi = 0.0,
          double contact_blend = 0.95)
      : world(worldSettings(dx)) {
    rod::HairSettings hs;
    hs.pic_blend = xi;
    hs.continuum.contact_blend = contact_blend;
    hs.continuum.youngs_modulus = E;
    hs.grid_spacing = dx;
    hs.gravity.setZero();
    hs.continuum.enabled = continuum;
    hair = std::make_shared<rod::HairDynamics>(hs);
    world.add("hair", hair);
    for (int level = 0; level < 2; ++level)
      for (int a = 0; a < n; ++a)
        for (int b = 0; b < n; ++b) {
          const bool along_y = crossed && level;
          const Vec3 root = along_y ? Vec3((a - 0.5 * (n - 1)) * 1e-3, -0.02,
                                           (b - 0.5 * (n - 1)) * 1e-3 + level * gap)
                                    : Vec3(-0.02, (a - 0.5 * (n - 1)) * 1e-3,
                                           (b - 0.5 * (n - 1)) * 1e-3 + level * gap);
          const int s = hair->addStrand(
              rod::straightStrand(root, along_y ? Vec3::UnitY() : Vec3::UnitX(), 0.04, 16),
              rod::humanHair(), false);
          hair->setVelocities(s, std::vector<Vec3>(hair->strand(s).numVertices(),
                                                   Vec3(0, 0, level ? v_high : v_low)));
          offsets.push_back(offsets.back() + hair->strand(s).numVertices());
        }
  }
  static WorldSettings worldSettings(double dx) {
    WorldSettings ws;
    ws.grid_spacing = dx;
    return ws;
  }
  std::vector<Vec3> positions() const {
    std::vector<Vec3> x;
    for (int s = 0; s < hair->numStrands(); ++s)
      x.insert(x.end(), hair->strand(s).positions().begin(), hair->strand(s).positions().end());
    return x;
  }
  // Mean vertical velocity of the lower (level 0) or upper bundle.
  double speed(int level) const {
    double v = 0.0;
    int count = 0;
    const int half = hair->numStrands() / 2;
    for (int s = level * half; s < (level + 1) * half; ++s)
      for (const Vec3& u : hair->velocities(s)) {
        v += u.z();
        ++count;
      }
    return v / count;
  }
};

// Bundles flying apart inside each other's kernels must keep their speed: a continuum with
// cohesion would pull them back. Returns the largest change of a vertex's velocity.
double flyingApart(double xi) {
  Bundles b(true, 0.004, -0.2, 0.2, 1000.0, 0.01, false, 3, xi);
  double worst = 0.0;
  for (int step = 0; step < 24; ++step) {
    b.world.step(1.0 / 240.0);
    for (int s = 0; s < b.hair->numStrands(); ++s)
      for (const Vec3& u : b.hair->velocities(s))
        worst = std::max(
            worst,
            (u - Vec3(0, 0, s < b.hair->numStrands() / 2 ? -0.2 : 0.2)).lpNorm<Eigen::Infinity>());
    if (xi == 0.0) {
      EXPECT_EQ(b.hair->lastContinuum().compressed, 0);
    }
  }
  if (xi == 0.0) {  // the bulk is left unstrained: F^E a rotation at every vertex
    for (int s = 0; s < b.hair->numStrands(); ++s)
      for (int i = 0; i < b.hair->strand(s).numVertices(); ++i) {
        const Mat3& F = b.hair->bulkDeformation(s, i);
        EXPECT_LT((F.transpose() * F - Mat3::Identity()).norm(), 1e-12);
      }
  }
  return worst;
}

TEST(HairContinuum, BundlesFlyingApartKeepTheirSpeed) {
  const double flip = flyingApart(0.0), pic = flyingApart(0.95);
  std::printf(
      "bundles 4 mm apart flying apart at 0.4 m/s for 0.1 s (dx 1 cm): largest change of "
      "a vertex velocity %.2e m/s at xi = 0, %.3f m/s at xi = 0.95 (the grid's averaging)\n",
      flip, pic);
  EXPECT_LT(flip, 1e-12);  // tension-free: the continuum adds nothing
}

// Two bundles of 8 x 8 strands (7 mm thick, dx 4 mm, crossed: the upper along y) 16 mm apart
// closing at 0.6 m/s, 0.25 s.
struct Collision {
  std::size_t crossings;
  double v_low, v_high, gap, k_ratio, p_err;
  int reset, substeps;
  long compressed, slid;  // vertex-steps pressed into other strands, of which sliding
};
Collision collide(bool continuum, double xi, double contact_blend) {
  Bundles b(continuum, 0.016, 0.3, -0.3, 1000.0, 0.004, true, 8, xi, contact_blend);
  const Vec3 p0 = b.hair->linearMomentum();
  const double k0 = b.hair->kineticEnergy();
  std::vector<Vec3> x0 = b.positions();
  Collision c{0, 0, 0, 0, 1.0, 0, 0, 0, 0, 0};
  for (int step = 0; step < 60; ++step) {
    b.world.step(1.0 / 240.0);
    const std::vector<Vec3> x1 = b.positions();
    c.crossings += countSegmentCrossings(x0, x1, b.offsets).count;
    x0 = x1;
    c.k_ratio = std::max(c.k_ratio, b.hair->kineticEnergy() / k0);
    c.p_err =
        std::max(c.p_err, (b.hair->linearMomentum() - p0).norm() / (0.3 * b.hair->totalMass()));
    c.reset += b.hair->lastContinuum().reset;
    c.compressed += b.hair->lastContinuum().compressed;
    c.slid += b.hair->lastContinuum().slid;
    c.substeps = std::max(c.substeps, b.hair->lastContinuum().substeps);
  }
  double z_low = 0.0, z_high = 0.0;
  const int half = b.hair->numStrands() / 2;
  for (int s = 0; s < b.hair->numStrands(); ++s)
    for (const Vec3& x : b.hair->strand(s).positions()) (s < half ? z_low : z_high) += x.z();
  c.gap = (z_high - z_low) / (half * b.hair->strand(0).numVertices());
  c.v_low = b.speed(0);
  c.v_high = b.speed(1);
  return c;
}

TEST(HairContinuum, BundlesFlyingTogetherBounceWithoutCrossing) {
  const Collision none = collide(false, 0.0, 0.0), pic = collide(false, 0.95, 0.95);
  const Collision flip = collide(true, 0.0, 0.0), han = collide(true, 0.95, 0.95);
  const Collision contact = collide(true, 0.0, 0.95);  // the continuum's default
  auto line = [](const char* what, const Collision& c) {
    std::printf(
        "  %-34s missed crossings %5zu, speeds after %+.3f / %+.3f m/s (+0.3 / -0.3 "
        "before), centres %+.1f mm apart, kinetic energy at most %.4f of the start, "
        "momentum kept to %.1e of m v, %d substeps, %d resets, %ld vertex-steps compressed "
        "(%ld sliding)\n",
        what, c.crossings, c.v_low, c.v_high, 1e3 * c.gap, c.k_ratio, c.p_err, c.substeps, c.reset,
        c.compressed, c.slid);
  };
  std::printf(
      "crossed bundles (2 x 64 strands, 7 mm thick, dx 4 mm) closing at 0.6 m/s, 0.25 s:\n");
  line("no continuum, xi = 0:", none);
  line("no continuum, xi = 0.95 (PIC):", pic);
  line("continuum, xi = 0:", flip);
  line("continuum, xi = 0.95 (Han):", han);
  line("continuum, xi = 0, 0.95 in contact:", contact);
  EXPECT_GT(none.crossings, 1000u);
  EXPECT_LT(none.gap, 0.0);  // they passed through
  // The grid sees the bulk's velocity, not each strand's within a cell: at xi = 0 (the default)
  // strands that interleave within a cell are invisible to it and pass on.
  EXPECT_GT(flip.crossings, 100u);
  // With Han's blend the continuum stops them and throws them back, momentum kept.
  EXPECT_EQ(han.crossings, 0u);
  EXPECT_LT(han.v_low, -0.05);
  EXPECT_GT(han.v_high, 0.05);
  EXPECT_GT(han.gap, 0.0);
  EXPECT_LE(han.k_ratio, 1.0 + 1e-9);  // a collision gains no energy
  EXPECT_LT(han.p_err, 1e-9);
  EXPECT_EQ(han.reset, 0);
  // The continuum's own blend at the default xi = 0: the same, without Han's blend everywhere.
  EXPECT_EQ(contact.crossings, 0u);
  EXPECT_LT(contact.v_low, -0.05);
  EXPECT_GT(contact.v_high, 0.05);
  EXPECT_GT(contact.gap, 0.0);
  EXPECT_LE(contact.k_ratio, 1.0 + 1e-9);
  EXPECT_LT(contact.p_err, 1e-9);
  EXPECT_EQ(contact.reset, 0);
  EXPECT_GT(contact.compressed, 0);
  EXPECT_EQ(none.compressed, 0);
}

// A strand alone is no contact: a clamped 10 cm hair swinging under gravity for 0.5 s (dx 1 cm,
// where its own vertices share every node) moves as without the continuum.
TEST(HairContinuum, StrandAloneIsUnchanged) {
  auto swing = [](bool continuum) {
    WorldSettings ws;
    ws.grid_spacing = 0.01;
    World world(ws);
    rod::HairSettings hs;
    hs.continuum.enabled = continuum;
    auto hair = std::make_shared<rod::HairDynamics>(hs);
    world.add("hair", hair);
    hair->addStrand(rod::straightStrand(Vec3(0, 0, 0.2), Vec3::UnitX(), 0.1, 40), rod::humanHair(),
                    true);
    for (int step = 0; step < 120; ++step) world.step(1.0 / 240.0);
    return hair->strand(0).positions();
  };
  const std::vector<Vec3> with = swing(true), without = swing(false);
  double worst = 0.0;
  for (std::size_t i = 0; i < with.size(); ++i)
    worst = std::max(worst, (with[i] - without[i]).norm());
  std::printf(
      "hair alone swinging 0.5 s: largest vertex distance with and without the continuum "
      "%.2e m (tip fell %.1f mm)\n",
      worst, 1e3 * (0.2 - with.back().z()));
  EXPECT_LT(worst, 1e-12);
}

}  // namespace
}  // namespace chs
