#include "cloth_hair_sim/node/collider_tracker.h"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include <tf2_eigen/tf2_eigen.h>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/common/names.h"

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

// A per-axis scale: one number for all axes or [x, y, z].
Eigen::Vector3d parseScale(XmlRpc::XmlRpcValue& v, const std::string& where) {
  if (v.getType() == XmlRpc::XmlRpcValue::TypeArray) return triple(v, where);
  return Eigen::Vector3d::Constant(number(v, where));
}

namespace fs = std::filesystem;

// The <name> in dir/package.xml, or "" when dir holds no package.
std::string packageName(const fs::path& dir) {
  std::ifstream in(dir / "package.xml");
  if (!in) return "";
  std::stringstream text;
  text << in.rdbuf();
  std::smatch m;
  const std::string xml = text.str();
  static const std::regex name("<name>\\s*([^<\\s]+)\\s*</name>");
  return std::regex_search(xml, m, name) ? m[1].str() : "";
}

// Depth-first search below root, not descending into packages (as rospack crawls).
bool findPackage(const fs::path& root, const std::string& package, int depth, fs::path& found) {
  std::error_code ec;
  if (depth < 0 || !fs::is_directory(root, ec) || fs::exists(root / "CATKIN_IGNORE", ec))
    return false;
  if (fs::exists(root / "package.xml", ec)) {
    if (packageName(root) != package) return false;
    found = root;
    return true;
  }
  for (fs::directory_iterator it(root, fs::directory_options::skip_permission_denied, ec), end;
       !ec && it != end; it.increment(ec))
    if (it->is_directory(ec) && findPackage(it->path(), package, depth - 1, found)) return true;
  return false;
}

std::vector<std::string> pathList(const char* variable) {
  std::vector<std::string> out;
  const char* value = std::getenv(variable);
  std::stringstream s(value ? value : "");
  for (std::string item; std::getline(s, item, ':');)
    if (!item.empty()) out.push_back(item);
  return out;
}

}  // namespace

bool tooOld(const ros::Time& stamp, const ros::Time& now, double max_age_s) {
  // Static transforms (and chains of them only) carry no stamp: never old.
  return max_age_s > 0.0 && !stamp.isZero() && (now - stamp).toSec() > max_age_s;
}

std::string resolveMeshUrl(const std::string& url) {
  const std::string package_scheme = "package://", file_scheme = "file://";
  if (url.rfind(file_scheme, 0) == 0) return url.substr(file_scheme.size());
  if (url.rfind(package_scheme, 0) != 0) {
    if (url.find("://") != std::string::npos)
      throw chs::InputError("mesh '" + url + "': only package:// and file:// URLs are supported");
    return url;
  }
  const std::string rest = url.substr(package_scheme.size());
  const size_t slash = rest.find('/');
  const std::string package = rest.substr(0, slash);
  const std::string inside = slash == std::string::npos ? "" : rest.substr(slash + 1);
  std::vector<fs::path> roots;
  for (const auto& r : pathList("ROS_PACKAGE_PATH")) roots.emplace_back(r);
  for (const auto& prefix : pathList("CMAKE_PREFIX_PATH"))
    roots.push_back(fs::path(prefix) / "share" / package);
  for (const auto& root : roots)  // the usual layout first: <root>/<package>
    if (packageName(root / package) == package) return (root / package / inside).string();
  for (const auto& root : roots) {
    fs::path found;
    if (findPackage(root, package, 6, found)) return (found / inside).string();
  }
  throw chs::InputError("mesh '" + url + "': package '" + package +
                        "' not found under ROS_PACKAGE_PATH or CMAKE_PREFIX_PATH");
}

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
      else if (key == "file")
        t.shape.mesh_file = resolveMeshUrl(text(kv.second, where + ".file"));
      else if (key == "scale")
        t.shape.mesh_scale = parseScale(kv.second, where + ".scale");
      else if (key == "voxel_size")
        t.shape.mesh_resolution.voxel_size = number(kv.second, where + ".voxel_size");
      else
        throw chs::InputError(where + ": unknown key '" + key + "'");
    }
    try {
      chs::checkName(t.name);
    } catch (const chs::InputError& e) {
      throw chs::InputError(where + ": " + e.what());
    }
    where = "collider '" + t.name + "'";
    if (t.frame_id.empty()) throw chs::InputError(where + ": needs a frame_id");
    if (!has_shape) throw chs::InputError(where + ": needs a shape");
    if (!(t.friction >= 0.0) || !std::isfinite(t.friction))
      throw chs::InputError(where + ": friction must be >= 0");
    for (const auto& other : out)
      if (other.name == t.name) throw chs::InputError(where + ": name used twice");
    const bool mesh_keys = !t.shape.mesh_file.empty() ||
                           t.shape.mesh_scale != Eigen::Vector3d::Ones() ||
                           t.shape.mesh_resolution.voxel_size != 0.0;
    if (mesh_keys && t.shape.type != chs::ColliderShape::Type::kMesh)
      throw chs::InputError(where + ": file, scale and voxel_size belong to shape: mesh");
    try {
      t.shape.validate();
      if (t.shape.type == chs::ColliderShape::Type::kMesh) t.shape.meshField();  // build it now
    } catch (const chs::InputError& e) {
      throw chs::InputError(where + ": " + e.what());
    }
    out.push_back(t);
  }
  return out;
}

ColliderTracker::ColliderTracker(const tf2_ros::Buffer& buffer, std::string world_frame,
                                 double timeout_s, double max_age_s)
    : buffer_(buffer),
      world_frame_(std::move(world_frame)),
      timeout_s_(timeout_s),
      max_age_s_(max_age_s) {}

bool ColliderTracker::update() {
  bool all_ok = true;
  const ros::Time now = ros::Time::now();
  for (auto& c : colliders_) {
    c.reappeared = false;
    std::string error;
    if (buffer_.canTransform(world_frame_, c.frame_id, ros::Time(0), ros::Duration(timeout_s_),
                             &error)) {
      try {
        const geometry_msgs::TransformStamped t =
            buffer_.lookupTransform(world_frame_, c.frame_id, ros::Time(0));
        const Eigen::Isometry3d pose = tf2::transformToEigen(t);
        if (pose.matrix().allFinite() && !tooOld(t.header.stamp, now, max_age_s_)) {
          c.world_from_frame = pose;
          c.reappeared = c.has_pose && c.stale;
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
