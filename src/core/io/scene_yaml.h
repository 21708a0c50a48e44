#pragma once
// The checked reading of YAML scene files shared by the drape scenes (io/scene.h) and the
// simulation scenes (io/simulation_scene.h): every key must be read, so whatever is left over is
// an unknown key, and every value error names its key. Private to the core (yaml-cpp is not part
// of its interface).
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "cloth_hair_sim/core/material/shell_material.h"
#include "cloth_hair_sim/core/mesh/quad_mesh.h"

namespace chs {

// Throws InputError("key: what").
[[noreturn]] void failKey(const std::string& key, const std::string& what);
// A number as messages show it (shortest form).
std::string str(double x);

// The text of a scene file; InputError "<path>: no such scene file" or "cannot read".
std::string readSceneFile(const std::string& path);
// The YAML document of a scene's text; InputError "scene: not valid YAML: ... at line N".
YAML::Node loadYaml(const std::string& yaml_text);
// YAML's own error while reading a document (a shape the checks did not foresee) as InputError
// "scene: ... at line N".
[[noreturn]] void failYaml(const YAML::Exception& e);

// A YAML mapping whose keys must all be read: whatever is left over is an unknown key.
class YamlSection {
 public:
  YamlSection(const YAML::Node& node, std::string path);

  bool has(const std::string& key) const { return static_cast<bool>(node_[key]); }
  const std::string& path() const { return path_; }
  std::string firstKey() const;
  std::string key(const std::string& k) const;

  YAML::Node get(const std::string& k);
  YAML::Node require(const std::string& k);

  double number(const std::string& k, std::optional<double> fallback = std::nullopt);
  double positive(const std::string& k, std::optional<double> fallback = std::nullopt);
  int integer(const std::string& k, int fallback, int minimum);
  bool boolean(const std::string& k, bool fallback);
  std::string text(const std::string& k, const std::string& fallback);
  // A non-empty list of names (e.g. a mesh file's parts); empty if the key is absent.
  std::vector<std::string> names(const std::string& k);
  Eigen::VectorXd vector(const std::string& k, int size);
  Eigen::Vector3d vector3(const std::string& k, const Eigen::Vector3d& fallback);

  // Throws for the first key nobody asked for.
  void done() const;

  static std::string scalarText(const YAML::Node& n);
  static double toNumber(const YAML::Node& n, const std::string& key);
  static Eigen::VectorXd toVector(const YAML::Node& n, const std::string& key, int size);

 private:
  YAML::Node node_;
  std::string path_;
  std::set<std::string> used_;
};

// A rigid pose (drape scenes) from the keys position [x, y, z] and rpy [r, p, y] (radians, URDF
// order: R = Rz(y) Ry(p) Rx(r)) or quaternion [x, y, z, w]; the identity when absent.
Eigen::Isometry3d parseRigidPose(YamlSection& s);

// Exactly one of the given keys must be present: the kind of a garment, collider or selector.
std::string kindOf(const YamlSection& s, const std::vector<std::string>& kinds,
                   const std::string& what);

// A material: a preset name or {preset (optional), young, poisson, thickness, areal_density,
// shear_correction, bending_rigidity}; name gets the preset's name, "custom" or
// "<preset> (modified)".
ShellMaterial parseMaterial(const YAML::Node& node, const std::string& key, std::string& name);

// A vertex selector: an index, a list of selectors, or a mapping with one of vertex, vertices,
// nearest, plane {axis, value, tolerance}, box {min, max}, boundary: true. Sorted, unique;
// throws for a selector that selects nothing or an index out of range.
std::vector<int> selectVertices(const YAML::Node& node, const std::string& key,
                                const QuadMesh& mesh);

}  // namespace chs
