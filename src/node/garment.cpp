#include "cloth_hair_sim/node/garment.h"

#include <cmath>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/io/material_presets.h"
#include "cloth_hair_sim/core/io/mesh_reader.h"
#include "cloth_hair_sim/core/mesh/grid_generators.h"
#include "cloth_hair_sim/core/mesh/mesh_check.h"

namespace chs_node {
namespace {

using chs::InputError;

chs::QuadMesh garmentMesh(const cloth_hair_sim::LoadGarment::Request& req) {
  const double scale = req.scale == 0.0 ? 1.0 : req.scale;
  if (!(scale > 0.0) || !std::isfinite(scale))
    throw InputError("scale must be positive and finite");
  if (!req.mesh_file.empty()) {
    if (!req.rectangle_size.empty() || !req.rectangle_cells.empty())
      throw InputError("give either mesh_file or rectangle_size, not both");
    return chs::readQuadMesh(req.mesh_file, scale);
  }
  if (req.rectangle_size.size() != 2)
    throw InputError("no mesh_file and no rectangle_size [lx, ly]: nothing to load");
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
                     const Eigen::Vector3d& gravity,
                     const chs::ParticleDynamicsSettings& settings) {
  if (req.name.empty()) throw InputError("a garment needs a name");
  Garment g;
  g.name = req.name;
  const Eigen::Isometry3d world_from_mesh = world_from_request_frame * poseFromMsg(req.pose);
  chs::DrapeProblem& p = g.reference;
  p.mesh = garmentMesh(req);
  for (auto& v : p.mesh.vertices) v = world_from_mesh * v;
  chs::checkMesh(p.mesh);
  p.material = garmentMaterial(req, g.material_name);
  p.gravity = gravity;
  for (int v : req.pinned) p.bc.pinned.push_back(v);
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
  p.validate();
  resetDynamics(g, settings);
  return g;
}

void resetDynamics(Garment& g, const chs::ParticleDynamicsSettings& settings) {
  g.dynamics = std::make_unique<chs::ParticleDynamics>(g.reference, settings);
  // stableTimeStep() bounds RK4's stability interval; keep a margin for contact stiffening.
  g.stable_dt = 0.5 * g.dynamics->stableTimeStep();
}

}  // namespace chs_node
