#pragma once
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "cloth_hair_sim/core/contact/mesh_sdf_surface.h"
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
//   mesh:     no dimensions; the closed triangle mesh in mesh_file, its coordinates in the shape
//             frame multiplied by mesh_scale per axis (0.001 for a file in mm), as a signed
//             distance field (MeshSdfSurface) with mesh_resolution
// Boxes and cylinders get rounded edges inside that outer size (see BoxSurface): edge_radius < 0
// picks min(1 mm, smallest size / 100), as scene tables do.
struct MeshFieldCache;

struct ColliderShape {
  enum class Type { kPlane, kSphere, kBox, kCylinder, kCapsule, kMesh };
  Type type = Type::kPlane;
  std::vector<double> dimensions;
  Eigen::Isometry3d offset = Eigen::Isometry3d::Identity();
  double edge_radius = -1.0;
  std::string mesh_file;  // a file path (URLs are resolved by the caller)
  Eigen::Vector3d mesh_scale = Eigen::Vector3d::Ones();
  // The file's nodes or meshes to keep (readTriangleMesh); empty: all of it.
  std::vector<std::string> mesh_parts;
  MeshSdfResolution mesh_resolution;

  // Throws InputError naming the dimension or pose that makes no sense.
  void validate() const;
  // The obstacle in the world when the carrying frame is at world_from_frame.
  std::shared_ptr<const RigidSurface> makeSurface(const Eigen::Isometry3d& world_from_frame) const;
  // The edge rounding actually used (0 for planes, spheres, capsules and meshes).
  double effectiveEdgeRadius() const;
  // A mesh's distance field in the shape frame, built on the first call (about a second for a
  // 10k-triangle mesh) and then reused, since makeSurface runs at every pose update; copies of
  // the shape share it. Built anew only if the file, scale or resolution changed. Throws
  // InputError for a shape that is not a valid mesh, naming the file and problem.
  std::shared_ptr<const MeshSdfSurface> meshField() const;

 private:
  std::shared_ptr<MeshFieldCache> mesh_cache_ = newMeshFieldCache();
  static std::shared_ptr<MeshFieldCache> newMeshFieldCache();
};

// Throws InputError for anything but plane | sphere | box | cylinder | capsule | mesh.
ColliderShape::Type parseColliderType(const std::string& name);
std::string colliderTypeName(ColliderShape::Type type);

}  // namespace chs
