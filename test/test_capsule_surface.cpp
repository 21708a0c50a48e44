// CapsuleSurface and the capsule ColliderShape against closed-form distances: along the side the
// gap is the distance to the axis minus the radius, beyond the ends the distance to the cap
// centre minus the radius.
#include <cmath>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/contact/capsule_surface.h"
#include "cloth_hair_sim/core/contact/collider_shape.h"

namespace chs {
namespace {

// A capsule of radius 0.05 around the segment (0, 0, -0.1) .. (0, 0, 0.1).
const double kR = 0.05, kHalf = 0.1;
const CapsuleSurface kCapsule(Eigen::Vector3d(0, 0, -kHalf), Eigen::Vector3d(0, 0, kHalf), kR);

TEST(CapsuleSurface, SideGapIsTheDistanceToTheAxis) {
  for (const Eigen::Vector3d& x :
       {Eigen::Vector3d(0.2, 0.0, 0.0), Eigen::Vector3d(0.03, 0.04, 0.07),
        Eigen::Vector3d(-0.01, 0.02, -0.09)}) {
    const SurfaceProjection p = kCapsule.project(x);
    const double rho = std::hypot(x.x(), x.y());
    EXPECT_NEAR(p.gap, rho - kR, 1e-14);
    EXPECT_LT((p.normal - Eigen::Vector3d(x.x(), x.y(), 0.0) / rho).norm(), 1e-14);
  }
}

TEST(CapsuleSurface, CapGapIsTheDistanceToTheCapCentre) {
  const Eigen::Vector3d top(0, 0, kHalf), bottom(0, 0, -kHalf);
  for (const Eigen::Vector3d& x : {Eigen::Vector3d(0.0, 0.0, 0.3), Eigen::Vector3d(0.1, -0.05, 0.2),
                                   Eigen::Vector3d(0.01, 0.02, 0.12)}) {
    const SurfaceProjection p = kCapsule.project(x);
    EXPECT_NEAR(p.gap, (x - top).norm() - kR, 1e-14);
    EXPECT_LT((p.normal - (x - top).normalized()).norm(), 1e-14);
  }
  const Eigen::Vector3d below(0.02, 0.0, -0.2);
  EXPECT_NEAR(kCapsule.project(below).gap, (below - bottom).norm() - kR, 1e-14);
}

TEST(CapsuleSurface, InsideIsNegativeAndTheAxisHasAUnitNormal) {
  EXPECT_NEAR(kCapsule.project(Eigen::Vector3d(0.01, 0.0, 0.05)).gap, 0.01 - kR, 1e-14);
  const SurfaceProjection axis = kCapsule.project(Eigen::Vector3d(0.0, 0.0, 0.02));
  EXPECT_NEAR(axis.gap, -kR, 1e-14);
  EXPECT_NEAR(axis.normal.norm(), 1.0, 1e-14);
  EXPECT_NEAR(axis.normal.z(), 0.0, 1e-14);
}

// The normal is the gradient of the gap and its gradient the Hessian, on the side and on a cap.
TEST(CapsuleSurface, NormalAndNormalGradientAreDerivatives) {
  const CapsuleSurface tilted(Eigen::Vector3d(0.1, -0.2, 0.3), Eigen::Vector3d(0.4, 0.1, 0.2),
                              0.07);
  const double e = 1e-6;
  for (const Eigen::Vector3d& x : {Eigen::Vector3d(0.3, 0.0, 0.4), Eigen::Vector3d(0.6, 0.2, 0.2),
                                   Eigen::Vector3d(0.0, -0.3, 0.35)}) {
    const SurfaceProjection p = tilted.project(x);
    Eigen::Vector3d grad;
    Eigen::Matrix3d hess;
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d d = e * Eigen::Vector3d::Unit(k);
      const SurfaceProjection plus = tilted.project(x + d), minus = tilted.project(x - d);
      grad[k] = (plus.gap - minus.gap) / (2 * e);
      hess.col(k) = (plus.normal - minus.normal) / (2 * e);
    }
    EXPECT_LT((grad - p.normal).norm(), 1e-8);
    EXPECT_LT((hess - p.normal_gradient).norm(), 1e-5);
  }
}

TEST(CapsuleSurface, RefusesBadInput) {
  EXPECT_THROW(CapsuleSurface(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), 0.0), InputError);
  EXPECT_THROW(CapsuleSurface(Eigen::Vector3d::Constant(NAN), Eigen::Vector3d::UnitZ(), 0.1),
               InputError);
}

// The collider shape: [radius, length] along the shape frame's z, placed by offset and frame.
TEST(CapsuleCollider, FollowsOffsetAndFrame) {
  ColliderShape shape;
  shape.type = parseColliderType("capsule");
  shape.dimensions = {0.04, 0.3};
  shape.offset.translate(Eigen::Vector3d(0.0, 0.0, -0.15));  // a limb hanging below its joint
  Eigen::Isometry3d frame = Eigen::Isometry3d::Identity();
  frame.translate(Eigen::Vector3d(1.0, 2.0, 1.5));
  frame.rotate(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY()));  // limb along world -x
  const auto surface = shape.makeSurface(frame);
  // Limb axis from (1, 2, 1.5) to (0.7, 2, 1.5); a point 0.1 above its middle.
  EXPECT_NEAR(surface->project(Eigen::Vector3d(0.85, 2.0, 1.6)).gap, 0.1 - 0.04, 1e-12);
  // Beyond the far end, on the axis: 0.05 from the cap centre.
  EXPECT_NEAR(surface->project(Eigen::Vector3d(0.65, 2.0, 1.5)).gap, 0.05 - 0.04, 1e-12);
  EXPECT_EQ(colliderTypeName(shape.type), "capsule");
  EXPECT_DOUBLE_EQ(shape.effectiveEdgeRadius(), 0.0);
  shape.dimensions = {0.04};
  EXPECT_THROW(shape.validate(), InputError);
}

}  // namespace
}  // namespace chs
