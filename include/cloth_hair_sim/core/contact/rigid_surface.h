#pragma once
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace chs {

// Closest-point query of a point against a rigid obstacle.
struct SurfaceProjection {
  double gap = 0.0;                                   // signed distance, < 0 inside
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  // outward unit normal (gradient of gap)
  Eigen::Matrix3d normal_gradient = Eigen::Matrix3d::Zero();  // d normal / d x (Hessian of gap)
};

// A rigid, frictionless obstacle given by its signed distance: the contact surfaces of seed 000
// section 2.2.2 (plane, table, pedestal, sphere). The Hessian makes the penalty tangent
// consistent where the normal turns (table edges, sphere, cylinder side).
class RigidSurface {
 public:
  virtual ~RigidSurface() = default;
  virtual SurfaceProjection project(const Eigen::Vector3d& x) const = 0;
  virtual std::string describe() const = 0;
};

using RigidSurfaces = std::vector<std::shared_ptr<const RigidSurface>>;

// Half-space {(x - point) . normal < 0} is solid.
class PlaneSurface : public RigidSurface {
 public:
  PlaneSurface(const Eigen::Vector3d& point, const Eigen::Vector3d& normal);
  SurfaceProjection project(const Eigen::Vector3d& x) const override;
  std::string describe() const override;

 private:
  Eigen::Vector3d point_, normal_;
};

// Axis-aligned solid box: a table is a box whose top face carries the cloth. The flat top covers
// exactly [min, max] in x and y at z = max.z; the edges are rounded with edge_radius beyond that
// footprint (the solid is the box [min, max - r e_z] grown by r). At a sharp corner the nearest
// face flips between top and side, and a node-on-surface penalty then pushes a node resting on
// the edge sideways off the table; the rounding makes the normal continuous.
class BoxSurface : public RigidSurface {
 public:
  BoxSurface(const Eigen::Vector3d& min_corner, const Eigen::Vector3d& max_corner,
             double edge_radius = 0.0);
  SurfaceProjection project(const Eigen::Vector3d& x) const override;
  std::string describe() const override;

 private:
  Eigen::Vector3d lo_, hi_;  // the box that grown by radius_ gives the solid
  double radius_;
};

// Solid vertical cylinder (a disc pedestal): axis along z through (cx, cy); the flat top disc of
// radius r lies at z_top, and the rim is rounded with edge_radius beyond it, as for BoxSurface.
class CylinderSurface : public RigidSurface {
 public:
  CylinderSurface(const Eigen::Vector2d& center_xy, double radius, double z_bottom, double z_top,
                  double edge_radius = 0.0);
  SurfaceProjection project(const Eigen::Vector3d& x) const override;
  std::string describe() const override;

 private:
  Eigen::Vector2d c_;
  double r_, zb_, zt_, edge_;  // zt_: top of the inner cylinder that grown by edge_ is the solid
};

class SphereSurface : public RigidSurface {
 public:
  SphereSurface(const Eigen::Vector3d& center, double radius);
  SurfaceProjection project(const Eigen::Vector3d& x) const override;
  std::string describe() const override;

 private:
  Eigen::Vector3d c_;
  double r_;
};

}  // namespace chs
