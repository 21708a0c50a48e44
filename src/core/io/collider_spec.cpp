#include "cloth_hair_sim/core/io/collider_spec.h"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "cloth_hair_sim/core/contact/capsule_surface.h"
#include "cloth_hair_sim/core/contact/posed_surface.h"

namespace chs {

std::shared_ptr<const RigidSurface> ColliderSpec::makeSurface() const {
  switch (type) {
    case Type::kPlane:
      return std::make_shared<PlaneSurface>(point, normal);
    case Type::kBox:
      return std::make_shared<BoxSurface>(lo, hi, edge_radius);
    case Type::kCylinder:
      return std::make_shared<CylinderSurface>(axis_xy, radius, z_bottom, z_top, edge_radius);
    case Type::kSphere:
      return std::make_shared<SphereSurface>(point, radius);
    case Type::kCapsule:
      return std::make_shared<CapsuleSurface>(end_a, end_b, radius);
    case Type::kMesh:
      return std::make_shared<PosedSurface>(mesh_field, pose);
  }
  return nullptr;
}

QuadPatches sketchCollider(const ColliderSpec& s, double z_floor, double extent) {
  using V = Eigen::Vector3d;
  QuadPatches out;
  switch (s.type) {
    case ColliderSpec::Type::kPlane: {
      const V n = s.normal.normalized();
      const V t1 = n.unitOrthogonal() * extent, t2 = n.cross(t1);
      out.push_back({s.point - t1 - t2, s.point + t1 - t2, s.point + t1 + t2, s.point - t1 + t2});
      break;
    }
    case ColliderSpec::Type::kBox: {
      const double zb = std::max(s.lo.z(), std::min(z_floor, s.hi.z()));
      const V a = s.lo, b = s.hi;
      const V c[8] = {{a.x(), a.y(), zb},    {b.x(), a.y(), zb},    {b.x(), b.y(), zb},
                      {a.x(), b.y(), zb},    {a.x(), a.y(), b.z()}, {b.x(), a.y(), b.z()},
                      {b.x(), b.y(), b.z()}, {a.x(), b.y(), b.z()}};
      out.push_back({c[4], c[5], c[6], c[7]});
      for (int k = 0; k < 4; ++k)
        out.push_back({c[k], c[(k + 1) % 4], c[4 + (k + 1) % 4], c[4 + k]});
      break;
    }
    case ColliderSpec::Type::kCylinder: {
      const int n = 48;
      const double zb = std::max(s.z_bottom, std::min(z_floor, s.z_top));
      const V top(s.axis_xy.x(), s.axis_xy.y(), s.z_top);
      for (int k = 0; k < n; ++k) {
        const double t0 = 2 * M_PI * k / n, t1 = 2 * M_PI * (k + 1) / n;
        const V r0(s.radius * std::cos(t0), s.radius * std::sin(t0), 0.0);
        const V r1(s.radius * std::cos(t1), s.radius * std::sin(t1), 0.0);
        out.push_back({top, top + r0, top + r1, top});  // pie slice as a degenerate quad
        const V down(0, 0, zb - s.z_top);
        out.push_back({top + r0 + down, top + r1 + down, top + r1, top + r0});
      }
      break;
    }
    case ColliderSpec::Type::kSphere: {
      const int nt = 16, np = 32;
      auto at = [&](int i, int j) {
        const double th = M_PI * i / nt, ph = 2 * M_PI * j / np;
        return V(s.point + s.radius * V(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph),
                                        std::cos(th)));
      };
      for (int i = 0; i < nt; ++i)
        for (int j = 0; j < np; ++j) {
          std::array<V, 4> q{at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)};
          if (std::max({q[0].z(), q[1].z(), q[2].z(), q[3].z()}) >= z_floor) out.push_back(q);
        }
      break;
    }
    case ColliderSpec::Type::kCapsule: {
      // Rings swept along the axis: each cap a quarter circle of profile, the side one band.
      const V axis = s.end_b - s.end_a;
      const double length = axis.norm();
      const V e = length > 0.0 ? V(axis / length) : V::UnitZ();
      const V u = e.unitOrthogonal(), w = e.cross(u);
      const int nc = 8, np = 32;
      std::vector<std::pair<double, double>> profile;  // (distance along e from a, ring radius)
      for (int i = 0; i <= nc; ++i) {
        const double t = -M_PI / 2 + M_PI / 2 * i / nc;
        profile.emplace_back(s.radius * std::sin(t), s.radius * std::cos(t));
      }
      for (int i = 0; i <= nc; ++i) {
        const double t = M_PI / 2 * i / nc;
        profile.emplace_back(length + s.radius * std::sin(t), s.radius * std::cos(t));
      }
      auto at = [&](std::size_t i, int j) {
        const double ph = 2 * M_PI * j / np;
        return V(s.end_a + profile[i].first * e +
                 profile[i].second * (std::cos(ph) * u + std::sin(ph) * w));
      };
      for (std::size_t i = 0; i + 1 < profile.size(); ++i)
        for (int j = 0; j < np; ++j) {
          std::array<V, 4> q{at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)};
          if (std::max({q[0].z(), q[1].z(), q[2].z(), q[3].z()}) >= z_floor) out.push_back(q);
        }
      break;
    }
    case ColliderSpec::Type::kMesh: {
      const TriangleMesh& mesh = s.mesh_field->mesh();
      for (const auto& t : mesh.triangles) {
        const V a = s.pose * mesh.vertices[t[0]], b = s.pose * mesh.vertices[t[1]],
                c = s.pose * mesh.vertices[t[2]];
        if (std::max({a.z(), b.z(), c.z()}) >= z_floor) out.push_back({a, b, c, c});
      }
      break;
    }
  }
  return out;
}

}  // namespace chs
