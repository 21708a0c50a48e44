#include "cloth_hair_sim/node/hair.h"

#include <algorithm>
#include <cmath>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/io/strand_file.h"
#include "cloth_hair_sim/core/io/triangle_mesh_reader.h"
#include "cloth_hair_sim/node/garment.h"
#include "cloth_hair_sim/node/grasp.h"

namespace chs_node {
namespace {

using chs::InputError;
using Vec3 = Eigen::Vector3d;

chs::rod::RodMaterial hairMaterial(const cloth_hair_sim::LoadHair::Request& req,
                                   std::string& name) {
  chs::rod::RodMaterial m;
  if (req.material == "human_hair") {
    m = chs::rod::humanHair();
    name = req.material;
  } else if (!req.material.empty()) {
    throw InputError("unknown material preset '" + req.material +
                     "' (known: human_hair; or leave it empty for explicit values)");
  } else {
    name = "explicit";
  }
  // With a preset, non-zero values override it; without one, they are the material.
  if (req.young != 0.0) m.youngs_modulus = req.young;
  if (req.shear != 0.0) m.shear_modulus = req.shear;
  if (req.radius != 0.0) {
    m.radius_1 = req.radius;
    m.radius_2 = 0.0;
  }
  if (req.density != 0.0) m.density = req.density;
  if (!req.material.empty() &&
      (req.young != 0.0 || req.shear != 0.0 || req.radius != 0.0 || req.density != 0.0))
    name += " (overridden)";
  chs::rod::checkRodMaterial(m, "hair material");
  return m;
}

// The guides in the root frame's coordinates.
chs::rod::Polylines hairStrands(const cloth_hair_sim::LoadHair::Request& req) {
  const Eigen::Isometry3d frame_from_groom = poseFromMsg(req.pose);
  if (req.segments < 0) throw InputError("segments must be >= 0");
  const double scale = req.scale == 0.0 ? 1.0 : req.scale;
  if (!(scale > 0.0) || !std::isfinite(scale))
    throw InputError("scale must be positive and finite");
  chs::rod::Polylines strands;
  if (!req.file.empty()) {
    strands = chs::readStrandFile(req.file);
    for (auto& s : strands) {
      if (req.segments > 0) s = chs::rod::resampleStrand(s, req.segments);
      for (auto& x : s) x = frame_from_groom * (scale * x);
    }
  } else {
    chs::rod::GroomSettings g;
    if (!req.scalp_mesh.empty()) {
      if (!req.scalp_radii.empty())
        throw InputError("scalp_radii go with an ellipsoid, not with scalp_mesh");
    } else if (req.scalp_radii.size() == 1) {
      g.scalp.radii = Vec3::Constant(req.scalp_radii[0]);
    } else if (req.scalp_radii.size() == 3) {
      g.scalp.radii = Vec3(req.scalp_radii[0], req.scalp_radii[1], req.scalp_radii[2]);
    } else {
      throw InputError(
          "no file: scalp_radii must be [r] (a sphere) or [a, b, c] (an ellipsoid), or "
          "scalp_mesh a head model");
    }
    const Vec3 d(req.patch_direction.x, req.patch_direction.y, req.patch_direction.z);
    if (d != Vec3::Zero()) g.scalp.direction = d;
    if (req.patch_angle != 0.0) g.scalp.cone_angle = req.patch_angle;
    g.strands = req.strands;
    g.length = req.length;
    if (req.segments > 0) g.segments = req.segments;
    g.curl_radius = req.curl_radius;
    g.curl_pitch = req.curl_pitch;
    if (req.seed != 0) g.seed = req.seed;
    if (req.scalp_mesh.empty()) {
      strands = chs::rod::groomScalp(g);
    } else {
      g.scalp.centre = Vec3(req.patch_centre.x, req.patch_centre.y, req.patch_centre.z);
      strands =
          chs::rod::groomMesh(chs::readTriangleMesh(req.scalp_mesh, Vec3::Constant(scale)), g);
    }
    for (auto& s : strands)
      for (auto& x : s) x = frame_from_groom * x;
  }
  chs::rod::checkStrands(strands);  // the simulation's limits, after resampling
  return strands;
}

}  // namespace

int Hair::numVertices() const {
  int n = 0;
  for (int s = 0; s < body->numStrands(); ++s) n += body->strand(s).numVertices();
  return n;
}

void HairGrasp::gripAt(chs::rod::HairDynamics& body, double alpha) const {
  body.setGripFrame(grip, interpolate(from, to, alpha) * attached_at.inverse());
}

void Hair::clampAt(double alpha) {
  const Eigen::Isometry3d motion = interpolate(from, to, alpha) * attached_at.inverse();
  for (int s = 0; s < body->numStrands(); ++s) body->setRootFrame(s, motion);
}

chs::rod::Polylines Hair::drawnStrands() const {
  chs::rod::Polylines out;
  std::vector<const std::vector<Vec3>*> guides;
  for (int s = 0; s < body->numStrands(); ++s) {
    out.push_back(body->strand(s).positions());
    guides.push_back(&body->strand(s).positions());
  }
  if (display.empty()) return out;  // guides of a file may differ in vertex count
  for (auto& d : chs::rod::displayStrands(display, guides)) out.push_back(std::move(d));
  return out;
}

void rebuildHairBody(Hair& hair, const Eigen::Isometry3d& world_from_frame,
                     const chs::rod::HairSettings& settings) {
  auto body = std::make_shared<chs::rod::HairDynamics>(settings);
  for (const auto& s : hair.rest) {
    std::vector<Vec3> x = s;
    for (auto& v : x) v = world_from_frame * v;
    body->addStrand(x, hair.material, !hair.loose);
  }
  hair.body = std::move(body);
  hair.attached_at = hair.from = hair.to = world_from_frame;
}

Hair buildHair(const cloth_hair_sim::LoadHair::Request& req,
               const Eigen::Isometry3d& world_from_frame, const chs::rod::HairSettings& settings,
               int display_default) {
  Hair h;
  h.request = req;
  h.name = req.name;
  h.frame_id = req.frame_id;
  h.loose = req.loose;
  h.material = hairMaterial(req, h.material_name);
  h.rest = hairStrands(req);
  const int display = req.display_strands == 0 ? display_default : std::max(0, req.display_strands);
  if (display > 0) {
    for (const auto& s : h.rest)
      if (s.size() != h.rest.front().size())
        throw InputError(
            "display strands need guides of one vertex count: give segments to resample the "
            "file's strands, or display_strands < 0 for none");
    std::vector<Vec3> roots;
    for (const auto& s : h.rest) roots.push_back(s.front());
    h.display = chs::rod::blendDisplayStrands(roots, display, req.seed == 0 ? 1 : req.seed);
  }
  rebuildHairBody(h, world_from_frame, settings);
  return h;
}

visualization_msgs::Marker hairMarker(const Hair& hair, int id, const std::vector<float>& rgba,
                                      double line_width) {
  visualization_msgs::Marker m;
  m.ns = "hair";
  m.id = id;
  m.type = visualization_msgs::Marker::LINE_LIST;
  m.action = visualization_msgs::Marker::ADD;
  m.pose.orientation.w = 1.0;
  m.scale.x = line_width;
  m.color.r = rgba[0];
  m.color.g = rgba[1];
  m.color.b = rgba[2];
  m.color.a = rgba[3];
  for (const auto& s : hair.drawnStrands())
    for (std::size_t i = 1; i < s.size(); ++i)
      for (const Vec3* x : {&s[i - 1], &s[i]}) {
        geometry_msgs::Point p;
        p.x = x->x();
        p.y = x->y();
        p.z = x->z();
        m.points.push_back(p);
      }
  return m;
}

}  // namespace chs_node
