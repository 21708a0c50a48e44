#include "cloth_hair_sim/node/urdf_colliders.h"

#include <cmath>

#include <ros/ros.h>
#include <urdf_parser/urdf_parser.h>

#include "cloth_hair_sim/core/common/input_error.h"

namespace chs_node {
namespace {

Eigen::Isometry3d isometry(const urdf::Pose& p) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translate(Eigen::Vector3d(p.position.x, p.position.y, p.position.z));
  t.rotate(Eigen::Quaterniond(p.rotation.w, p.rotation.x, p.rotation.y, p.rotation.z).normalized());
  return t;
}

// One collision element as a shape, or false (with a warning) for geometry we cannot collide.
bool toShape(const urdf::Collision& c, const std::string& where, chs::ColliderShape& shape,
             std::vector<std::string>& warnings) {
  if (!c.geometry) return false;
  shape.offset = isometry(c.origin);
  switch (c.geometry->type) {
    case urdf::Geometry::SPHERE:
      shape.type = chs::ColliderShape::Type::kSphere;
      shape.dimensions = {static_cast<const urdf::Sphere&>(*c.geometry).radius};
      return true;
    case urdf::Geometry::BOX: {
      const urdf::Vector3& d = static_cast<const urdf::Box&>(*c.geometry).dim;
      shape.type = chs::ColliderShape::Type::kBox;
      shape.dimensions = {d.x, d.y, d.z};
      return true;
    }
    case urdf::Geometry::CYLINDER: {
      const auto& cyl = static_cast<const urdf::Cylinder&>(*c.geometry);
      shape.type = chs::ColliderShape::Type::kCylinder;
      shape.dimensions = {cyl.radius, cyl.length};
      return true;
    }
    case urdf::Geometry::MESH: {
      // A mesh collider needs a closed surface: a file that cannot give one is skipped with a
      // warning, as robots often carry open visual-grade meshes on minor links.
      const auto& mesh = static_cast<const urdf::Mesh&>(*c.geometry);
      shape.type = chs::ColliderShape::Type::kMesh;
      shape.mesh_scale = Eigen::Vector3d(mesh.scale.x, mesh.scale.y, mesh.scale.z);
      try {
        shape.mesh_file = resolveMeshUrl(mesh.filename);
        shape.meshField();  // built now, once: errors show at startup, not mid-simulation
      } catch (const chs::InputError& e) {
        warnings.push_back(where + ": mesh '" + mesh.filename + "' skipped: " + e.what());
        return false;
      }
      return true;
    }
  }
  return false;
}

bool near(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return (a - b).norm() < 1e-6;
}

// Fuses each cylinder with two spheres of its radius centred on its end faces into a capsule.
void fuseCapsules(std::vector<chs::ColliderShape>& shapes) {
  using Type = chs::ColliderShape::Type;
  for (size_t i = 0; i < shapes.size(); ++i) {
    if (shapes[i].type != Type::kCylinder) continue;
    const double r = shapes[i].dimensions[0], half = 0.5 * shapes[i].dimensions[1];
    const Eigen::Vector3d ends[2] = {shapes[i].offset * Eigen::Vector3d(0, 0, -half),
                                     shapes[i].offset * Eigen::Vector3d(0, 0, half)};
    int cap[2] = {-1, -1};
    for (size_t j = 0; j < shapes.size(); ++j)
      for (int e = 0; e < 2; ++e)
        if (cap[e] < 0 && shapes[j].type == Type::kSphere &&
            std::abs(shapes[j].dimensions[0] - r) < 1e-6 &&
            near(shapes[j].offset.translation(), ends[e]))
          cap[e] = static_cast<int>(j);
    if (cap[0] < 0 || cap[1] < 0 || cap[0] == cap[1]) continue;
    shapes[i].type = Type::kCapsule;
    shapes[i].edge_radius = -1.0;
    for (int j : {std::max(cap[0], cap[1]), std::min(cap[0], cap[1])}) {
      shapes.erase(shapes.begin() + j);
      if (static_cast<size_t>(j) < i) --i;
    }
  }
}

}  // namespace

UrdfColliders parseUrdfColliders(const std::string& urdf_xml, const std::string& frame_prefix) {
  const urdf::ModelInterfaceSharedPtr model = urdf::parseURDF(urdf_xml);
  if (!model) throw chs::InputError("the robot description is not a URDF that urdfdom can parse");
  UrdfColliders out;
  for (const auto& [link_name, link] : model->links_) {
    std::vector<urdf::CollisionSharedPtr> elements = link->collision_array;
    if (elements.empty() && link->collision) elements.push_back(link->collision);
    std::vector<chs::ColliderShape> shapes;
    for (size_t i = 0; i < elements.size(); ++i) {
      chs::ColliderShape shape;
      const std::string where = "link '" + link_name + "' collision " + std::to_string(i);
      if (elements[i] && toShape(*elements[i], where, shape, out.warnings)) shapes.push_back(shape);
    }
    fuseCapsules(shapes);
    for (size_t i = 0; i < shapes.size(); ++i) {
      TrackedCollider t;
      t.name = shapes.size() == 1 ? link_name : link_name + "_" + std::to_string(i);
      t.frame_id = frame_prefix + link_name;
      t.shape = shapes[i];
      try {
        t.shape.validate();
      } catch (const chs::InputError& e) {
        throw chs::InputError("URDF link '" + link_name + "': " + e.what());
      }
      out.colliders.push_back(t);
    }
  }
  return out;
}

std::vector<TrackedCollider> withUrdfColliders(const ros::NodeHandle& pnh,
                                               std::vector<TrackedCollider> colliders) {
  bool enabled = false;
  pnh.param("urdf_colliders", enabled, enabled);
  if (!enabled) return colliders;
  std::string param = "robot_description", prefix, xml;
  pnh.param("robot_description", param, param);
  pnh.param("urdf_frame_prefix", prefix, prefix);
  double friction = 0.0;  // Coulomb mu of cloth on the robot's links
  pnh.param("urdf_friction", friction, friction);
  if (!(friction >= 0.0) || !std::isfinite(friction))
    throw chs::InputError("parameter ~urdf_friction must be >= 0");
  if (!ros::NodeHandle().getParam(param, xml) || xml.empty())
    throw chs::InputError("~urdf_colliders is on but parameter '" + param +
                          "' holds no robot description");
  UrdfColliders urdf = parseUrdfColliders(xml, prefix);
  for (const auto& w : urdf.warnings) ROS_WARN("URDF colliders: %s", w.c_str());
  for (auto& c : urdf.colliders) {
    c.friction = friction;
    for (const auto& other : colliders)
      if (other.name == c.name)
        throw chs::InputError("URDF collider '" + c.name + "' clashes with a configured collider");
    colliders.push_back(std::move(c));
  }
  ROS_INFO("URDF colliders: %zu from '%s'", urdf.colliders.size(), param.c_str());
  return colliders;
}

}  // namespace chs_node
