#include "scene_panels.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <set>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/io/mesh_reader.h"
#include "cloth_hair_sim/core/mesh/boundary_edges.h"
#include "cloth_hair_sim/core/mesh/grid_generators.h"
#include "scene_yaml.h"

namespace chs {

namespace {

QuadMesh parsePanelMesh(YamlSection& p, const std::string& base_dir, GarmentPanel& panel) {
  const std::string kind = kindOf(p, {"rectangle", "file"}, "panel");
  if (kind == "rectangle") {
    YamlSection r(p.get(kind), p.key(kind));
    const Eigen::Vector2d size = r.vector("size", 2);
    const Eigen::VectorXd cells = r.vector("cells", 2);
    r.done();
    for (int i = 0; i < 2; ++i) {
      if (!(size[i] > 0.0)) failKey(r.key("size"), "must be positive");
      if (cells[i] < 1 || cells[i] != std::floor(cells[i]) || cells[i] > 1e5)
        failKey(r.key("cells"), "must be positive integers");
    }
    panel.nx = static_cast<int>(cells[0]);
    panel.ny = static_cast<int>(cells[1]);
    return makeRectangleMesh(size[0], size[1], panel.nx, panel.ny);
  }
  const YAML::Node f = p.get("file");
  std::string path;
  double scale = 1.0;
  if (f.IsScalar()) {
    path = f.as<std::string>();
  } else {
    YamlSection fs(f, p.key("file"));
    path = fs.text("path", "");
    if (path.empty()) failKey(fs.key("path"), "missing");
    scale = fs.positive("scale", 1.0);
    fs.done();
  }
  const std::filesystem::path fp(path);
  try {
    return readQuadMesh(fp.is_absolute() ? path : (std::filesystem::path(base_dir) / fp).string(),
                        scale);
  } catch (const InputError& e) {
    failKey(p.key("file"), e.what());
  }
}

// Panels are cut flat: the sewing, not the reference state, gives the garment its shape.
void checkFlat(const QuadMesh& mesh, double tolerance, const std::string& key) {
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  Eigen::AlignedBox3d box;
  for (const auto& x : mesh.vertices) centroid += x, box.extend(x);
  centroid /= static_cast<double>(mesh.numVertices());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const auto& x : mesh.vertices) cov += (x - centroid) * (x - centroid).transpose();
  const Eigen::Vector3d normal =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(cov).eigenvectors().col(0);
  const double tol = tolerance > 0.0 ? tolerance : 1e-4 * box.diagonal().norm();
  int worst = 0;
  double off = 0.0;
  for (int v = 0; v < mesh.numVertices(); ++v) {
    const double d = std::abs(normal.dot(mesh.vertices[v] - centroid));
    if (d > off) off = d, worst = v;
  }
  if (off > tol)
    failKey(key, "is not flat: its vertex " + std::to_string(worst) + " lies " + str(off) +
                     " m off the panel's best-fit plane (tolerance " + str(tol) +
                     " m, garment.flat_tolerance); panels are cut flat and the seams shape them");
}

struct Side {
  const GarmentPanel* panel = nullptr;
  std::vector<int> vertices;  // of the panel's own mesh
  std::string what;           // "panel front, side left"
};

Side parseSide(const YAML::Node& node, const std::string& key, const GarmentPanels& g) {
  YamlSection s(node, key);
  Side side;
  const std::string name = s.text("panel", "");
  if (name.empty()) failKey(s.key("panel"), "missing (the name of a garment panel)");
  std::string names;
  for (const auto& p : g.panels) {
    names += (names.empty() ? "" : ", ") + p.name;
    if (p.name == name) side.panel = &p;
  }
  if (!side.panel) failKey(s.key("panel"), "unknown panel '" + name + "' (panels: " + names + ")");
  const GarmentPanel& p = *side.panel;
  const std::string kind = kindOf(s, {"side", "vertices"}, "seam side");
  if (kind == "side") {
    const std::string which = s.text("side", "");
    if (p.nx == 0)
      failKey(s.key("side"), "panel '" + name +
                                 "' is a mesh file: only rectangle panels have named sides; list "
                                 "its boundary vertices instead");
    // Vertex (i, j) of a rectangle is j (nx + 1) + i (makeRectangleMesh); sides run along +x
    // (bottom, top) or +y (left, right) of the panel's own frame.
    if (which == "bottom" || which == "top") {
      for (int i = 0; i <= p.nx; ++i)
        side.vertices.push_back((which == "bottom" ? 0 : p.ny) * (p.nx + 1) + i);
    } else if (which == "left" || which == "right") {
      for (int j = 0; j <= p.ny; ++j)
        side.vertices.push_back(j * (p.nx + 1) + (which == "left" ? 0 : p.nx));
    } else {
      failKey(s.key("side"), "must be left, right, bottom or top, got '" + which + "'");
    }
    side.what = "panel " + name + ", side " + which;
  } else {
    const YAML::Node list = s.get("vertices");
    if (!list.IsSequence() || list.size() == 0)
      failKey(s.key("vertices"), "must be a list of the panel's vertex indices");
    std::set<int> boundary;
    for (const auto& e : boundaryEdges(p.mesh)) boundary.insert(e.begin(), e.end());
    std::set<int> seen;
    for (const auto& item : list) {
      const double x = YamlSection::toNumber(item, s.key("vertices"));
      const int v = static_cast<int>(x);
      if (x != v || v < 0 || v >= p.mesh.numVertices())
        failKey(s.key("vertices"), "panel '" + name + "' has vertices 0 to " +
                                       std::to_string(p.mesh.numVertices() - 1) + ", got " +
                                       str(x));
      if (!boundary.count(v))
        failKey(s.key("vertices"), "vertex " + std::to_string(v) + " of panel '" + name +
                                       "' is not on its boundary: seams join panel edges");
      if (!seen.insert(v).second)
        failKey(s.key("vertices"), "vertex " + std::to_string(v) + " is listed twice");
      side.vertices.push_back(v);
    }
    side.what = "panel " + name + ", " + std::to_string(side.vertices.size()) + " vertices";
  }
  s.done();
  return side;
}

double length(const Side& s) {
  double l = 0.0;
  for (std::size_t i = 1; i < s.vertices.size(); ++i)
    l += (s.panel->mesh.vertices[s.vertices[i]] - s.panel->mesh.vertices[s.vertices[i - 1]]).norm();
  return l;
}

}  // namespace

GarmentPanels parsePanels(const YAML::Node& garment, const std::string& base_dir) {
  YamlSection g(garment, "garment");
  const YAML::Node list = g.require("panels");
  if (!list.IsSequence() || list.size() == 0) failKey("garment.panels", "must be a list of panels");
  const double flat_tolerance = g.has("flat_tolerance") ? g.positive("flat_tolerance") : 0.0;
  g.done();
  GarmentPanels out;
  for (std::size_t i = 0; i < list.size(); ++i) {
    const std::string key = "garment.panels[" + std::to_string(i) + "]";
    YamlSection p(list[i], key);
    GarmentPanel panel;
    panel.name = p.text("name", "");
    if (panel.name.empty()) failKey(p.key("name"), "missing (seams name the panels)");
    for (const auto& other : out.panels)
      if (other.name == panel.name) failKey(p.key("name"), "'" + panel.name + "' is used twice");
    panel.mesh = parsePanelMesh(p, base_dir, panel);
    const Eigen::Isometry3d pose = parseRigidPose(p);
    p.done();
    checkFlat(panel.mesh, flat_tolerance, key);
    panel.first_vertex = out.mesh.numVertices();
    for (const auto& x : panel.mesh.vertices) out.mesh.vertices.push_back(pose * x);
    for (auto q : panel.mesh.quads) {
      for (int& v : q) v += panel.first_vertex;
      out.mesh.quads.push_back(q);
    }
    out.panels.push_back(std::move(panel));
  }
  return out;
}

std::vector<Seam> parseSeams(const YAML::Node& node, const GarmentPanels& panels) {
  if (!node.IsSequence() || node.size() == 0) failKey("seams", "must be a list of seams");
  if (panels.panels.empty())
    failKey("seams", "need a garment of panels (garment: {panels: [...]}) to sew");
  std::vector<Seam> seams;
  for (std::size_t i = 0; i < node.size(); ++i) {
    const std::string key = "seams[" + std::to_string(i) + "]";
    YamlSection s(node[i], key);
    const Side a = parseSide(s.require("a"), s.key("a"), panels);
    Side b = parseSide(s.require("b"), s.key("b"), panels);
    if (s.boolean("reverse", false)) std::reverse(b.vertices.begin(), b.vertices.end());
    s.done();
    if (a.vertices.size() != b.vertices.size())
      failKey(key, "sews " + std::to_string(a.vertices.size()) + " vertices (" + a.what + ") to " +
                       std::to_string(b.vertices.size()) + " (" + b.what +
                       "): both sides need as many vertices");
    const double la = length(a), lb = length(b);
    if (std::abs(la - lb) > 0.01 * std::max(la, lb))
      failKey(key, "sews a side " + str(la) + " m long (" + a.what + ") to one " + str(lb) +
                       " m long (" + b.what + "): the lengths must agree within 1%");
    Seam seam;
    for (std::size_t k = 0; k < a.vertices.size(); ++k) {
      const int va = a.panel->first_vertex + a.vertices[k];
      const int vb = b.panel->first_vertex + b.vertices[k];
      if (va == vb)
        failKey(key, "sews vertex " + std::to_string(a.vertices[k]) + " of panel " + a.panel->name +
                         " to itself");
      seam.side_a.push_back(va);
      seam.side_b.push_back(vb);
    }
    seams.push_back(std::move(seam));
  }
  return seams;
}

}  // namespace chs
