#include "cloth_hair_sim/node/garment.h"

#include <array>
#include <cmath>
#include <map>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/common/names.h"
#include "cloth_hair_sim/core/io/material_presets.h"
#include "cloth_hair_sim/core/io/mesh_reader.h"
#include "cloth_hair_sim/core/mesh/grid_generators.h"
#include "cloth_hair_sim/core/mesh/mesh_check.h"

namespace chs_node {
namespace {

using chs::InputError;

// True if the quad a-b-c-d turns the same way at every corner (seen along its mean normal).
bool convexQuad(const std::array<Eigen::Vector3d, 4>& p) {
  const Eigen::Vector3d n = (p[2] - p[0]).cross(p[3] - p[1]);
  for (int k = 0; k < 4; ++k)
    if ((p[(k + 1) % 4] - p[k]).cross(p[(k + 2) % 4] - p[(k + 1) % 4]).dot(n) <= 0.0) return false;
  return true;
}

// The core is quad based: triangles are paired, each with a neighbour across a shared edge
// (wound the other way) into a convex quad. Greedy, preferring the longest shared edge: a quad
// split along a diagonal comes back whole, since the diagonal is its triangles' longest edge.
chs::QuadMesh quadsFromTriangles(const shape_msgs::Mesh& msg, double scale) {
  chs::QuadMesh mesh;
  for (const auto& v : msg.vertices)
    mesh.vertices.emplace_back(scale * v.x, scale * v.y, scale * v.z);
  const int n = static_cast<int>(msg.triangles.size());
  std::vector<std::array<int, 3>> tri(n);
  std::map<std::pair<int, int>, std::vector<int>> edge_triangles;
  for (int t = 0; t < n; ++t) {
    for (int k = 0; k < 3; ++k) {
      const auto v = msg.triangles[t].vertex_indices[k];
      if (v >= mesh.vertices.size())
        throw InputError("inline mesh: triangle " + std::to_string(t) + " has vertex " +
                         std::to_string(v) + " out of range (" +
                         std::to_string(mesh.vertices.size()) + " vertices)");
      tri[t][k] = static_cast<int>(v);
    }
    for (int k = 0; k < 3; ++k) {
      const int a = tri[t][k], b = tri[t][(k + 1) % 3];
      edge_triangles[{std::min(a, b), std::max(a, b)}].push_back(t);
    }
  }
  std::vector<char> paired(n, 0);
  for (int t = 0; t < n; ++t) {
    if (paired[t]) continue;
    double best_length = -1.0;
    std::array<int, 4> best_quad{};
    int best_partner = -1;
    for (int k = 0; k < 3; ++k) {
      const int p = tri[t][k], q = tri[t][(k + 1) % 3], r = tri[t][(k + 2) % 3];
      for (int u : edge_triangles[{std::min(p, q), std::max(p, q)}]) {
        if (u == t || paired[u]) continue;
        int j = 0;  // the neighbour must hold the edge as q -> p
        while (j < 3 && !(tri[u][j] == q && tri[u][(j + 1) % 3] == p)) ++j;
        if (j == 3) continue;
        const int s = tri[u][(j + 2) % 3];
        const std::array<int, 4> quad{r, p, s, q};
        const double length = (mesh.vertices[p] - mesh.vertices[q]).norm();
        if (length > best_length &&
            convexQuad({mesh.vertices[r], mesh.vertices[p], mesh.vertices[s], mesh.vertices[q]})) {
          best_length = length;
          best_quad = quad;
          best_partner = u;
        }
      }
    }
    if (best_partner < 0)
      throw InputError("inline mesh: triangle " + std::to_string(t) +
                       " has no neighbour to form a convex quad with; the simulator is quad "
                       "based: send each quad as two triangles sharing a diagonal");
    paired[t] = paired[best_partner] = 1;
    mesh.quads.push_back(best_quad);
  }
  // A vertex in no quad would get no mass; dropping it would renumber the pins.
  std::vector<char> used(mesh.vertices.size(), 0);
  for (const auto& q : mesh.quads)
    for (int v : q) used[v] = 1;
  for (std::size_t v = 0; v < used.size(); ++v)
    if (!used[v])
      throw InputError("inline mesh: vertex " + std::to_string(v) + " is in no triangle");
  return mesh;
}

chs::QuadMesh garmentMesh(const cloth_hair_sim::LoadGarment::Request& req) {
  const double scale = req.scale == 0.0 ? 1.0 : req.scale;
  if (!(scale > 0.0) || !std::isfinite(scale))
    throw InputError("scale must be positive and finite");
  const bool inline_mesh = !req.mesh.vertices.empty() || !req.mesh.triangles.empty();
  const int sources = !req.mesh_file.empty() + inline_mesh +
                      (!req.rectangle_size.empty() || !req.rectangle_cells.empty());
  if (sources > 1) throw InputError("give one of mesh_file, mesh and rectangle_size, not several");
  if (!req.mesh_file.empty()) return chs::readQuadMesh(req.mesh_file, scale);
  if (inline_mesh) {
    if (req.mesh.triangles.empty()) throw InputError("inline mesh: no triangles");
    return quadsFromTriangles(req.mesh, scale);
  }
  if (req.rectangle_size.size() != 2)
    throw InputError("no mesh_file, mesh or rectangle_size [lx, ly]: nothing to load");
  const double lx = scale * req.rectangle_size[0], ly = scale * req.rectangle_size[1];
  if (!(lx > 0.0) || !(ly > 0.0) || !std::isfinite(lx) || !std::isfinite(ly))
    throw InputError("rectangle_size must be positive and finite (m)");
  int nx = 0, ny = 0;
  if (req.rectangle_cells.empty()) {  // about 2 cm quads
    nx = std::max(2, static_cast<int>(std::lround(lx / 0.02)));
    ny = std::max(2, static_cast<int>(std::lround(ly / 0.02)));
  } else if (req.rectangle_cells.size() == 2) {
    nx = req.rectangle_cells[0];
    ny = req.rectangle_cells[1];
  } else {
    throw InputError("rectangle_cells must be [nx, ny]");
  }
  if (nx < 1 || ny < 1 || nx > 1000 || ny > 1000)
    throw InputError("rectangle_cells must be between 1 and 1000 in each direction");
  return chs::makeRectangleMesh(lx, ly, nx, ny);
}

chs::ShellMaterial garmentMaterial(const cloth_hair_sim::LoadGarment::Request& req,
                                   std::string& name) {
  chs::ShellMaterial m;
  if (!req.material.empty()) {
    const auto preset = chs::materialPreset(req.material);
    if (!preset) {
      std::string known;
      for (const auto& n : chs::materialPresetNames()) known += (known.empty() ? "" : ", ") + n;
      throw InputError("material preset '" + req.material + "' is unknown (presets: " + known +
                       ")");
    }
    m = *preset;
    name = req.material;
  } else {
    name = "custom";
  }
  bool modified = false;
  auto take = [&](double value, double& field) {
    if (value != 0.0) {  // NaN is not 0 either: taken, then refused by validate()
      field = value;
      modified = true;
    }
  };
  take(req.young, m.young);
  take(req.poisson, m.poisson);
  take(req.thickness, m.thickness);
  take(req.areal_density, m.areal_density);
  if (modified && !req.material.empty()) name += " (modified)";
  m.validate();  // its messages start with "material:"
  return m;
}

int axisOf(char c) {
  if (c == 'x') return 0;
  if (c == 'y') return 1;
  if (c == 'z') return 2;
  return -1;
}

}  // namespace

Eigen::Isometry3d poseFromMsg(const geometry_msgs::Pose& pose) {
  const Eigen::Vector3d p(pose.position.x, pose.position.y, pose.position.z);
  Eigen::Quaterniond q(pose.orientation.w, pose.orientation.x, pose.orientation.y,
                       pose.orientation.z);
  if (!p.allFinite() || !q.coeffs().allFinite()) throw InputError("pose has NaN or Inf values");
  if (q.coeffs().isZero()) q = Eigen::Quaterniond::Identity();
  if (std::abs(q.norm() - 1.0) > 1e-3)
    throw InputError("pose orientation is not a unit quaternion (norm " + std::to_string(q.norm()) +
                     ")");
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translate(p);
  t.rotate(q.normalized());
  return t;
}

Garment buildGarment(const cloth_hair_sim::LoadGarment::Request& req,
                     const Eigen::Isometry3d& world_from_request_frame,
                     const std::map<std::string, Eigen::Isometry3d>& world_from_frames,
                     const SimParams& params) {
  chs::checkName(req.name);
  Garment g;
  g.name = req.name;
  g.request = req;
  g.world_from_request_frame = world_from_request_frame;
  g.world_from_frames = world_from_frames;
  const Eigen::Isometry3d world_from_mesh = world_from_request_frame * poseFromMsg(req.pose);
  chs::DrapeProblem& p = g.reference;
  p.mesh = garmentMesh(req);
  for (auto& v : p.mesh.vertices) v = world_from_mesh * v;
  chs::checkMesh(p.mesh);
  p.material = garmentMaterial(req, g.material_name);
  p.gravity = params.gravity;
  for (int v : req.pinned) p.bc.pinned.push_back(v);
  for (int v : req.clamped) p.bc.clamped.push_back(v);
  for (const auto& f : req.fixed) {
    if (f.axes.empty())
      throw InputError("fixed vertex " + std::to_string(f.vertex) + ": no axes (use x, y, z)");
    for (char c : f.axes) {
      const int axis = axisOf(c);
      if (axis < 0)
        throw InputError("fixed vertex " + std::to_string(f.vertex) + ": axis '" +
                         std::string(1, c) + "' is not x, y or z");
      p.bc.fixed_components.push_back({f.vertex, axis});
    }
  }
  std::vector<char> attached(p.mesh.numVertices(), 0);
  for (const auto& group : req.attached) {
    const std::string who = "attached pins of frame '" + group.frame_id + "': ";
    const auto frame = world_from_frames.find(group.frame_id);
    if (group.frame_id.empty() || frame == world_from_frames.end())
      throw InputError(who + "no such frame (give a tf frame_id)");
    if (group.vertices.empty()) throw InputError(who + "no vertices");
    for (int v : group.vertices) {
      if (v < 0 || v >= p.mesh.numVertices())
        throw InputError(who + "vertex " + std::to_string(v) + " out of range (" +
                         std::to_string(p.mesh.numVertices()) + " vertices)");
      if (attached[v]++) throw InputError(who + "vertex " + std::to_string(v) + " attached twice");
      // A static drape holds them where they were at load.
      p.bc.pinned.push_back(v);
    }
    g.frame_pins.emplace_back(group.frame_id,
                              std::vector<int>(group.vertices.begin(), group.vertices.end()),
                              p.mesh.vertices, frame->second);
  }
  p.validate();
  resetDynamics(g, params);
  return g;
}

FreshDynamics freshDynamics(const chs::DrapeProblem& reference,
                            const std::optional<double>& self_friction, const SimParams& params) {
  FreshDynamics f;
  if (params.dynamics_backend == "mpm") {
    chs::HybridShellSettings s = params.mpm;
    if (self_friction) s.contact.friction = *self_friction;
    auto shell = std::make_shared<chs::HybridShellDynamics>(reference, s);
    f.dynamics = shell;
    f.body = shell;
  } else {
    f.dynamics = std::make_shared<chs::ParticleDynamics>(reference, params.particle);
  }
  return f;
}

void resetDynamics(Garment& g, const SimParams& params) {
  g.body.reset();
  FreshDynamics f = freshDynamics(g.reference, g.self_friction, params);
  g.dynamics = std::move(f.dynamics);
  g.body = std::move(f.body);
}

}  // namespace chs_node
