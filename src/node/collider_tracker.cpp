#include "cloth_hair_sim/node/collider_tracker.h"

#include <cmath>

#include <tf2_eigen/tf2_eigen.h>

#include "cloth_hair_sim/core/common/input_error.h"

namespace chs_node {
namespace {

double number(XmlRpc::XmlRpcValue& v, const std::string& where) {
  if (v.getType() == XmlRpc::XmlRpcValue::TypeDouble) return static_cast<double>(v);
  if (v.getType() == XmlRpc::XmlRpcValue::TypeInt) return static_cast<int>(v);
  throw chs::InputError(where + ": must be a number");
}

std::vector<double> numbers(XmlRpc::XmlRpcValue& v, const std::string& where) {
  if (v.getType() != XmlRpc::XmlRpcValue::TypeArray)
    throw chs::InputError(where + ": must be a list");
  std::vector<double> out;
  for (int i = 0; i < v.size(); ++i) out.push_back(number(v[i], where));
  return out;
}

std::string text(XmlRpc::XmlRpcValue& v, const std::string& where) {
  if (v.getType() != XmlRpc::XmlRpcValue::TypeString)
    throw chs::InputError(where + ": must be text");
  return static_cast<std::string>(v);
}

Eigen::Vector3d triple(XmlRpc::XmlRpcValue& v, const std::string& where) {
  const std::vector<double> d = numbers(v, where);
  if (d.size() != 3) throw chs::InputError(where + ": needs 3 numbers");
  return Eigen::Vector3d(d[0], d[1], d[2]);
}

Eigen::Isometry3d parseOffset(XmlRpc::XmlRpcValue& v, const std::string& where) {
  if (v.getType() != XmlRpc::XmlRpcValue::TypeStruct)
    throw chs::InputError(where + ": must be {xyz: [x, y, z], rpy: [roll, pitch, yaw]}");
  Eigen::Vector3d xyz = Eigen::Vector3d::Zero(), rpy = Eigen::Vector3d::Zero();
  for (auto& kv : v) {
    if (kv.first == "xyz")
      xyz = triple(kv.second, where + ".xyz");
    else if (kv.first == "rpy")
      rpy = triple(kv.second, where + ".rpy");
    else
      throw chs::InputError(where + ": unknown key '" + kv.first + "'");
  }
  // URDF convention: fixed-axis roll, pitch, yaw = R_z(yaw) R_y(pitch) R_x(roll).
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translate(xyz);
  t.rotate(Eigen::AngleAxisd(rpy.z(), Eigen::Vector3d::UnitZ()) *
           Eigen::AngleAxisd(rpy.y(), Eigen::Vector3d::UnitY()) *
           Eigen::AngleAxisd(rpy.x(), Eigen::Vector3d::UnitX()));
  return t;
}

}  // namespace

std::vector<TrackedCollider> parseColliders(XmlRpc::XmlRpcValue& list) {
  if (list.getType() != XmlRpc::XmlRpcValue::TypeArray)
    throw chs::InputError("~colliders: must be a list");
  std::vector<TrackedCollider> out;
  for (int i = 0; i < list.size(); ++i) {
    std::string where = "~colliders[" + std::to_string(i) + "]";
    XmlRpc::XmlRpcValue& c = list[i];
    if (c.getType() != XmlRpc::XmlRpcValue::TypeStruct)
      throw chs::InputError(where + ": must be a mapping");
    TrackedCollider t;
    bool has_shape = false;
    for (auto& kv : c) {
      const std::string& key = kv.first;
      if (key == "name")
        t.name = text(kv.second, where + ".name");
      else if (key == "frame_id")
        t.frame_id = text(kv.second, where + ".frame_id");
      else if (key == "shape") {
        t.shape.type = chs::parseColliderType(text(kv.second, where + ".shape"));
        has_shape = true;
      } else if (key == "dimensions")
        t.shape.dimensions = numbers(kv.second, where + ".dimensions");
      else if (key == "offset")
        t.shape.offset = parseOffset(kv.second, where + ".offset");
      else if (key == "edge_radius")
        t.shape.edge_radius = number(kv.second, where + ".edge_radius");
      else if (key == "friction")
        t.friction = number(kv.second, where + ".friction");
      else
        throw chs::InputError(where + ": unknown key '" + key + "'");
    }
    if (t.name.empty()) throw chs::InputError(where + ": needs a name");
    where = "collider '" + t.name + "'";
    if (t.frame_id.empty()) throw chs::InputError(where + ": needs a frame_id");
    if (!has_shape) throw chs::InputError(where + ": needs a shape");
    if (!(t.friction >= 0.0) || !std::isfinite(t.friction))
      throw chs::InputError(where + ": friction must be >= 0");
    for (const auto& other : out)
      if (other.name == t.name) throw chs::InputError(where + ": name used twice");
    try {
      t.shape.validate();
    } catch (const chs::InputError& e) {
      throw chs::InputError(where + ": " + e.what());
    }
    out.push_back(t);
  }
  return out;
}

ColliderTracker::ColliderTracker(const tf2_ros::Buffer& buffer, std::string world_frame,
                                 double timeout_s)
    : buffer_(buffer), world_frame_(std::move(world_frame)), timeout_s_(timeout_s) {}

bool ColliderTracker::update() {
  bool all_ok = true;
  for (auto& c : colliders_) {
    std::string error;
    if (buffer_.canTransform(world_frame_, c.frame_id, ros::Time(0), ros::Duration(timeout_s_),
                             &error)) {
      try {
        const Eigen::Isometry3d pose =
            tf2::transformToEigen(buffer_.lookupTransform(world_frame_, c.frame_id, ros::Time(0)));
        if (pose.matrix().allFinite()) {
          c.world_from_frame = pose;
          c.has_pose = true;
          c.stale = false;
          continue;
        }
      } catch (const tf2::TransformException&) {
        // Raced with a buffer change: treated as missing below.
      }
    }
    c.stale = true;
    all_ok = false;
  }
  return all_ok;
}

chs::RigidSurfaces ColliderTracker::surfaces() const {
  chs::RigidSurfaces out;
  for (const auto& c : colliders_)
    if (c.has_pose) out.push_back(c.shape.makeSurface(c.world_from_frame));
  return out;
}

std::vector<double> ColliderTracker::frictions() const {
  std::vector<double> out;
  for (const auto& c : colliders_)
    if (c.has_pose) out.push_back(c.friction);
  return out;
}

std::vector<std::string> ColliderTracker::staleNames() const {
  std::vector<std::string> out;
  for (const auto& c : colliders_)
    if (c.stale) out.push_back(c.name);
  return out;
}

int ColliderTracker::activeCount() const {
  int n = 0;
  for (const auto& c : colliders_) n += c.has_pose ? 1 : 0;
  return n;
}

}  // namespace chs_node
