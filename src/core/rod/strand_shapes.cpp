#include "cloth_hair_sim/core/rod/strand_shapes.h"

#include <cmath>
#include <string>

#include <Eigen/Geometry>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/rod/parallel_transport.h"

namespace chs::rod {
namespace {

using Vec3 = Eigen::Vector3d;

void checkCommon(const char* who, const Vec3& root, const Vec3& direction, double length,
                 int segments) {
  if (!root.allFinite()) throw InputError(std::string(who) + ": root must be finite");
  if (!direction.allFinite() || direction.norm() < 1e-12)
    throw InputError(std::string(who) + ": direction must be finite and non-zero");
  if (!(length > 0.0 && std::isfinite(length)))
    throw InputError(std::string(who) + ": length must be positive and finite");
  if (segments < 1) throw InputError(std::string(who) + ": needs at least one segment");
}

}  // namespace

std::vector<Vec3> straightStrand(const Vec3& root, const Vec3& direction, double length,
                                 int segments) {
  checkCommon("straight strand", root, direction, length, segments);
  const Vec3 t = direction.normalized();
  std::vector<Vec3> x(segments + 1);
  for (int i = 0; i <= segments; ++i) x[i] = root + (length * i / segments) * t;
  return x;
}

std::vector<Vec3> helicalStrand(const Vec3& root, const Vec3& axis, double radius, double pitch,
                                double length, int segments) {
  checkCommon("helical strand", root, axis, length, segments);
  if (!(radius > 0.0 && std::isfinite(radius)) || !std::isfinite(pitch))
    throw InputError("helical strand: radius must be positive, pitch finite");
  const Vec3 a = axis.normalized(), u = anyNormal(a), w = a.cross(u);
  const double c = pitch / (2.0 * M_PI), speed = std::sqrt(radius * radius + c * c);
  std::vector<Vec3> x(segments + 1);
  for (int i = 0; i <= segments; ++i) {
    const double phi = length * i / segments / speed;  // arc length / (ds / dphi)
    x[i] = root + radius * (std::cos(phi) - 1.0) * u + radius * std::sin(phi) * w + c * phi * a;
  }
  return x;
}

std::vector<Vec3> wavyStrand(const Vec3& root, const Vec3& direction, const Vec3& normal,
                             double amplitude, double wavelength, double length, int segments) {
  checkCommon("wavy strand", root, direction, length, segments);
  if (!std::isfinite(amplitude) || !(wavelength > 0.0 && std::isfinite(wavelength)))
    throw InputError("wavy strand: amplitude must be finite, wavelength positive");
  const Vec3 t = direction.normalized();
  const Vec3 n = (normal - normal.dot(t) * t);
  if (!n.allFinite() || n.norm() < 1e-12)
    throw InputError("wavy strand: normal must not be parallel to the direction");
  const Vec3 nn = n.normalized();
  const double k = 2.0 * M_PI / wavelength;
  // The curve by its abscissa s; arc length grows by sqrt(1 + (A k cos ks)^2) ds. March in fine
  // steps and place a vertex each time the arc length passes the next multiple of L / n.
  const auto at = [&](double s) { return Vec3(root + s * t + amplitude * std::sin(k * s) * nn); };
  const double h = std::min(wavelength, length) / 2000.0;
  std::vector<Vec3> x{root};
  double s = 0.0, arc = 0.0;
  Vec3 prev = root;
  while (static_cast<int>(x.size()) <= segments) {
    const Vec3 next = at(s + h);
    const double ds = (next - prev).norm(), target = length * x.size() / segments;
    if (arc + ds >= target) {
      x.push_back(prev + (target - arc) / ds * (next - prev));
    } else {
      arc += ds;
      s += h;
      prev = next;
    }
  }
  return x;
}

}  // namespace chs::rod
