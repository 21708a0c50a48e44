#include "cloth_hair_sim/core/io/scene.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include <yaml-cpp/yaml.h>
#include <Eigen/Geometry>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/io/mesh_reader.h"
#include "cloth_hair_sim/core/io/triangle_mesh_reader.h"
#include "cloth_hair_sim/core/mesh/grid_generators.h"
#include "scene_panels.h"
#include "scene_yaml.h"

namespace chs {

namespace {

// The checked YAML reading is shared with simulation scenes (scene_yaml.h).
using Section = YamlSection;

[[noreturn]] void fail(const std::string& key, const std::string& what) {
  failKey(key, what);
}

QuadMesh parseGarment(const YAML::Node& node, const std::string& base_dir) {
  Section g(node, "garment");
  const std::string kind = kindOf(g, {"rectangle", "disc", "file", "panels"}, "garment");
  if (kind == "rectangle") {
    Section r(g.get(kind), "garment.rectangle");
    const Eigen::Vector2d size = r.vector("size", 2);
    const Eigen::VectorXd cells = r.vector("cells", 2);
    const Eigen::Vector3d centre = r.vector3("centre", Eigen::Vector3d::Zero());
    r.done();
    g.done();
    for (int i = 0; i < 2; ++i) {
      if (!(size[i] > 0.0)) fail("garment.rectangle.size", "must be positive");
      if (cells[i] < 1 || cells[i] != std::floor(cells[i]) || cells[i] > 1e5)
        fail("garment.rectangle.cells", "must be positive integers");
    }
    return makeRectangleMesh(size[0], size[1], static_cast<int>(cells[0]),
                             static_cast<int>(cells[1]), centre);
  }
  if (kind == "disc") {
    Section d(g.get(kind), "garment.disc");
    const double radius = d.positive("radius");
    const int cells = d.integer("cells", 0, 3);
    if (!d.has("cells")) fail("garment.disc.cells", "missing");
    const Eigen::Vector3d centre = d.vector3("centre", Eigen::Vector3d::Zero());
    d.done();
    g.done();
    return makeDiscMesh(radius, cells, centre);
  }
  const YAML::Node f = g.get("file");
  std::string path;
  double scale = 1.0;
  Eigen::Vector3d translate = Eigen::Vector3d::Zero();
  if (f.IsScalar()) {
    path = f.as<std::string>();
  } else {
    Section fs(f, "garment.file");
    path = fs.text("path", "");
    if (path.empty()) fail("garment.file.path", "missing");
    scale = fs.positive("scale", 1.0);
    translate = fs.vector3("translate", translate);
    fs.done();
  }
  g.done();
  const std::filesystem::path p(path);
  QuadMesh mesh =
      readQuadMesh(p.is_absolute() ? path : (std::filesystem::path(base_dir) / p).string(), scale);
  for (auto& v : mesh.vertices) v += translate;
  return mesh;
}

// Edge rounding of tables, boxes and pedestals (m): optional key edge_radius.
double edgeRadius(Section& s, double fallback) {
  const double r = s.number("edge_radius", fallback);
  if (!(r >= 0.0)) fail(s.key("edge_radius"), "must not be negative (m)");
  return r;
}

// A closed triangle mesh file (any assimp format) as a distance field, posed in the world.
void parseMeshCollider(Section& s, const std::string& base_dir, ColliderSpec& c) {
  c.type = ColliderSpec::Type::kMesh;
  const std::string file = s.text("file", "");
  if (file.empty()) fail(s.key("file"), "missing (a closed triangle mesh, e.g. .stl, .obj, .dae)");
  const std::filesystem::path p(file);
  c.mesh_file = p.is_absolute() ? file : (std::filesystem::path(base_dir) / p).string();
  Eigen::Vector3d scale = Eigen::Vector3d::Ones();
  if (s.has("scale")) {
    const YAML::Node n = s.get("scale");
    scale = n.IsSequence() ? Eigen::Vector3d(Section::toVector(n, s.key("scale"), 3))
                           : Eigen::Vector3d::Constant(Section::toNumber(n, s.key("scale")));
    if (!(scale.array() > 0.0).all()) fail(s.key("scale"), "must be positive");
  }
  c.pose = parseRigidPose(s);
  const std::vector<std::string> parts = s.names("parts");
  MeshSdfResolution resolution;
  if (s.has("voxel_size")) resolution.voxel_size = s.positive("voxel_size");
  s.done();  // unknown keys before the file is read and its field built (seconds for a body)
  TriangleMesh mesh;
  try {
    mesh = readTriangleMesh(c.mesh_file, scale, parts);  // its errors name the file
  } catch (const InputError& e) {
    fail(s.key("file"), e.what());
  }
  try {
    c.mesh_field = std::make_shared<const MeshSdfSurface>(mesh, resolution);
  } catch (const InputError& e) {
    fail(s.key("file"), c.mesh_file + ": " + e.what());
  }
}

// A capsule by its cap centres {a, b, radius} or by {centre, axis, length, radius}, where length
// is the distance between the cap centres (as ColliderShape, SDF and URDF capsules).
void parseCapsule(Section& s, ColliderSpec& c) {
  c.type = ColliderSpec::Type::kCapsule;
  c.radius = s.positive("radius");
  if (s.has("a") || s.has("b")) {
    if (s.has("centre")) fail(s.key("centre"), "give either a and b or centre, axis and length");
    c.end_a = s.vector("a", 3);
    c.end_b = s.vector("b", 3);
  } else {
    const Eigen::Vector3d centre = s.vector("centre", 3);
    const Eigen::Vector3d axis = s.vector("axis", 3);
    if (!(axis.norm() > 0.0)) fail(s.key("axis"), "must not be zero");
    const double length = s.number("length");
    if (length < 0.0) fail(s.key("length"), "must not be negative (0 is a sphere)");
    c.end_a = centre - 0.5 * length * axis.normalized();
    c.end_b = centre + 0.5 * length * axis.normalized();
  }
}

ColliderSpec parseCollider(const YAML::Node& node, const std::string& key,
                           const std::string& base_dir) {
  if (!node.IsMap() || node.size() != 1)
    fail(key,
         "a collider is a mapping with one key: plane, table, box, pedestal, cylinder, sphere, "
         "capsule or mesh");
  Section outer(node, key);
  const std::string kind =
      kindOf(outer, {"plane", "table", "box", "pedestal", "cylinder", "sphere", "capsule", "mesh"},
             "collider");
  Section s(outer.get(kind), key + "." + kind);
  ColliderSpec c;
  c.label = kind;
  if (kind == "plane") {
    c.type = ColliderSpec::Type::kPlane;
    c.point = s.vector3("point", Eigen::Vector3d::Zero());
    c.normal = s.vector3("normal", Eigen::Vector3d::UnitZ());
    if (!(c.normal.norm() > 0.0)) fail(s.key("normal"), "must not be zero");
  } else if (kind == "table") {  // a box given by its top face, which carries the cloth
    c.type = ColliderSpec::Type::kBox;
    const Eigen::Vector3d top = s.vector3("top_centre", Eigen::Vector3d::Zero());
    const Eigen::Vector2d size = s.vector("size", 2);
    const double depth = s.positive("depth", 0.5);
    if (!(size.minCoeff() > 0.0)) fail(s.key("size"), "must be positive");
    c.lo = top - Eigen::Vector3d(size.x() / 2, size.y() / 2, depth);
    c.hi = top + Eigen::Vector3d(size.x() / 2, size.y() / 2, 0.0);
    // Real table edges are rounded; a sharp one lets node contact push cloth off sideways.
    c.edge_radius = edgeRadius(s, std::min({size.minCoeff() / 100.0, depth / 2, 1e-3}));
  } else if (kind == "box") {
    c.type = ColliderSpec::Type::kBox;
    c.lo = s.vector("min", 3);
    c.hi = s.vector("max", 3);
    if ((c.hi.array() <= c.lo.array()).any()) fail(s.key("max"), "must exceed min in x, y and z");
    c.edge_radius = edgeRadius(s, 0.0);
  } else if (kind == "pedestal" || kind == "cylinder") {  // vertical, given by its top face
    c.type = ColliderSpec::Type::kCylinder;
    const Eigen::Vector3d top = s.vector3("top_centre", Eigen::Vector3d::Zero());
    c.radius = s.positive("radius");
    const double depth = s.positive("depth", 0.5);
    c.axis_xy = top.head<2>();
    c.z_top = top.z();
    c.z_bottom = top.z() - depth;
    c.edge_radius = edgeRadius(s, std::min({c.radius / 100.0, depth / 2, 1e-3}));
  } else if (kind == "sphere") {
    c.type = ColliderSpec::Type::kSphere;
    c.point = s.vector3("centre", Eigen::Vector3d::Zero());
    c.radius = s.positive("radius");
  } else if (kind == "capsule") {
    parseCapsule(s, c);
  } else {
    parseMeshCollider(s, base_dir, c);
  }
  s.done();
  return c;
}

BoundaryConditions parseBoundary(const YAML::Node& node, const QuadMesh& mesh) {
  Section s(node, "boundary");
  BoundaryConditions bc;
  if (s.has("clamped")) bc.clamped = selectVertices(s.get("clamped"), "boundary.clamped", mesh);
  if (s.has("pinned")) bc.pinned = selectVertices(s.get("pinned"), "boundary.pinned", mesh);
  auto list = [&](const std::string& k) {
    YAML::Node n = s.get(k);
    if (n && !n.IsSequence()) fail(s.key(k), "must be a list");
    return n;
  };
  if (YAML::Node fixed = list("fixed")) {
    for (std::size_t i = 0; i < fixed.size(); ++i) {
      const std::string key = "boundary.fixed[" + std::to_string(i) + "]";
      Section f(fixed[i], key);
      const auto verts = selectVertices(f.require("vertices"), f.key("vertices"), mesh);
      const YAML::Node axes = f.require("axes");
      if (!axes.IsSequence() || axes.size() == 0) fail(f.key("axes"), "must be a list of x, y, z");
      for (const auto& a : axes) {
        const std::string name = a.IsScalar() ? a.Scalar() : "";
        const int axis = name == "x" ? 0 : name == "y" ? 1 : name == "z" ? 2 : -1;
        if (axis < 0) fail(f.key("axes"), "must name x, y or z, got '" + name + "'");
        for (int v : verts) bc.fixed_components.push_back({v, axis});
      }
      f.done();
    }
  }
  if (YAML::Node loads = list("loads")) {
    for (std::size_t i = 0; i < loads.size(); ++i) {
      const std::string key = "boundary.loads[" + std::to_string(i) + "]";
      Section l(loads[i], key);
      const auto verts = selectVertices(l.require("vertices"), l.key("vertices"), mesh);
      NodalLoad load;
      load.force = l.vector3("force", Eigen::Vector3d::Zero());
      load.moment = l.vector3("moment", Eigen::Vector3d::Zero());
      l.done();
      for (int v : verts) {
        load.vertex = v;
        bc.loads.push_back(load);
      }
    }
  }
  s.done();
  return bc;
}

FemShellSettings parseFemShell(const YAML::Node& node) {
  Section s(node, "fem_shell");
  FemShellSettings f;
  f.tolerance = s.positive("tolerance", f.tolerance);
  f.max_iterations_per_step = s.integer("max_iterations_per_step", f.max_iterations_per_step, 1);
  f.target_iterations = s.integer("target_iterations", f.target_iterations, 1);
  f.initial_load_increment = s.positive("initial_load_increment", f.initial_load_increment);
  f.max_load_increment = s.positive("max_load_increment", f.max_load_increment);
  f.max_load_steps = s.integer("max_load_steps", f.max_load_steps, 1);
  f.max_cutbacks = s.integer("max_cutbacks", f.max_cutbacks, 0);
  f.contact_stiffness = s.number("contact_stiffness", f.contact_stiffness);
  if (f.contact_stiffness < 0.0)
    fail(s.key("contact_stiffness"), "must not be negative (0 picks one)");
  f.arc_length = s.boolean("arc_length", f.arc_length);
  f.stabilization = s.number("stabilization", f.stabilization);
  if (f.stabilization < 0.0) fail(s.key("stabilization"), "must not be negative (0 = off)");
  f.max_settling_steps = s.integer("max_settling_steps", f.max_settling_steps, 0);
  f.imperfection = s.number("imperfection", f.imperfection);
  if (f.imperfection < 0.0) fail(s.key("imperfection"), "must not be negative (m)");
  f.imperfection_seed = static_cast<unsigned>(s.integer("imperfection_seed", 1, 0));
  const std::string shape = s.text("imperfection_shape", "random");
  if (shape == "waves")
    f.imperfection_shape = FemShellSettings::Imperfection::kWaves;
  else if (shape != "random")
    fail(s.key("imperfection_shape"), "must be random or waves, got '" + shape + "'");
  f.imperfection_waves = s.integer("imperfection_waves", f.imperfection_waves, 1);
  const std::string solver = s.text("solver", "auto");
  if (solver == "energy_newton")
    f.solver = FemShellMethod::kEnergyNewton;
  else if (solver == "arc_length")
    f.solver = FemShellMethod::kArcLength;
  else if (solver != "auto")
    fail(s.key("solver"), "must be auto, energy_newton or arc_length, got '" + solver + "'");
  f.max_iterations = s.integer("max_iterations", f.max_iterations, 1);
  f.max_saddle_escapes = s.integer("max_saddle_escapes", f.max_saddle_escapes, 0);
  f.edge_contact = s.boolean("edge_contact", f.edge_contact);
  f.seam_steps = s.integer("seam_steps", f.seam_steps, 1);
  f.coarse_levels = s.integer("coarse_levels", f.coarse_levels, 0);
  s.done();
  if (f.tolerance >= 1.0) fail(s.key("tolerance"), "must be below 1 (a relative residual)");
  if (f.initial_load_increment > f.max_load_increment)
    fail(s.key("initial_load_increment"), "must not exceed max_load_increment");
  return f;
}

ParticleSettings parseParticle(const YAML::Node& node) {
  Section s(node, "particle");
  ParticleSettings p;
  p.network.stretch_compression = s.positive("stretch_compression", p.network.stretch_compression);
  p.network.shear_compression = s.positive("shear_compression", p.network.shear_compression);
  auto nonNegative = [&](const char* k, double fallback) {
    const double x = s.number(k, fallback);
    if (x < 0.0) fail(s.key(k), "must not be negative (0 picks a default)");
    return x;
  };
  p.c_disp = nonNegative("c_disp", p.c_disp);
  p.c_acc = nonNegative("c_acc", p.c_acc);
  p.momentum = s.number("momentum", p.momentum);
  if (!(p.momentum >= 0.0 && p.momentum < 1.0)) fail(s.key("momentum"), "must lie in [0, 1)");
  p.restart = s.boolean("restart", p.restart);
  p.displacement_tolerance = s.positive("displacement_tolerance", p.displacement_tolerance);
  p.force_tolerance = s.positive("force_tolerance", p.force_tolerance);
  p.max_iterations = s.integer("max_iterations", p.max_iterations, 1);
  p.progress_interval = s.integer("progress_interval", p.progress_interval, 1);
  p.contact_tolerance = nonNegative("contact_tolerance", p.contact_tolerance);
  p.sewing_stiffness = nonNegative("sewing_stiffness", p.sewing_stiffness);
  p.seam_join_distance = nonNegative("seam_join_distance", p.seam_join_distance);
  p.max_sewing_iterations = s.integer("max_sewing_iterations", p.max_sewing_iterations, 1);
  s.done();
  return p;
}

// An orthotropic woven fabric: {woven: preset | {preset, fields}, warp: [x, y, z]}. Sets the
// problem's fabric and, for validation and the weight, its isotropic equivalent (the same
// thickness and density, E from the mean bending rigidity).
void parseWoven(const YAML::Node& node, Scene& scene) {
  Section s(node, "material");
  WovenFabric f;
  const YAML::Node w = s.get("woven");
  auto preset = [&](const std::string& name, const std::string& key) {
    auto p = wovenFabricPreset(name);
    if (!p) {
      std::string names;
      for (const auto& n : wovenFabricPresetNames()) names += (names.empty() ? "" : ", ") + n;
      fail(key, "unknown woven fabric preset '" + name + "' (known: " + names + ")");
    }
    return *p;
  };
  if (w.IsScalar()) {
    scene.material_name = w.Scalar();
    f = preset(w.Scalar(), "material.woven");
  } else {
    Section ws(w, "material.woven");
    const bool has_preset = ws.has("preset");
    scene.material_name = has_preset ? ws.text("preset", "") : "custom woven";
    if (has_preset) f = preset(scene.material_name, ws.key("preset"));
    auto value = [&](const char* k, double& field) {
      if (ws.has(k))
        field = ws.number(k);
      else if (!has_preset)
        fail(ws.key(k), "missing (no preset to take it from)");
    };
    value("tensile_warp", f.tensile_warp);
    value("tensile_weft", f.tensile_weft);
    value("poisson", f.poisson);
    value("shear", f.shear);
    value("bending_warp", f.bending_warp);
    value("bending_weft", f.bending_weft);
    value("thickness", f.thickness);
    value("areal_density", f.areal_density);
    ws.done();
  }
  if (!s.has("warp"))
    fail("material.warp",
         "missing: an orthotropic fabric needs the direction of its warp yarns in the flat "
         "garment, e.g. warp: [1, 0, 0]");
  f.warp = s.vector("warp", 3);
  s.done();
  try {
    f.validate();
  } catch (const InputError& e) {
    fail("material", e.what());
  }
  ShellMaterial& m = scene.problem.material;
  m.poisson = f.poisson;
  m.thickness = f.thickness;
  m.areal_density = f.areal_density;
  m.young = 12.0 * (1.0 - f.poisson * f.poisson) * std::sqrt(f.bending_warp * f.bending_weft) /
            std::pow(f.thickness, 3);
  scene.problem.fabric = f;
  scene.material_name = "woven " + scene.material_name;
}

SolidShellSettings parseSolidShell(const YAML::Node& node) {
  Section s(node, "solid_shell");
  SolidShellSettings o;
  const std::string scheme = s.text("scheme", "static");
  try {
    o.scheme = parseSolidShellScheme(scheme);
  } catch (const InputError&) {
    fail(s.key("scheme"), "must be static, dynamic or energy, got '" + scheme + "'");
  }
  const std::string strain = s.text("thickness_strain", "green");
  if (strain != "green" && strain != "quasi_engineering")
    fail(s.key("thickness_strain"), "must be green or quasi_engineering, got '" + strain + "'");
  o.thickness_strain =
      strain == "green" ? ThicknessStrain::kGreen : ThicknessStrain::kQuasiEngineering;
  o.mu = s.number("mu", o.mu);
  o.tolerance = s.positive("tolerance", o.tolerance);
  o.multiplier = s.positive("multiplier", o.multiplier);
  o.free_length = s.number("free_length", o.free_length);
  o.max_iterations = s.integer("max_iterations", o.max_iterations, 1);
  o.damping = s.number("damping", o.damping);
  o.mass_scaling = s.positive("mass_scaling", o.mass_scaling);
  o.time_step = s.number("time_step", o.time_step);
  o.end_time = s.positive("end_time", o.end_time);
  o.contact_stiffness = s.number("contact_stiffness", o.contact_stiffness);
  o.progress_interval = s.integer("progress_interval", o.progress_interval, 1);
  o.adaptive_levels = s.integer("adaptive_levels", o.adaptive_levels, 0);
  o.refine_threshold = s.number("refine_threshold", o.refine_threshold);
  o.merge_margin = s.number("merge_margin", o.merge_margin);
  o.adapt_interval = s.integer("adapt_interval", o.adapt_interval, 1);
  o.adapt_iterations = s.integer("adapt_iterations", o.adapt_iterations, 1);
  s.done();
  try {
    validateSolidShellSettings(o);
  } catch (const InputError& e) {
    fail("solid_shell", e.what());
  }
  return o;
}

SceneOutput parseOutput(const YAML::Node& node, SceneOutput out) {
  Section s(node, "output");
  out.directory = s.text("directory", out.directory);
  out.obj = s.text("obj", out.obj);
  out.ply = s.text("ply", out.ply);
  out.report = s.text("report", out.report);
  out.convergence = s.text("convergence", out.convergence);
  out.picture = s.text("picture", out.picture);
  s.done();
  for (const auto* f :
       {&out.directory, &out.obj, &out.ply, &out.report, &out.convergence, &out.picture})
    if (f->empty()) fail("output", "file names must not be empty");
  return out;
}

Scene parse(const YAML::Node& root, const std::string& base_dir, const std::string& name) {
  if (!root || root.IsNull()) fail("scene", "is empty");
  Section s(root, "");
  Scene scene;
  scene.name = s.text("name", name);
  if (scene.name.empty()) fail("name", "must not be empty");
  scene.method = parseMethod(s.text("method", "fem_shell"));
  scene.problem.gravity = s.vector3("gravity", scene.problem.gravity);
  const YAML::Node garment = s.require("garment");
  GarmentPanels panels;
  if (garment.IsMap() && garment["panels"]) {
    panels = parsePanels(garment, base_dir);
    scene.problem.mesh = panels.mesh;
  } else {
    scene.problem.mesh = parseGarment(garment, base_dir);
  }
  if (s.has("seams")) scene.problem.seams = parseSeams(s.get("seams"), panels);
  const YAML::Node material = s.require("material");
  if (material.IsMap() && material["woven"])
    parseWoven(material, scene);
  else if (material.IsScalar() && wovenFabricPreset(material.Scalar()))
    fail("material", "'" + material.Scalar() +
                         "' is an orthotropic woven fabric and needs its warp direction: write "
                         "{woven: " +
                         material.Scalar() + ", warp: [x, y, z]}");
  else
    scene.problem.material = parseMaterial(material, "material", scene.material_name);
  if (YAML::Node colliders = s.get("colliders")) {
    if (!colliders.IsSequence()) fail("colliders", "must be a list");
    for (std::size_t i = 0; i < colliders.size(); ++i) {
      scene.colliders.push_back(
          parseCollider(colliders[i], "colliders[" + std::to_string(i) + "]", base_dir));
      scene.problem.colliders.push_back(scene.colliders.back().makeSurface());
    }
  }
  if (s.has("boundary")) scene.problem.bc = parseBoundary(s.get("boundary"), scene.problem.mesh);
  if (s.has("fem_shell")) scene.fem_shell = parseFemShell(s.get("fem_shell"));
  if (s.has("particle")) scene.particle = parseParticle(s.get("particle"));
  if (s.has("solid_shell")) scene.solid_shell = parseSolidShell(s.get("solid_shell"));
  scene.output.directory = "drape_output/" + scene.name;
  if (s.has("output")) scene.output = parseOutput(s.get("output"), scene.output);
  s.done();
  scene.problem.validate();
  return scene;
}

}  // namespace

std::string methodName(DrapeMethod method) {
  switch (method) {
    case DrapeMethod::kFemShell:
      return "fem_shell";
    case DrapeMethod::kParticle:
      return "particle";
    case DrapeMethod::kSolidShell:
      return "solid_shell";
  }
  return "unknown";
}

DrapeMethod parseMethod(const std::string& name) {
  if (name == "fem_shell") return DrapeMethod::kFemShell;
  if (name == "particle") return DrapeMethod::kParticle;
  if (name == "solid_shell") return DrapeMethod::kSolidShell;
  throw InputError("method: must be fem_shell, particle or solid_shell, got '" + name + "'");
}

Scene parseScene(const std::string& yaml_text, const std::string& base_dir,
                 const std::string& name) {
  const YAML::Node root = loadYaml(yaml_text);
  try {
    return parse(root, base_dir, name);
  } catch (const YAML::Exception& e) {  // a shape the checks above did not foresee
    failYaml(e);
  }
}

Scene loadScene(const std::string& path) {
  const std::string text = readSceneFile(path);
  const std::filesystem::path p(path);
  try {
    Scene scene = parseScene(text, p.parent_path().string(), p.stem().string());
    scene.file = path;
    return scene;
  } catch (const InputError& e) {
    throw InputError(path + ": " + e.what());
  }
}

std::vector<std::pair<std::string, double>> settingsList(const FemShellSettings& s) {
  return {
      {"tolerance", s.tolerance},
      {"max_iterations_per_step", s.max_iterations_per_step},
      {"target_iterations", s.target_iterations},
      {"initial_load_increment", s.initial_load_increment},
      {"max_load_increment", s.max_load_increment},
      {"max_load_steps", s.max_load_steps},
      {"max_cutbacks", s.max_cutbacks},
      {"contact_stiffness", s.contact_stiffness},
      {"arc_length", s.arc_length ? 1.0 : 0.0},
      {"stabilization", s.stabilization},
      {"max_settling_steps", s.max_settling_steps},
      {"imperfection", s.imperfection},
      {"imperfection_seed", static_cast<double>(s.imperfection_seed)},
      {"imperfection_waves",
       s.imperfection_shape == FemShellSettings::Imperfection::kWaves ? s.imperfection_waves : 0},
      {"solver", static_cast<double>(s.solver)},  // 0 auto, 1 energy_newton, 2 arc_length
      {"max_iterations", s.max_iterations},
      {"max_saddle_escapes", s.max_saddle_escapes},
      {"edge_contact", s.edge_contact ? 1.0 : 0.0},
      {"seam_steps", s.seam_steps},
      {"coarse_levels", s.coarse_levels}};
}

std::vector<std::pair<std::string, double>> settingsList(const ParticleSettings& s) {
  return {{"stretch_compression", s.network.stretch_compression},
          {"shear_compression", s.network.shear_compression},
          {"c_disp", s.c_disp},
          {"c_acc", s.c_acc},
          {"momentum", s.momentum},
          {"restart", s.restart ? 1.0 : 0.0},
          {"displacement_tolerance", s.displacement_tolerance},
          {"force_tolerance", s.force_tolerance},
          {"max_iterations", s.max_iterations},
          {"progress_interval", s.progress_interval},
          {"contact_tolerance", s.contact_tolerance},
          {"sewing_stiffness", s.sewing_stiffness},
          {"seam_join_distance", s.seam_join_distance},
          {"max_sewing_iterations", s.max_sewing_iterations}};
}

std::vector<std::pair<std::string, double>> materialList(const ShellMaterial& m) {
  return {{"young_Pa", m.young},
          {"poisson", m.poisson},
          {"thickness_m", m.thickness},
          {"areal_density_kg_m2", m.areal_density},
          {"shear_correction", m.shear_correction},
          {"bending_rigidity_Nm", m.bendingStiffness()}};
}

std::vector<std::pair<std::string, double>> settingsList(const SolidShellSettings& s) {
  return {{"dynamic", s.scheme == SolidShellScheme::kDynamic ? 1.0 : 0.0},
          {"energy", s.scheme == SolidShellScheme::kEnergy ? 1.0 : 0.0},
          {"quasi_engineering_thickness_strain",
           s.thickness_strain == ThicknessStrain::kQuasiEngineering ? 1.0 : 0.0},
          {"mu", s.mu},
          {"tolerance", s.tolerance},
          {"multiplier", s.multiplier},
          {"free_length", s.free_length},
          {"max_iterations", s.max_iterations},
          {"damping", s.damping},
          {"mass_scaling", s.mass_scaling},
          {"time_step", s.time_step},
          {"end_time", s.end_time},
          {"contact_stiffness", s.contact_stiffness},
          {"adaptive_levels", s.adaptive_levels},
          {"refine_threshold", s.refine_threshold},
          {"merge_margin", s.merge_margin},
          {"adapt_interval", s.adapt_interval},
          {"adapt_iterations", s.adapt_iterations}};
}

std::vector<std::pair<std::string, double>> materialList(const WovenFabric& f) {
  return {{"tensile_warp_N_m", f.tensile_warp},
          {"tensile_weft_N_m", f.tensile_weft},
          {"poisson", f.poisson},
          {"shear_N_m", f.shear},
          {"bending_warp_Nm", f.bending_warp},
          {"bending_weft_Nm", f.bending_weft},
          {"thickness_m", f.thickness},
          {"areal_density_kg_m2", f.areal_density},
          {"warp_x", f.warp.x()},
          {"warp_y", f.warp.y()},
          {"warp_z", f.warp.z()}};
}

}  // namespace chs
