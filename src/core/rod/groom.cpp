#include "cloth_hair_sim/core/rod/groom.h"

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
  if (!p.centre.allFinite()) throw InputError("groom: scalp centre must be finite");
  if (!positiveFinite(p.radii.minCoeff()) || !p.radii.allFinite())
    throw InputError("groom: scalp radii must be positive and finite");
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
    if (s.curl_radius > 0.0) {
      std::vector<Vec3> x =
          helicalStrand(root, normal, s.curl_radius, s.curl_pitch, s.length, s.segments);
      // Each curl turned about the normal by its own phase, so that the strands do not curl in
      // step.
      const Eigen::AngleAxisd turn(phase, normal);
      for (auto& v : x) v = root + turn * (v - root);
      strands.push_back(std::move(x));
    } else {
      strands.push_back(straightStrand(root, normal, s.length, s.segments));
    }
  }
  return strands;
}

}  // namespace chs::rod
