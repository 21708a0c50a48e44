// Colliders carried by frames (ColliderShape, PosedSurface) and moving obstacles in the
// particle dynamics (ParticleDynamics::setColliders): the pieces the ROS node poses from tf.
#include <cmath>
#include <memory>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/contact/collider_shape.h"
#include "cloth_hair_sim/core/contact/posed_surface.h"
#include "cloth_hair_sim/core/io/material_presets.h"
#include "cloth_hair_sim/core/mesh/grid_generators.h"
#include "cloth_hair_sim/core/particle/particle_dynamics.h"

namespace chs {
namespace {

Eigen::Isometry3d pose(const Eigen::Vector3d& t, double angle, const Eigen::Vector3d& axis) {
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  p.translate(t);
  p.rotate(Eigen::AngleAxisd(angle, axis.normalized()));
  return p;
}

TEST(PosedSurface, MatchesTheLocalSurfaceMovedRigidly) {
  auto box = std::make_shared<BoxSurface>(Eigen::Vector3d(-0.1, -0.2, -0.3),
                                          Eigen::Vector3d(0.1, 0.2, 0.3), 0.01);
  const Eigen::Isometry3d t = pose({0.5, -1.0, 2.0}, 0.7, {1.0, 2.0, 3.0});
  const PosedSurface posed(box, t);
  for (const Eigen::Vector3d& local :
       {Eigen::Vector3d(0.3, 0.05, 0.1), Eigen::Vector3d(0.0, 0.0, 0.35),
        Eigen::Vector3d(0.11, 0.21, 0.31), Eigen::Vector3d(0.02, -0.1, 0.0)}) {
    const SurfaceProjection a = box->project(local), b = posed.project(t * local);
    EXPECT_NEAR(a.gap, b.gap, 1e-12);
    EXPECT_LT((t.linear() * a.normal - b.normal).norm(), 1e-12);
    const Eigen::Matrix3d h = t.linear() * a.normal_gradient * t.linear().transpose();
    EXPECT_LT((h - b.normal_gradient).norm(), 1e-9);
  }
}

TEST(PosedSurface, NormalIsTheGradientOfTheGap) {
  auto sphere = std::make_shared<SphereSurface>(Eigen::Vector3d(0.1, 0.0, 0.0), 0.2);
  const PosedSurface posed(sphere, pose({1.0, 2.0, 3.0}, 1.1, {0.0, 1.0, 1.0}));
  const Eigen::Vector3d x(1.4, 2.1, 2.8);
  const double e = 1e-6;
  Eigen::Vector3d grad;
  for (int k = 0; k < 3; ++k) {
    Eigen::Vector3d d = Eigen::Vector3d::Zero();
    d[k] = e;
    grad[k] = (posed.project(x + d).gap - posed.project(x - d).gap) / (2 * e);
  }
  EXPECT_LT((grad - posed.project(x).normal).norm(), 1e-6);
}

TEST(PosedSurface, RefusesANonRigidPose) {
  auto plane = std::make_shared<PlaneSurface>(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ());
  Eigen::Isometry3d scaled = Eigen::Isometry3d::Identity();
  scaled.linear() *= 2.0;
  EXPECT_THROW(PosedSurface(plane, scaled), InputError);
  Eigen::Isometry3d nan = Eigen::Isometry3d::Identity();
  nan.translation().x() = std::nan("");
  EXPECT_THROW(PosedSurface(plane, nan), InputError);
  EXPECT_THROW(PosedSurface(nullptr, Eigen::Isometry3d::Identity()), InputError);
}

TEST(ColliderShape, TableTopFromFrameAndOffset) {
  // A table frame at its top face: the box hangs below it by the offset.
  ColliderShape table;
  table.type = parseColliderType("box");
  table.dimensions = {0.8, 0.6, 0.7};
  table.offset.translate(Eigen::Vector3d(0.0, 0.0, -0.35));
  const auto s = table.makeSurface(pose({1.0, 2.0, 0.7}, M_PI / 2, Eigen::Vector3d::UnitZ()));
  EXPECT_NEAR(s->project({1.0, 2.0, 0.75}).gap, 0.05, 1e-12);  // above the top
  EXPECT_LT((s->project({1.0, 2.0, 0.75}).normal - Eigen::Vector3d::UnitZ()).norm(), 1e-12);
  // Turned by 90 degrees: the 0.8 m side lies along world y.
  EXPECT_NEAR(s->project({1.0, 2.5, 0.5}).gap, 0.1, 1e-12);
  EXPECT_NEAR(s->project({1.4, 2.0, 0.5}).gap, 0.1, 1e-12);
  EXPECT_LT(s->project({1.0, 2.0, 0.5}).gap, 0.0);            // inside
  EXPECT_NEAR(s->project({1.0, 2.0, -0.1}).gap, 0.1, 1e-12);  // below the bottom
  table.edge_radius = 0.3;                                    // no room for such rounding
  EXPECT_THROW(table.validate(), InputError);
}

TEST(ColliderShape, CylinderAxisFollowsTheFrame) {
  ColliderShape c;
  c.type = parseColliderType("cylinder");
  c.dimensions = {0.1, 1.0};
  // Axis turned from z onto world x; the outer size holds with the default rounding.
  const auto s = c.makeSurface(pose(Eigen::Vector3d::Zero(), M_PI / 2, Eigen::Vector3d::UnitY()));
  EXPECT_NEAR(s->project({0.3, 0.0, 0.25}).gap, 0.15, 1e-12);
  EXPECT_NEAR(s->project({0.6, 0.0, 0.0}).gap, 0.1, 1e-12);
  EXPECT_NEAR(s->project({-0.6, 0.0, 0.0}).gap, 0.1, 1e-12);
}

TEST(ColliderShape, RefusesNonsense) {
  ColliderShape c;
  c.type = ColliderShape::Type::kSphere;
  EXPECT_THROW(c.validate(), InputError);  // no radius
  c.dimensions = {-1.0};
  EXPECT_THROW(c.validate(), InputError);
  c.dimensions = {std::nan("")};
  EXPECT_THROW(c.validate(), InputError);
  c.dimensions = {0.1};
  EXPECT_NO_THROW(c.validate());
  c.type = ColliderShape::Type::kBox;
  EXPECT_THROW(c.validate(), InputError);  // needs three sizes
  EXPECT_THROW(parseColliderType("cone"), InputError);
  EXPECT_EQ(colliderTypeName(parseColliderType("plane")), "plane");
}

TEST(ParticleDynamics, FollowsAMovedCollider) {
  // A small sheet resting on a plane; raising the plane lifts the sheet with it.
  DrapeProblem p;
  p.mesh = makeRectangleMesh(0.1, 0.1, 4, 4, Eigen::Vector3d(0.0, 0.0, 0.0));
  p.material = *materialPreset("cotton_eischen");
  ColliderShape floor;
  floor.type = ColliderShape::Type::kPlane;
  p.colliders = {floor.makeSurface(Eigen::Isometry3d::Identity())};
  ParticleDynamicsSettings settings;
  settings.damping = 5.0;
  ParticleDynamics d(p, settings);
  const double dt = d.stableTimeStep();
  for (int i = 0; i < 200; ++i) d.step(dt);
  EXPECT_NEAR(d.centreOfMass().z(), 0.0, 1e-5);

  d.setColliders({floor.makeSurface(pose({0.0, 0.0, 0.01}, 0.0, Eigen::Vector3d::UnitZ()))});
  EXPECT_EQ(d.colliders().size(), 1u);
  d.step(dt);
  for (const auto& x : d.positions()) EXPECT_GE(x.z(), 0.01 - 1e-9);
  EXPECT_THROW(d.setColliders({nullptr}), InputError);
}

}  // namespace
}  // namespace chs
