#include "cloth_hair_sim/core/contact/collider_shape.h"

#include <algorithm>
#include <cmath>
#include <mutex>
#include <sstream>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/contact/capsule_surface.h"
#include "cloth_hair_sim/core/contact/posed_surface.h"

namespace chs {

// The field of a mesh shape with what it was built from; one per shape, shared by its copies.
struct MeshFieldCache {
  std::mutex mutex;
  std::string file;
  Eigen::Vector3d scale = Eigen::Vector3d::Zero();
  std::vector<std::string> parts;
  MeshSdfResolution resolution;
  std::shared_ptr<const MeshSdfSurface> field;
};

std::shared_ptr<MeshFieldCache> ColliderShape::newMeshFieldCache() {
  return std::make_shared<MeshFieldCache>();
}

ColliderShape::Type parseColliderType(const std::string& name) {
  if (name == "plane") return ColliderShape::Type::kPlane;
  if (name == "sphere") return ColliderShape::Type::kSphere;
  if (name == "box") return ColliderShape::Type::kBox;
  if (name == "cylinder") return ColliderShape::Type::kCylinder;
  if (name == "capsule") return ColliderShape::Type::kCapsule;
  if (name == "mesh") return ColliderShape::Type::kMesh;
  throw InputError("collider shape '" + name +
                   "' is unknown: use plane, sphere, box, cylinder, capsule or mesh");
}

std::string colliderTypeName(ColliderShape::Type type) {
  switch (type) {
    case ColliderShape::Type::kPlane:
      return "plane";
    case ColliderShape::Type::kSphere:
      return "sphere";
    case ColliderShape::Type::kBox:
      return "box";
    case ColliderShape::Type::kCylinder:
      return "cylinder";
    case ColliderShape::Type::kCapsule:
      return "capsule";
    case ColliderShape::Type::kMesh:
      return "mesh";
  }
  return "unknown";
}

void ColliderShape::validate() const {
  const std::string name = colliderTypeName(type);
  const size_t expected = type == Type::kPlane || type == Type::kMesh ? 0
                          : type == Type::kSphere                     ? 1
                          : type == Type::kBox                        ? 3
                                                                      : 2;
  if (dimensions.size() != expected)
    throw InputError(name + " collider: needs " + std::to_string(expected) + " dimensions, got " +
                     std::to_string(dimensions.size()));
  for (size_t i = 0; i < dimensions.size(); ++i)
    if (!(dimensions[i] > 0.0) || !std::isfinite(dimensions[i]))
      throw InputError(name + " collider: dimension " + std::to_string(i) +
                       " must be positive and finite (m)");
  const Eigen::Matrix3d r = offset.linear();
  if (!offset.matrix().allFinite() || !(r.transpose() * r).isIdentity(1e-6))
    throw InputError(name + " collider: the offset pose must be finite with a unit quaternion");
  if (!std::isfinite(edge_radius)) throw InputError(name + " collider: edge radius must be finite");
  if (type == Type::kMesh) {
    // The file itself is read (and its absence reported) when the field is built.
    if (mesh_file.empty()) throw InputError("mesh collider: needs a mesh file");
    if (!mesh_scale.allFinite() || !(mesh_scale.array() > 0.0).all()) {
      std::ostringstream s;
      s << "mesh collider: scale must be positive and finite, got (" << mesh_scale.transpose()
        << ")";
      throw InputError(s.str());
    }
    for (double v :
         {mesh_resolution.voxel_size, mesh_resolution.exterior_band, mesh_resolution.interior_band})
      if (!(v >= 0.0) || !std::isfinite(v))
        throw InputError("mesh collider: voxel size and band widths must be >= 0 (0: default)");
  }
  if ((type == Type::kBox || type == Type::kCylinder) &&
      !(effectiveEdgeRadius() < 0.5 * *std::min_element(dimensions.begin(), dimensions.end())))
    throw InputError(name + " collider: edge radius must be below half the smallest dimension");
}

double ColliderShape::effectiveEdgeRadius() const {
  if (type == Type::kPlane || type == Type::kSphere || type == Type::kCapsule ||
      type == Type::kMesh)
    return 0.0;
  if (edge_radius >= 0.0) return edge_radius;
  const double smallest = *std::min_element(dimensions.begin(), dimensions.end());
  return std::min(1e-3, smallest / 100.0);
}

std::shared_ptr<const MeshSdfSurface> ColliderShape::meshField() const {
  if (type != Type::kMesh) throw InputError(colliderTypeName(type) + " collider: has no mesh");
  validate();
  const std::lock_guard<std::mutex> lock(mesh_cache_->mutex);
  MeshFieldCache& c = *mesh_cache_;
  const MeshSdfResolution& r = mesh_resolution;
  if (!c.field || c.file != mesh_file || c.scale != mesh_scale || c.parts != mesh_parts ||
      c.resolution.voxel_size != r.voxel_size || c.resolution.exterior_band != r.exterior_band ||
      c.resolution.interior_band != r.interior_band) {
    c.field = MeshSdfSurface::fromFile(mesh_file, mesh_scale, r, mesh_parts);
    c.file = mesh_file;
    c.scale = mesh_scale;
    c.parts = mesh_parts;
    c.resolution = r;
  }
  return c.field;
}

std::shared_ptr<const RigidSurface> ColliderShape::makeSurface(
    const Eigen::Isometry3d& world_from_frame) const {
  validate();
  const Eigen::Vector3d o = Eigen::Vector3d::Zero();
  std::shared_ptr<const RigidSurface> local;
  switch (type) {
    case Type::kPlane:
      local = std::make_shared<PlaneSurface>(o, Eigen::Vector3d::UnitZ());
      break;
    case Type::kSphere:
      local = std::make_shared<SphereSurface>(o, dimensions[0]);
      break;
    // The core's rounded solids grow their given box / cylinder by the edge radius except on
    // top; shrink them first so that the solid has exactly the given outer size.
    case Type::kBox: {
      const double e = effectiveEdgeRadius();
      const Eigen::Vector3d half =
          0.5 * Eigen::Vector3d(dimensions[0], dimensions[1], dimensions[2]);
      local = std::make_shared<BoxSurface>(-half + Eigen::Vector3d::Constant(e),
                                           half - Eigen::Vector3d(e, e, 0.0), e);
      break;
    }
    case Type::kCylinder: {
      const double e = effectiveEdgeRadius();
      local = std::make_shared<CylinderSurface>(Eigen::Vector2d::Zero(), dimensions[0] - e,
                                                -0.5 * dimensions[1] + e, 0.5 * dimensions[1], e);
      break;
    }
    case Type::kCapsule: {
      const Eigen::Vector3d half(0.0, 0.0, 0.5 * dimensions[1]);
      local = std::make_shared<CapsuleSurface>(-half, half, dimensions[0]);
      break;
    }
    case Type::kMesh:
      local = meshField();
      break;
  }
  return std::make_shared<PosedSurface>(local, world_from_frame * offset);
}

}  // namespace chs
