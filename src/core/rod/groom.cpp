#include "cloth_hair_sim/core/rod/groom.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include <Eigen/Geometry>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/rod/parallel_transport.h"
#include "cloth_hair_sim/core/rod/strand_shapes.h"

namespace chs::rod {
namespace {

using Vec3 = Eigen::Vector3d;

// Consecutive vertices closer than this are duplicates [m].
constexpr double kDuplicate = 1e-9;

bool positiveFinite(double x) {
  return x > 0.0 && std::isfinite(x);
}

// The checks groomScalp and groomMesh share: the patch's cone and the strands.
void checkGroom(const GroomSettings& s) {
  const ScalpPatch& p = s.scalp;
  if (!p.centre.allFinite()) throw InputError("groom: scalp centre must be finite");
  if (!p.direction.allFinite() || p.direction.norm() < 1e-12)
    throw InputError("groom: patch direction must be finite and non-zero");
  if (!(p.cone_angle > 0.0 && p.cone_angle <= M_PI))
    throw InputError("groom: patch cone angle must be in (0, pi] rad");
  if (s.strands < 1 || s.strands > kMaxGroomStrands)
    throw InputError("groom: strand count must be 1.." + std::to_string(kMaxGroomStrands));
  if (s.segments < 1) throw InputError("groom: needs at least one segment per strand");
  if (static_cast<long>(s.strands) * (s.segments + 1) > kMaxGroomVertices)
    throw InputError("groom: " + std::to_string(s.strands) + " strands of " +
                     std::to_string(s.segments) + " segments exceed the limit of " +
                     std::to_string(kMaxGroomVertices) + " vertices");
  if (!positiveFinite(s.length)) throw InputError("groom: length must be positive and finite");
  if (!(s.curl_radius >= 0.0) || !std::isfinite(s.curl_radius) || !std::isfinite(s.curl_pitch))
    throw InputError("groom: curl radius must be >= 0 and the pitch finite");
  if (s.curl_radius > 0.0 && s.curl_pitch == 0.0)
    throw InputError("groom: a curl needs a non-zero pitch (a flat ring overlaps itself)");
}

// A strand from its root along the surface normal: straight, or a curl about the normal turned
// by its own phase, so that the strands do not curl in step.
std::vector<Vec3> growStrand(const Vec3& root, const Vec3& normal, double phase,
                             const GroomSettings& s) {
  if (s.curl_radius <= 0.0) return straightStrand(root, normal, s.length, s.segments);
  std::vector<Vec3> x =
      helicalStrand(root, normal, s.curl_radius, s.curl_pitch, s.length, s.segments);
  const Eigen::AngleAxisd turn(phase, normal);
  for (auto& v : x) v = root + turn * (v - root);
  return x;
}

}  // namespace

void checkStrands(const Polylines& strands, long max_vertices) {
  if (strands.empty()) throw InputError("groom: no strands");
  if (strands.size() > static_cast<std::size_t>(kMaxGroomStrands))
    throw InputError("groom: " + std::to_string(strands.size()) + " strands, more than the limit " +
                     std::to_string(kMaxGroomStrands));
  long vertices = 0;
  for (std::size_t s = 0; s < strands.size(); ++s) {
    const auto& x = strands[s];
    const std::string who = "groom: strand " + std::to_string(s);
    vertices += static_cast<long>(x.size());
    if (vertices > max_vertices)
      throw InputError("groom: more than the limit of " + std::to_string(max_vertices) +
                       " vertices (at strand " + std::to_string(s) + ")");
    if (x.size() < 2) throw InputError(who + " has fewer than two vertices");
    double length = 0.0;
    for (std::size_t i = 0; i < x.size(); ++i) {
      if (!x[i].allFinite())
        throw InputError(who + ", vertex " + std::to_string(i) + " is not finite");
      if (i > 0) length += (x[i] - x[i - 1]).norm();
    }
    if (!(length > kDuplicate)) throw InputError(who + " has zero length");
    for (std::size_t i = 1; i < x.size(); ++i)
      if ((x[i] - x[i - 1]).norm() < kDuplicate)
        throw InputError(who + ": vertices " + std::to_string(i - 1) + " and " + std::to_string(i) +
                         " are duplicates (a zero-length edge)");
  }
}

std::vector<Vec3> resampleStrand(const std::vector<Vec3>& strand, int segments) {
  if (segments < 1) throw InputError("resample strand: needs at least one segment");
  checkStrands({strand});
  std::vector<double> arc(strand.size(), 0.0);
  for (std::size_t i = 1; i < strand.size(); ++i)
    arc[i] = arc[i - 1] + (strand[i] - strand[i - 1]).norm();
  std::vector<Vec3> out{strand.front()};
  std::size_t e = 1;  // the edge (e - 1, e) holding the next target
  for (int k = 1; k < segments; ++k) {
    const double target = arc.back() * k / segments;
    while (arc[e] < target) ++e;
    const double t = (target - arc[e - 1]) / (arc[e] - arc[e - 1]);
    out.push_back(strand[e - 1] + t * (strand[e] - strand[e - 1]));
  }
  out.push_back(strand.back());
  return out;
}

Polylines groomScalp(const GroomSettings& s) {
  const ScalpPatch& p = s.scalp;
  if (!positiveFinite(p.radii.minCoeff()) || !p.radii.allFinite())
    throw InputError("groom: scalp radii must be positive and finite");
  checkGroom(s);

  const Vec3 d = p.direction.normalized(), e1 = anyNormal(d), e2 = d.cross(e1);
  std::mt19937 rng(s.seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double cos_max = std::cos(p.cone_angle);
  Polylines strands;
  strands.reserve(s.strands);
  for (int k = 0; k < s.strands; ++k) {
    // Uniform in solid angle: cos(theta) uniform on [cos(cone), 1].
    const double c = 1.0 - unit(rng) * (1.0 - cos_max), sn = std::sqrt(std::max(0.0, 1 - c * c));
    const double phi = 2.0 * M_PI * unit(rng), phase = 2.0 * M_PI * unit(rng);
    const Vec3 u = c * d + sn * (std::cos(phi) * e1 + std::sin(phi) * e2);
    const Vec3 root = p.centre + p.radii.cwiseProduct(u);
    const Vec3 normal = u.cwiseQuotient(p.radii).normalized();  // gradient of the ellipsoid
    strands.push_back(growStrand(root, normal, phase, s));
  }
  return strands;
}

Polylines groomMesh(const TriangleMesh& mesh, const GroomSettings& s) {
  checkGroom(s);
  if (mesh.numTriangles() == 0) throw InputError("groom: the scalp mesh has no triangles");
  for (int v = 0; v < mesh.numVertices(); ++v)
    if (!mesh.vertices[v].allFinite())
      throw InputError("groom: scalp mesh vertex " + std::to_string(v) + " is not finite");
  for (int t = 0; t < mesh.numTriangles(); ++t)
    for (int c : mesh.triangles[t])
      if (c < 0 || c >= mesh.numVertices())
        throw InputError("groom: scalp mesh triangle " + std::to_string(t) +
                         " has a corner out of range");
  const ScalpPatch& p = s.scalp;
  const Vec3 d = p.direction.normalized();
  const double cos_max = std::cos(p.cone_angle);
  // Area-weighted vertex normals (the cross products are twice the areas), and the triangles of
  // the region with their cumulative area.
  std::vector<Vec3> vertex_normal(mesh.numVertices(), Vec3::Zero());
  std::vector<int> region;
  std::vector<double> cumulative;
  double area = 0.0;
  for (int t = 0; t < mesh.numTriangles(); ++t) {
    const auto& [a, b, c] = mesh.triangles[t];
    const Vec3 n = (mesh.vertices[b] - mesh.vertices[a]).cross(mesh.vertices[c] - mesh.vertices[a]);
    for (int k : mesh.triangles[t]) vertex_normal[k] += n;
    const Vec3 towards = (mesh.vertices[a] + mesh.vertices[b] + mesh.vertices[c]) / 3.0 - p.centre;
    if (n.norm() > 0.0 && towards.norm() > 0.0 && towards.normalized().dot(d) >= cos_max) {
      region.push_back(t);
      area += 0.5 * n.norm();
      cumulative.push_back(area);
    }
  }
  if (region.empty())
    throw InputError("groom: no triangle of the scalp mesh has its centroid within the patch's " +
                     std::to_string(p.cone_angle) + " rad of its direction seen from its centre");
  std::mt19937 rng(s.seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Polylines strands;
  strands.reserve(s.strands);
  for (int k = 0; k < s.strands; ++k) {
    const double pick = unit(rng) * area;
    const std::size_t i = std::min<std::size_t>(
        std::lower_bound(cumulative.begin(), cumulative.end(), pick) - cumulative.begin(),
        region.size() - 1);
    const auto& [a, b, c] = mesh.triangles[region[i]];
    // Uniform in the triangle's area.
    const double r1 = std::sqrt(unit(rng)), r2 = unit(rng), phase = 2.0 * M_PI * unit(rng);
    const double wa = 1.0 - r1, wb = r1 * (1.0 - r2), wc = r1 * r2;
    const Vec3 root = wa * mesh.vertices[a] + wb * mesh.vertices[b] + wc * mesh.vertices[c];
    Vec3 normal = wa * vertex_normal[a] + wb * vertex_normal[b] + wc * vertex_normal[c];
    if (!(normal.norm() > 0.0))  // opposite faces cancelled (a sheet folded on itself)
      normal = (mesh.vertices[b] - mesh.vertices[a]).cross(mesh.vertices[c] - mesh.vertices[a]);
    normal.normalize();
    if (normal.dot(root - p.centre) < 0.0) normal = -normal;
    strands.push_back(growStrand(root, normal, phase, s));
  }
  return strands;
}

}  // namespace chs::rod
