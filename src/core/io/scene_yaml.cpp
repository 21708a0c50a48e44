#include "scene_yaml.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <Eigen/Geometry>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/io/material_presets.h"
#include "cloth_hair_sim/core/mesh/vertex_selection.h"

namespace chs {

void failKey(const std::string& key, const std::string& what) {
  throw InputError(key + ": " + what);
}

std::string str(double x) {
  std::ostringstream s;
  s << x;
  return s.str();
}

YamlSection::YamlSection(const YAML::Node& node, std::string path)
    : node_(node), path_(std::move(path)) {
  if (!node_.IsMap()) failKey(path_.empty() ? "scene" : path_, "must be a mapping of keys");
}

std::string YamlSection::firstKey() const {
  return node_.size() > 0 ? node_.begin()->first.as<std::string>() : std::string();
}

std::string YamlSection::key(const std::string& k) const {
  return path_.empty() ? k : path_ + "." + k;
}

YAML::Node YamlSection::get(const std::string& k) {
  used_.insert(k);
  return node_[k];
}

YAML::Node YamlSection::require(const std::string& k) {
  YAML::Node n = get(k);
  if (!n) failKey(key(k), "missing");
  return n;
}

double YamlSection::number(const std::string& k, std::optional<double> fallback) {
  YAML::Node n = get(k);
  if (!n) {
    if (!fallback) failKey(key(k), "missing");
    return *fallback;
  }
  return toNumber(n, key(k));
}

double YamlSection::positive(const std::string& k, std::optional<double> fallback) {
  const double x = number(k, fallback);
  if (!(x > 0.0)) failKey(key(k), "must be positive, got " + str(x));
  return x;
}

int YamlSection::integer(const std::string& k, int fallback, int minimum) {
  YAML::Node n = get(k);
  if (!n) return fallback;
  int x = 0;
  try {
    x = n.as<int>();
  } catch (const YAML::Exception&) {
    failKey(key(k), "must be an integer, got '" + scalarText(n) + "'");
  }
  if (x < minimum) failKey(key(k), "must be at least " + std::to_string(minimum));
  return x;
}

bool YamlSection::boolean(const std::string& k, bool fallback) {
  YAML::Node n = get(k);
  if (!n) return fallback;
  try {
    return n.as<bool>();
  } catch (const YAML::Exception&) {
    failKey(key(k), "must be true or false, got '" + scalarText(n) + "'");
  }
}

std::string YamlSection::text(const std::string& k, const std::string& fallback) {
  YAML::Node n = get(k);
  if (!n) return fallback;
  if (!n.IsScalar()) failKey(key(k), "must be a string");
  return n.as<std::string>();
}

std::vector<std::string> YamlSection::names(const std::string& k) {
  std::vector<std::string> out;
  YAML::Node n = get(k);
  if (!n) return out;
  if (!n.IsSequence() || n.size() == 0) failKey(key(k), "must be a list of names");
  for (const auto& name : n) {
    if (!name.IsScalar()) failKey(key(k), "must be a list of names");
    out.push_back(name.Scalar());
  }
  return out;
}

Eigen::VectorXd YamlSection::vector(const std::string& k, int size) {
  return toVector(require(k), key(k), size);
}

Eigen::Vector3d YamlSection::vector3(const std::string& k, const Eigen::Vector3d& fallback) {
  if (!has(k)) return fallback;
  return vector(k, 3);
}

void YamlSection::done() const {
  for (const auto& kv : node_) {
    const std::string k = kv.first.as<std::string>();
    if (!used_.count(k)) failKey(key(k), "unknown key");
  }
}

std::string YamlSection::scalarText(const YAML::Node& n) {
  return n.IsScalar() ? n.Scalar() : std::string("<not a scalar>");
}

double YamlSection::toNumber(const YAML::Node& n, const std::string& key) {
  double x = 0.0;
  try {
    if (!n.IsScalar()) throw YAML::Exception(YAML::Mark(), "");
    x = n.as<double>();
  } catch (const YAML::Exception&) {
    failKey(key, "must be a number, got '" + scalarText(n) + "'");
  }
  if (!std::isfinite(x)) failKey(key, "must be finite");
  return x;
}

Eigen::VectorXd YamlSection::toVector(const YAML::Node& n, const std::string& key, int size) {
  if (!n.IsSequence() || static_cast<int>(n.size()) != size)
    failKey(key, "must be a list of " + std::to_string(size) + " numbers");
  Eigen::VectorXd v(size);
  for (int i = 0; i < size; ++i) v[i] = toNumber(n[i], key + "[" + std::to_string(i) + "]");
  return v;
}

// A rigid pose: position plus rpy (radians, URDF order: yaw about z, then pitch about y, then
// roll about x, i.e. R = Rz Ry Rx) or quaternion [x, y, z, w].
Eigen::Isometry3d parseRigidPose(YamlSection& s) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = s.vector3("position", Eigen::Vector3d::Zero());
  if (s.has("rpy") && s.has("quaternion"))
    failKey(s.key("quaternion"), "give either rpy or quaternion");
  if (s.has("rpy")) {
    const Eigen::Vector3d rpy = s.vector("rpy", 3);
    pose.linear() = (Eigen::AngleAxisd(rpy.z(), Eigen::Vector3d::UnitZ()) *
                     Eigen::AngleAxisd(rpy.y(), Eigen::Vector3d::UnitY()) *
                     Eigen::AngleAxisd(rpy.x(), Eigen::Vector3d::UnitX()))
                        .toRotationMatrix();
  } else if (s.has("quaternion")) {
    const Eigen::VectorXd q = s.vector("quaternion", 4);
    // A quaternion written with a few digits is off unit length by ~1e-4; more is a typo.
    if (std::abs(q.norm() - 1.0) > 1e-3)
      failKey(s.key("quaternion"),
              "must be a unit quaternion [x, y, z, w], its norm is " + str(q.norm()));
    pose.linear() = Eigen::Quaterniond(q[3], q[0], q[1], q[2]).normalized().toRotationMatrix();
  }
  return pose;
}

std::string kindOf(const YamlSection& s, const std::vector<std::string>& kinds,
                   const std::string& what) {
  std::string found, list;
  for (const auto& k : kinds) {
    list += (list.empty() ? "" : ", ") + k;
    if (s.has(k)) {
      if (!found.empty())
        failKey(s.key(k), "a " + what + " has one kind only (also " + found + ")");
      found = k;
    }
  }
  if (found.empty()) {
    const std::string other = s.firstKey();
    if (!other.empty()) failKey(s.key(other), "unknown " + what + " kind (known: " + list + ")");
    failKey(s.path(), "a " + what + " needs one of: " + list);
  }
  return found;
}

ShellMaterial parseMaterial(const YAML::Node& node, const std::string& key, std::string& name) {
  auto preset = [&](const std::string& n, const std::string& k) {
    auto m = materialPreset(n);
    if (!m) {
      std::string names;
      for (const auto& p : materialPresetNames()) names += (names.empty() ? "" : ", ") + p;
      failKey(k, "unknown material preset '" + n + "' (known: " + names + ")");
    }
    return *m;
  };
  if (node.IsScalar()) {
    name = node.as<std::string>();
    return preset(name, key);
  }
  YamlSection s(node, key);
  ShellMaterial m;
  const bool has_preset = s.has("preset");
  if (has_preset) {
    name = s.text("preset", "");
    m = preset(name, s.key("preset"));
  } else {
    name = "custom";
  }
  bool modified = false;
  auto value = [&](const char* k, double& field) {
    if (!s.has(k)) {
      if (!has_preset) failKey(s.key(k), "missing (no preset to take it from)");
      return;
    }
    field = s.number(k);
    modified = true;
  };
  value("young", m.young);
  value("poisson", m.poisson);
  value("thickness", m.thickness);
  value("areal_density", m.areal_density);
  if (s.has("shear_correction")) m.shear_correction = s.number("shear_correction"), modified = true;
  if (s.has("bending_rigidity")) {  // D in N m: sets E for the given thickness and nu
    if (s.has("young")) failKey(s.key("bending_rigidity"), "give either young or bending_rigidity");
    const double d = s.positive("bending_rigidity");
    m.young = 12.0 * (1.0 - m.poisson * m.poisson) * d / std::pow(m.thickness, 3);
    modified = true;
  }
  s.done();
  if (!(m.young > 0.0)) failKey(s.key("young"), "must be positive (Pa), got " + str(m.young));
  if (!(m.poisson >= 0.0 && m.poisson < 0.5))
    failKey(s.key("poisson"), "must lie in [0, 0.5), got " + str(m.poisson));
  if (!(m.thickness > 0.0))
    failKey(s.key("thickness"), "must be positive (m), got " + str(m.thickness));
  if (!(m.areal_density >= 0.0))
    failKey(s.key("areal_density"), "must not be negative (kg/m^2), got " + str(m.areal_density));
  if (!(m.shear_correction > 0.0)) failKey(s.key("shear_correction"), "must be positive");
  if (has_preset && modified) name += " (modified)";
  return m;
}

namespace {

void select(const YAML::Node& node, const std::string& key, const QuadMesh& mesh,
            std::vector<int>& out) {
  if (node.IsScalar()) {
    int v = -1;
    try {
      v = node.as<int>();
    } catch (const YAML::Exception&) {
      failKey(key, "a vertex index must be an integer, got '" + node.Scalar() + "'");
    }
    if (v < 0 || v >= mesh.numVertices())
      failKey(key, "vertex " + std::to_string(v) + " is out of range (the mesh has " +
                       std::to_string(mesh.numVertices()) + " vertices)");
    out.push_back(v);
    return;
  }
  if (node.IsSequence()) {
    for (std::size_t i = 0; i < node.size(); ++i)
      select(node[i], key + "[" + std::to_string(i) + "]", mesh, out);
    return;
  }
  YamlSection s(node, key);
  const std::string kind =
      kindOf(s, {"vertex", "vertices", "nearest", "plane", "box", "boundary"}, "vertex selector");
  const std::size_t before = out.size();
  if (kind == "vertex" || kind == "vertices") {
    select(s.get(kind), s.key(kind), mesh, out);
  } else if (kind == "nearest") {
    out.push_back(nearestVertex(mesh, s.vector("nearest", 3)));
  } else if (kind == "plane") {
    YamlSection p(s.get(kind), s.key(kind));
    const std::string axis = p.text("axis", "");
    const int a = axis == "x" ? 0 : axis == "y" ? 1 : axis == "z" ? 2 : -1;
    if (a < 0) failKey(p.key("axis"), "must be x, y or z");
    const double value = p.number("value");
    const double tol = p.number("tolerance", 1e-6);
    if (tol < 0.0) failKey(p.key("tolerance"), "must not be negative");
    p.done();
    const auto v = verticesOnPlane(mesh, a, value, tol);
    out.insert(out.end(), v.begin(), v.end());
  } else if (kind == "box") {
    YamlSection b(s.get(kind), s.key(kind));
    const auto v = verticesInBox(mesh, b.vector("min", 3), b.vector("max", 3));
    b.done();
    out.insert(out.end(), v.begin(), v.end());
  } else {
    if (!s.boolean("boundary", false)) failKey(s.key("boundary"), "only 'boundary: true' selects");
    const auto v = boundaryVertices(mesh);
    out.insert(out.end(), v.begin(), v.end());
  }
  s.done();
  if (out.size() == before) failKey(key, "selects no vertex");
}

}  // namespace

std::vector<int> selectVertices(const YAML::Node& node, const std::string& key,
                                const QuadMesh& mesh) {
  std::vector<int> v;
  select(node, key, mesh, v);
  std::sort(v.begin(), v.end());
  v.erase(std::unique(v.begin(), v.end()), v.end());
  return v;
}

std::string readSceneFile(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw InputError(path + ": no such scene file");
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  if (!in) throw InputError(path + ": cannot read scene file");
  return text.str();
}

YAML::Node loadYaml(const std::string& yaml_text) {
  try {
    return YAML::Load(yaml_text);
  } catch (const YAML::Exception& e) {
    throw InputError("scene: not valid YAML: " + e.msg + " at line " +
                     std::to_string(e.mark.line + 1));
  }
}

void failYaml(const YAML::Exception& e) {
  throw InputError("scene: " + e.msg + " at line " + std::to_string(e.mark.line + 1));
}

}  // namespace chs
