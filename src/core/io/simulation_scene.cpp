#include "cloth_hair_sim/core/io/simulation_scene.h"

#include <cmath>
#include <filesystem>
#include <set>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/common/names.h"
#include "cloth_hair_sim/core/io/mesh_reader.h"
#include "cloth_hair_sim/core/io/strand_file.h"
#include "cloth_hair_sim/core/io/triangle_mesh_reader.h"
#include "cloth_hair_sim/core/mesh/grid_generators.h"
#include "scene_yaml.h"

namespace chs {

namespace {

std::string indexed(const std::string& key, std::size_t i) {
  return key + "[" + std::to_string(i) + "]";
}

std::string resolve(const std::string& path, const std::string& base_dir, const std::string& key) {
  if (path.empty()) failKey(key, "missing");
  const std::filesystem::path p(path);
  const std::string full = p.is_absolute() ? path : (std::filesystem::path(base_dir) / p).string();
  std::error_code ec;
  if (!std::filesystem::is_regular_file(full, ec)) failKey(key, "no such file: " + full);
  return full;
}

// The one key of `kinds` that s has (its other keys are checked by done(): a misspelt kind is
// then an unknown key, wherever it stands).
std::string presentKind(const YamlSection& s, const std::vector<std::string>& kinds,
                        const std::string& what) {
  std::string found, list;
  for (const auto& k : kinds) {
    list += (list.empty() ? "" : ", ") + k;
    if (!s.has(k)) continue;
    if (!found.empty()) failKey(s.key(k), "a " + what + " has one kind only (also " + found + ")");
    found = k;
  }
  if (found.empty()) failKey(s.path(), "needs one of: " + list);
  return found;
}

// position and rotation (roll, pitch, yaw about the fixed x, y, z axes, as URDF) of a frame.
Eigen::Isometry3d parsePose(YamlSection& s) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = s.vector3("position", Eigen::Vector3d::Zero());
  const Eigen::Vector3d rpy = s.vector3("rotation", Eigen::Vector3d::Zero());
  pose.linear() = (Eigen::AngleAxisd(rpy.z(), Eigen::Vector3d::UnitZ()) *
                   Eigen::AngleAxisd(rpy.y(), Eigen::Vector3d::UnitY()) *
                   Eigen::AngleAxisd(rpy.x(), Eigen::Vector3d::UnitX()))
                      .toRotationMatrix();
  return pose;
}

std::string parseName(YamlSection& s, const std::string& fallback, std::set<std::string>& taken) {
  const std::string name = s.text("name", fallback);
  try {
    checkName(name);
  } catch (const InputError& e) {
    failKey(s.key("name"), e.what());
  }
  if (!taken.insert(name).second) failKey(s.key("name"), "'" + name + "' is used twice");
  return name;
}

QuadMesh parseGeometry(YamlSection& b, const std::string& base_dir) {
  const std::string kind = presentKind(b, {"rectangle", "mesh"}, "body geometry");
  if (kind == "rectangle") {
    YamlSection r(b.get(kind), b.key(kind));
    const Eigen::Vector2d size = r.vector("size", 2);
    const Eigen::VectorXd cells = r.vector("cells", 2);
    const Eigen::Vector3d centre = r.vector3("centre", Eigen::Vector3d::Zero());
    r.done();
    if (!(size.minCoeff() > 0.0)) failKey(r.key("size"), "must be positive (m)");
    for (int i = 0; i < 2; ++i)
      if (cells[i] < 1 || cells[i] != std::floor(cells[i]) || cells[i] > 1e4)
        failKey(r.key("cells"), "must be positive integers");
    return makeRectangleMesh(size[0], size[1], static_cast<int>(cells[0]),
                             static_cast<int>(cells[1]), centre);
  }
  const YAML::Node m = b.get(kind);
  std::string file;
  double scale = 1.0;
  std::string key = b.key(kind);
  if (m.IsScalar()) {
    file = m.as<std::string>();
  } else {
    YamlSection ms(m, key);
    file = ms.text("file", "");
    key = ms.key("file");
    scale = ms.positive("scale", 1.0);
    ms.done();
  }
  const std::string path = resolve(file, base_dir, key);
  try {
    return readQuadMesh(path, scale);
  } catch (const InputError& e) {
    failKey(key, e.what());
  }
}

SimulationBody parseBody(const YAML::Node& node, const std::string& key,
                         const std::string& fallback_name, const std::string& base_dir,
                         const Eigen::Vector3d& gravity, std::set<std::string>& names) {
  YamlSection b(node, key);
  SimulationBody body;
  body.name = parseName(b, fallback_name, names);
  QuadMesh mesh = parseGeometry(b, base_dir);
  const Eigen::Isometry3d pose = parsePose(b);
  for (auto& v : mesh.vertices) v = pose * v;
  body.problem.mesh = std::move(mesh);
  body.problem.material =
      parseMaterial(b.require("material"), b.key("material"), body.material_name);
  body.problem.gravity = gravity;
  if (b.has("pins"))
    body.problem.bc.pinned = selectVertices(b.get("pins"), b.key("pins"), body.problem.mesh);
  body.velocity = b.vector3("velocity", Eigen::Vector3d::Zero());
  b.done();
  try {
    body.problem.validate();
  } catch (const InputError& e) {
    failKey(key, e.what());
  }
  return body;
}

const std::vector<std::string> kColliderKinds = {"plane",    "sphere",  "box", "table",
                                                 "cylinder", "capsule", "mesh"};

ColliderShape parseShape(YamlSection& c, const std::string& kind, const std::string& base_dir) {
  ColliderShape shape;
  YamlSection s(c.get(kind), c.key(kind));
  auto edge = [&] {
    shape.edge_radius = s.number("edge_radius", -1.0);
    if (s.has("edge_radius") && shape.edge_radius < 0.0)
      failKey(s.key("edge_radius"), "must not be negative (m)");
  };
  if (kind == "plane") {
    shape.type = ColliderShape::Type::kPlane;
  } else if (kind == "sphere") {
    shape.type = ColliderShape::Type::kSphere;
    shape.dimensions = {s.positive("radius")};
  } else if (kind == "box" || kind == "table") {
    shape.type = ColliderShape::Type::kBox;
    if (kind == "box") {
      const Eigen::Vector3d size = s.vector("size", 3);
      if (!(size.minCoeff() > 0.0)) failKey(s.key("size"), "must be positive (m)");
      shape.dimensions = {size.x(), size.y(), size.z()};
    } else {
      const Eigen::Vector2d size = s.vector("size", 2);
      if (!(size.minCoeff() > 0.0)) failKey(s.key("size"), "must be positive (m)");
      const double depth = s.positive("depth", 0.5);
      shape.dimensions = {size.x(), size.y(), depth};
      shape.offset.translation() = Eigen::Vector3d(0.0, 0.0, -0.5 * depth);
    }
    edge();
  } else if (kind == "cylinder" || kind == "capsule") {
    shape.type =
        kind == "cylinder" ? ColliderShape::Type::kCylinder : ColliderShape::Type::kCapsule;
    shape.dimensions = {s.positive("radius"), s.positive("length")};
    if (kind == "cylinder") edge();
  } else {
    shape.type = ColliderShape::Type::kMesh;
    shape.mesh_file = resolve(s.text("file", ""), base_dir, s.key("file"));
    shape.mesh_scale = Eigen::Vector3d::Constant(s.positive("scale", 1.0));
    shape.mesh_parts = s.names("parts");  // the file's nodes or meshes to keep
    shape.mesh_resolution.voxel_size = s.number("voxel_size", 0.0);
    if (shape.mesh_resolution.voxel_size < 0.0)
      failKey(s.key("voxel_size"), "must not be negative (0: default)");
  }
  s.done();
  try {
    shape.validate();
    if (shape.type == ColliderShape::Type::kMesh) shape.meshField();
  } catch (const InputError& e) {
    failKey(c.key(kind), e.what());
  }
  return shape;
}

rod::RodMaterial parseRodMaterial(YamlSection& h, std::string& name) {
  rod::RodMaterial m = rod::humanHair();
  name = "human_hair";
  if (!h.has("material")) return m;
  const YAML::Node node = h.get("material");
  const std::string key = h.key("material");
  if (node.IsScalar()) {
    if (YamlSection::scalarText(node) != "human_hair")
      failKey(key, "unknown preset '" + YamlSection::scalarText(node) + "' (known: human_hair)");
    return m;
  }
  YamlSection ms(node, key);
  const std::string preset = ms.text("preset", "");
  if (!preset.empty() && preset != "human_hair")
    failKey(ms.key("preset"), "unknown preset '" + preset + "' (known: human_hair)");
  name = preset.empty() ? "explicit" : preset + " (overridden)";
  if (preset.empty()) m = rod::RodMaterial();
  m.youngs_modulus = ms.number("young", m.youngs_modulus);
  m.shear_modulus = ms.number("shear", m.shear_modulus);
  if (ms.has("radius")) {
    m.radius_1 = ms.number("radius");
    m.radius_2 = 0.0;
  }
  m.density = ms.number("density", m.density);
  ms.done();
  try {
    rod::checkRodMaterial(m, "material");
  } catch (const InputError& e) {
    failKey(key, e.what());
  }
  return m;
}

rod::Polylines parseStrands(YamlSection& h, const std::string& base_dir) {
  const std::string kind = presentKind(h, {"groom", "file"}, "hair geometry");
  const Eigen::Isometry3d pose = parsePose(h);
  rod::Polylines strands;
  try {
    if (kind == "groom") {
      YamlSection g(h.get("groom"), h.key("groom"));
      rod::GroomSettings gs;
      gs.strands = g.integer("strands", gs.strands, 1);
      gs.length = g.positive("length", gs.length);
      gs.segments = g.integer("segments", gs.segments, 1);
      if (g.has("radii")) {
        const YAML::Node r = g.get("radii");
        gs.scalp.radii = r.IsScalar()
                             ? Eigen::Vector3d::Constant(YamlSection::toNumber(r, g.key("radii")))
                             : Eigen::Vector3d(YamlSection::toVector(r, g.key("radii"), 3));
      }
      gs.scalp.centre = g.vector3("centre", gs.scalp.centre);
      gs.scalp.direction = g.vector3("direction", gs.scalp.direction);
      gs.scalp.cone_angle = g.number("cone_angle", gs.scalp.cone_angle);
      gs.curl_radius = g.number("curl_radius", gs.curl_radius);
      gs.curl_pitch = g.number("curl_pitch", gs.curl_pitch);
      gs.seed = static_cast<std::uint32_t>(g.integer("seed", 1, 0));
      if (g.has("mesh")) {
        // The scalp region of a triangle mesh (a head model) instead of an ellipsoid's patch.
        if (g.has("radii")) failKey(g.key("radii"), "goes with an ellipsoid, not with mesh");
        YamlSection m(g.get("mesh"), g.key("mesh"));
        const std::string path = resolve(m.text("file", ""), base_dir, m.key("file"));
        const double scale = m.positive("scale", 1.0);
        const std::vector<std::string> parts = m.names("parts");
        m.done();
        g.done();
        TriangleMesh mesh;
        try {
          mesh = readTriangleMesh(path, Eigen::Vector3d::Constant(scale), parts);
        } catch (const InputError& e) {
          failKey(m.key("file"), e.what());
        }
        strands = rod::groomMesh(mesh, gs);
      } else {
        g.done();
        strands = rod::groomScalp(gs);
      }
    } else {
      const YAML::Node f = h.get("file");
      std::string file;
      double scale = 1.0;
      int segments = 0;
      if (f.IsScalar()) {
        file = YamlSection::scalarText(f);
      } else {
        YamlSection fs(f, h.key("file"));
        file = fs.text("file", "");
        scale = fs.positive("scale", 1.0);
        segments = fs.integer("segments", 0, 0);
        fs.done();
      }
      if (file.empty()) failKey(h.key("file"), "needs a path");
      const std::filesystem::path path = std::filesystem::path(file).is_absolute()
                                             ? std::filesystem::path(file)
                                             : std::filesystem::path(base_dir) / file;
      strands = readStrandFile(path.string());
      for (auto& strand : strands) {
        if (segments > 0) strand = rod::resampleStrand(strand, segments);
        for (auto& x : strand) x *= scale;
      }
    }
    for (auto& strand : strands)
      for (auto& x : strand) x = pose * x;
    rod::checkStrands(strands);
  } catch (const InputError& e) {
    failKey(h.key(kind), e.what());
  }
  return strands;
}

SimulationHair parseHair(const YAML::Node& node, const std::string& key,
                         const std::string& fallback_name, const std::string& base_dir,
                         std::set<std::string>& names) {
  YamlSection h(node, key);
  SimulationHair out;
  out.name = parseName(h, fallback_name, names);
  out.strands = parseStrands(h, base_dir);
  out.material = parseRodMaterial(h, out.material_name);
  out.roots = h.text("roots", out.roots);
  out.pic_blend = h.number("pic_blend", out.pic_blend);
  if (!(out.pic_blend >= 0.0 && out.pic_blend <= 1.0))
    failKey(h.key("pic_blend"), "must lie in [0, 1]");
  if (h.has("continuum")) {
    YamlSection c(h.get("continuum"), h.key("continuum"));
    rod::StrandContinuumSettings& cs = out.continuum;
    cs.enabled = c.boolean("enabled", true);
    cs.youngs_modulus = c.number("youngs_modulus", cs.youngs_modulus);
    cs.poisson_ratio = c.number("poisson_ratio", cs.poisson_ratio);
    cs.friction = c.number("friction", cs.friction);
    cs.contact_blend = c.number("contact_blend", cs.contact_blend);
    c.done();
    try {
      rod::HairSettings check;
      check.continuum = cs;
      rod::HairDynamics{check};
    } catch (const InputError& e) {
      failKey(h.key("continuum"), e.what());
    }
  }
  h.done();
  return out;
}

ScriptedMotion parseMotion(const YAML::Node& node, const std::string& key) {
  YamlSection m(node, key);
  ScriptedMotion motion;
  if (m.has("keyframes")) {
    if (m.has("linear_velocity") || m.has("angular_velocity"))
      failKey(m.key("keyframes"), "give either keyframes or velocities");
    const YAML::Node list = m.get("keyframes");
    if (!list.IsSequence() || list.size() < 2)
      failKey(m.key("keyframes"), "must be a list of at least two {time, position, rotation}");
    motion.kind = ScriptedMotion::Kind::kKeyframes;
    for (std::size_t i = 0; i < list.size(); ++i) {
      YamlSection k(list[i], indexed(m.key("keyframes"), i));
      ScriptedMotion::Keyframe f;
      f.time = k.number("time");
      if (!motion.keyframes.empty() && !(f.time > motion.keyframes.back().time))
        failKey(k.key("time"), "must exceed the previous keyframe's time");
      f.pose = parsePose(k);
      k.done();
      motion.keyframes.push_back(f);
    }
  } else {
    motion.kind = ScriptedMotion::Kind::kVelocity;
    motion.linear = m.vector3("linear_velocity", Eigen::Vector3d::Zero());
    motion.angular = m.vector3("angular_velocity", Eigen::Vector3d::Zero());
    if (motion.linear.isZero(0.0) && motion.angular.isZero(0.0))
      failKey(key, "needs linear_velocity, angular_velocity or keyframes");
  }
  m.done();
  return motion;
}

SimulationCollider parseCollider(const YAML::Node& node, const std::string& key, std::size_t index,
                                 const std::string& base_dir, std::set<std::string>& names) {
  YamlSection c(node, key);
  SimulationCollider out;
  const std::string kind = presentKind(c, kColliderKinds, "collider");
  out.kind = kind;
  out.name = parseName(c, kind + std::to_string(index), names);
  out.shape = parseShape(c, kind, base_dir);
  out.pose = parsePose(c);
  out.friction = c.number("friction", out.friction);
  if (out.friction < 0.0) failKey(c.key("friction"), "must not be negative");
  if (c.has("motion")) out.motion = parseMotion(c.get("motion"), c.key("motion"));
  c.done();
  return out;
}

void parseWorld(const YAML::Node& node, SimulationScene& scene) {
  YamlSection w(node, "world");
  WorldSettings& ws = scene.world;
  HybridShellSettings& sh = scene.shell;
  ws.grid_spacing = w.number("grid_spacing", 0.0);
  if (ws.grid_spacing < 0.0) failKey(w.key("grid_spacing"), "must not be negative (0: derived)");
  ws.kernel_degree = w.integer("kernel_degree", ws.kernel_degree, 2);
  if (ws.kernel_degree > 3) failKey(w.key("kernel_degree"), "must be 2 or 3");
  ws.body_friction = w.number("body_friction", ws.body_friction);
  if (ws.body_friction < 0.0) failKey(w.key("body_friction"), "must not be negative");
  ws.contact_distance = w.number("contact_distance", 0.0);
  if (ws.contact_distance < 0.0)
    failKey(w.key("contact_distance"), "must not be negative (0: a quarter of dx)");
  sh.damping = w.number("damping", sh.damping);
  if (sh.damping < 0.0) failKey(w.key("damping"), "must not be negative (1/s)");
  const std::string integration = w.text("integration", "symplectic_euler");
  try {
    sh.integration = timeIntegrationFromName(integration);
  } catch (const InputError& e) {
    failKey(w.key("integration"), e.what());
  }
  sh.max_time_step = w.positive("max_time_step", sh.max_time_step);
  sh.safety = w.positive("safety", sh.safety);
  sh.cfl = w.positive("cfl", sh.cfl);
  ws.cfl = sh.cfl;  // between bodies as within each
  ws.max_particles = w.integer("max_particles", ws.max_particles, 1);
  sh.lagrangian_tolerance = w.positive("lagrangian_tolerance", sh.lagrangian_tolerance);
  sh.lagrangian_gravity_fraction =
      w.number("lagrangian_gravity_fraction", sh.lagrangian_gravity_fraction);
  if (!(sh.lagrangian_gravity_fraction >= 0.0 && sh.lagrangian_gravity_fraction < 1.0))
    failKey(w.key("lagrangian_gravity_fraction"), "must lie in [0, 1)");
  sh.elastic_max_iterations = w.integer("elastic_max_iterations", sh.elastic_max_iterations, 1);
  sh.obstacle_stiffness = w.number("obstacle_stiffness", sh.obstacle_stiffness);
  sh.obstacle_point_stiffness = w.number("obstacle_point_stiffness", sh.obstacle_point_stiffness);
  if (sh.obstacle_stiffness < 0.0 || sh.obstacle_point_stiffness < 0.0)
    failKey(w.key(sh.obstacle_stiffness < 0.0 ? "obstacle_stiffness" : "obstacle_point_stiffness"),
            "must not be negative (0 leaves the obstacles to the grid)");
  sh.obstacle_offset = w.positive("obstacle_offset", sh.obstacle_offset);
  sh.obstacle_friction_velocity =
      w.positive("obstacle_friction_velocity", sh.obstacle_friction_velocity);
  sh.contact_between_layers_only =
      w.boolean("contact_between_layers_only", sh.contact_between_layers_only);
  sh.cfl_between_layers_only = w.boolean("cfl_between_layers_only", sh.cfl_between_layers_only);
  sh.flip_blend = w.number("flip_blend", sh.flip_blend);
  if (!(sh.flip_blend >= 0.0 && sh.flip_blend <= 1.0))
    failKey(w.key("flip_blend"), "must lie in [0, 1]");
  sh.display_segments = w.integer("display_segments", sh.display_segments, 1);
  w.done();
  sh.grid_spacing = ws.grid_spacing;
  sh.kernel_degree = ws.kernel_degree;
}

SimulationScene parse(const YAML::Node& root, const std::string& base_dir,
                      const std::string& name) {
  if (!root || root.IsNull()) failKey("scene", "is empty");
  YamlSection s(root, "");
  SimulationScene scene;
  scene.name = s.text("name", name);
  if (scene.name.empty()) failKey("name", "must not be empty");
  scene.duration = s.positive("duration", scene.duration);
  scene.frame_rate = s.positive("frame_rate", scene.frame_rate);
  scene.max_substeps_per_frame =
      s.integer("max_substeps_per_frame", scene.max_substeps_per_frame, 1);
  if (scene.numFrames() > 1000000) failKey("frame_rate", "gives more than a million frames");
  scene.gravity = s.vector3("gravity", scene.gravity);
  if (s.has("world")) parseWorld(s.get("world"), scene);
  std::set<std::string> body_names, collider_names;
  if (YAML::Node bodies = s.get("bodies")) {
    if (!bodies.IsSequence()) failKey("bodies", "must be a list");
    for (std::size_t i = 0; i < bodies.size(); ++i)
      scene.bodies.push_back(parseBody(bodies[i], indexed("bodies", i), "body" + std::to_string(i),
                                       base_dir, scene.gravity, body_names));
  }
  if (YAML::Node hair = s.get("hair")) {
    if (!hair.IsSequence()) failKey("hair", "must be a list");
    for (std::size_t i = 0; i < hair.size(); ++i)
      scene.hair.push_back(
          parseHair(hair[i], indexed("hair", i), "hair" + std::to_string(i), base_dir, body_names));
  }
  if (scene.bodies.empty() && scene.hair.empty())
    failKey("bodies", "the scene needs at least one body or hair");
  if (YAML::Node colliders = s.get("colliders")) {
    if (!colliders.IsSequence()) failKey("colliders", "must be a list");
    for (std::size_t i = 0; i < colliders.size(); ++i)
      scene.colliders.push_back(
          parseCollider(colliders[i], indexed("colliders", i), i, base_dir, collider_names));
  }
  s.done();
  for (std::size_t k = 0; k < scene.hair.size(); ++k) {
    SimulationHair& h = scene.hair[k];
    if (h.roots == "fixed" || h.roots == "loose") continue;
    for (std::size_t c = 0; c < scene.colliders.size(); ++c)
      if (scene.colliders[c].name == h.roots) h.root_collider = static_cast<int>(c);
    if (h.root_collider < 0)
      failKey(indexed("hair", k) + ".roots",
              "'" + h.roots + "' is neither fixed, loose nor a collider's name");
  }
  return scene;
}

}  // namespace

int SimulationScene::numFrames() const {
  return static_cast<int>(std::ceil(duration * frame_rate - 1e-9));
}

SimulationScene parseSimulationScene(const std::string& yaml_text, const std::string& base_dir,
                                     const std::string& name) {
  const YAML::Node root = loadYaml(yaml_text);
  try {
    return parse(root, base_dir, name);
  } catch (const YAML::Exception& e) {  // a shape the checks above did not foresee
    failYaml(e);
  }
}

SimulationScene loadSimulationScene(const std::string& path) {
  const std::string text = readSceneFile(path);
  const std::filesystem::path p(path);
  try {
    SimulationScene scene = parseSimulationScene(text, p.parent_path().string(), p.stem().string());
    scene.file = path;
    return scene;
  } catch (const InputError& e) {
    throw InputError(path + ": " + e.what());
  }
}

}  // namespace chs
