#pragma once
#include <array>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "cloth_hair_sim/core/contact/mesh_sdf_surface.h"
#include "cloth_hair_sim/core/contact/rigid_surface.h"

namespace chs {

// The geometry of a scene's rigid obstacle as written in the scene file. Kept next to the
// RigidSurface built from it because the surfaces expose no geometry, and pictures need it.
struct ColliderSpec {
  enum class Type { kPlane, kBox, kCylinder, kSphere, kCapsule, kMesh };
  Type type = Type::kPlane;
  std::string label;  // as named in the scene: plane, table, box, pedestal, cylinder, sphere,
                      // capsule, mesh
  Eigen::Vector3d point = Eigen::Vector3d::Zero();    // plane: a point; sphere: centre
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  // plane: outward normal
  Eigen::Vector3d lo = Eigen::Vector3d::Zero(), hi = Eigen::Vector3d::Zero();  // box corners
  Eigen::Vector2d axis_xy = Eigen::Vector2d::Zero();  // cylinder axis position
  Eigen::Vector3d end_a = Eigen::Vector3d::Zero(), end_b = Eigen::Vector3d::Zero();  // capsule
  double radius = 0.0;                 // cylinder, sphere, capsule
  double z_bottom = 0.0, z_top = 0.0;  // cylinder
  double edge_radius = 0.0;            // box, cylinder: rounded edges
  // mesh: the distance field in the mesh's own (scaled) frame, placed in the world by pose.
  std::string mesh_file;
  std::shared_ptr<const MeshSdfSurface> mesh_field;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();

  std::shared_ptr<const RigidSurface> makeSurface() const;
};

// Quads approximating the obstacle's surface down to z_floor, for pictures only (planes give a
// square of half-size extent around point; a mesh's triangles are quads with a repeated corner).
using QuadPatches = std::vector<std::array<Eigen::Vector3d, 4>>;
QuadPatches sketchCollider(const ColliderSpec& spec, double z_floor, double extent);

}  // namespace chs
