#pragma once
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "cloth_hair_sim/core/contact/rigid_surface.h"

namespace chs {

// A rigid obstacle described in the frame of the body that carries it (a robot link, a table),
// as in URDF collision geometry: the shape is centred on its own frame, which sits at `offset`
// in the carrying frame. Sizes in meters:
//   plane:    no dimensions; the half-space z < 0 of the shape frame is solid
//   sphere:   [radius]
//   box:      [size_x, size_y, size_z], full edge lengths
//   cylinder: [radius, length], axis along the shape frame's z
//   capsule:  [radius, length], the segment between the cap centres along z (as SDF and
//             urdfdom 4), so the solid spans length + 2 radius
// Boxes and cylinders get rounded edges inside that outer size (see BoxSurface): edge_radius < 0
// picks min(1 mm, smallest size / 100), as scene tables do.
struct ColliderShape {
  enum class Type { kPlane, kSphere, kBox, kCylinder, kCapsule };
  Type type = Type::kPlane;
  std::vector<double> dimensions;
  Eigen::Isometry3d offset = Eigen::Isometry3d::Identity();
  double edge_radius = -1.0;

  // Throws InputError naming the dimension or pose that makes no sense.
  void validate() const;
  // The obstacle in the world when the carrying frame is at world_from_frame.
  std::shared_ptr<const RigidSurface> makeSurface(const Eigen::Isometry3d& world_from_frame) const;
  // The edge rounding actually used (0 for planes, spheres and capsules).
  double effectiveEdgeRadius() const;
};

// Throws InputError for anything but plane | sphere | box | cylinder | capsule.
ColliderShape::Type parseColliderType(const std::string& name);
std::string colliderTypeName(ColliderShape::Type type);

}  // namespace chs
