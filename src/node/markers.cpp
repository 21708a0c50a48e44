#include "cloth_hair_sim/node/markers.h"

#include <array>
#include <cmath>
#include <utility>

#include <tf2_eigen/tf2_eigen.h>

namespace chs_node {
namespace {

geometry_msgs::Point point(const Eigen::Vector3d& v) {
  geometry_msgs::Point p;
  p.x = v.x();
  p.y = v.y();
  p.z = v.z();
  return p;
}

std_msgs::ColorRGBA palette(int i) {
  static const std::array<std::array<float, 3>, 6> rgb{{{0.85f, 0.25f, 0.2f},
                                                        {0.2f, 0.45f, 0.85f},
                                                        {0.95f, 0.7f, 0.15f},
                                                        {0.3f, 0.7f, 0.35f},
                                                        {0.6f, 0.35f, 0.75f},
                                                        {0.9f, 0.5f, 0.7f}}};
  const auto& c = rgb[static_cast<size_t>(i) % rgb.size()];
  std_msgs::ColorRGBA out;
  out.r = c[0];
  out.g = c[1];
  out.b = c[2];
  out.a = 1.0f;
  return out;
}

// rviz has no capsule primitive: a triangulated one, centred on its frame, axis z.
void addCapsuleTriangles(double radius, double length, visualization_msgs::Marker& m) {
  const int half_rings = 4, segments = 16;
  std::vector<std::pair<double, double>> rings;  // (ring radius, z), bottom pole to top pole
  for (int i = 0; i <= 2 * half_rings + 1; ++i) {
    const bool top = i > half_rings;
    const double phi = M_PI / 2 * ((top ? i - 1 : i) - half_rings) / half_rings;
    rings.emplace_back(radius * std::cos(phi),
                       radius * std::sin(phi) + (top ? 0.5 : -0.5) * length);
  }
  auto at = [&](size_t ring, int seg) {
    const double a = 2.0 * M_PI * seg / segments;
    return point(Eigen::Vector3d(rings[ring].first * std::cos(a), rings[ring].first * std::sin(a),
                                 rings[ring].second));
  };
  for (size_t i = 0; i + 1 < rings.size(); ++i)
    for (int j = 0; j < segments; ++j)
      for (const auto& p :
           {at(i, j), at(i, j + 1), at(i + 1, j + 1), at(i, j), at(i + 1, j + 1), at(i + 1, j)})
        m.points.push_back(p);
}

// The collider's own (scaled) triangles in its shape frame. A closed mesh need not be
// consistently wound, and rviz culls back faces, so both windings are drawn.
void addMeshTriangles(const chs::TriangleMesh& mesh, visualization_msgs::Marker& m) {
  m.points.reserve(6 * mesh.triangles.size());
  for (const auto& t : mesh.triangles) {
    for (int k : {0, 1, 2}) m.points.push_back(point(mesh.vertices[t[k]]));
    for (int k : {0, 2, 1}) m.points.push_back(point(mesh.vertices[t[k]]));
  }
}

}  // namespace

std::vector<visualization_msgs::Marker> garmentMarkers(const chs::DisplaySurface& surface, int id,
                                                       int colour, double back_offset) {
  visualization_msgs::Marker front;
  front.ns = "garments";
  front.id = id;
  front.type = visualization_msgs::Marker::TRIANGLE_LIST;
  front.action = visualization_msgs::Marker::ADD;
  front.pose.orientation.w = 1.0;
  front.scale.x = front.scale.y = front.scale.z = 1.0;
  front.color = palette(colour);
  visualization_msgs::Marker back = front;
  back.ns = "garments_back";
  back.color.r *= 0.6f;
  back.color.g *= 0.6f;
  back.color.b *= 0.6f;
  // Area-weighted vertex normals (the cross products carry twice the triangle areas).
  const auto& x = surface.vertices;
  std::vector<Eigen::Vector3d> normal(x.size(), Eigen::Vector3d::Zero());
  for (const auto& t : surface.triangles) {
    const Eigen::Vector3d n = (x[t[1]] - x[t[0]]).cross(x[t[2]] - x[t[0]]);
    for (int k : t) normal[k] += n;
  }
  for (auto& n : normal)
    if (n.norm() > 0.0) n.normalize();
  front.points.reserve(surface.triangles.size() * 3);
  back.points.reserve(surface.triangles.size() * 3);
  for (const auto& t : surface.triangles) {
    for (int k : {0, 1, 2}) front.points.push_back(point(x[t[k]]));
    for (int k : {0, 2, 1}) back.points.push_back(point(x[t[k]] - back_offset * normal[t[k]]));
  }
  return {front, back};
}

visualization_msgs::Marker colliderMarker(const TrackedCollider& c, int id) {
  visualization_msgs::Marker m;
  m.ns = "colliders";
  m.id = id;
  m.action = visualization_msgs::Marker::ADD;
  m.color.r = m.color.g = m.color.b = 0.6f;
  m.color.a = c.stale ? 0.25f : 0.6f;  // a collider holding its last pose fades
  Eigen::Isometry3d pose = c.shapePose();
  const auto& d = c.shape.dimensions;
  switch (c.shape.type) {
    case chs::ColliderShape::Type::kPlane:
      m.type = visualization_msgs::Marker::CUBE;
      m.scale.x = m.scale.y = 4.0;
      m.scale.z = 0.002;
      pose.translate(Eigen::Vector3d(0.0, 0.0, -0.001));  // top face on the plane
      break;
    case chs::ColliderShape::Type::kSphere:
      m.type = visualization_msgs::Marker::SPHERE;
      m.scale.x = m.scale.y = m.scale.z = 2.0 * d[0];
      break;
    case chs::ColliderShape::Type::kBox:
      m.type = visualization_msgs::Marker::CUBE;
      m.scale.x = d[0];
      m.scale.y = d[1];
      m.scale.z = d[2];
      break;
    case chs::ColliderShape::Type::kCylinder:
      m.type = visualization_msgs::Marker::CYLINDER;
      m.scale.x = m.scale.y = 2.0 * d[0];
      m.scale.z = d[1];
      break;
    case chs::ColliderShape::Type::kCapsule:
      m.type = visualization_msgs::Marker::TRIANGLE_LIST;
      m.scale.x = m.scale.y = m.scale.z = 1.0;
      addCapsuleTriangles(d[0], d[1], m);
      break;
    case chs::ColliderShape::Type::kMesh:
      m.type = visualization_msgs::Marker::TRIANGLE_LIST;
      m.scale.x = m.scale.y = m.scale.z = 1.0;
      addMeshTriangles(c.shape.meshField()->mesh(), m);
      break;
  }
  m.pose = tf2::toMsg(pose);
  return m;
}

shape_msgs::Mesh meshMessage(const chs::QuadMesh& mesh, const std::vector<Eigen::Vector3d>& x) {
  shape_msgs::Mesh out;
  for (const auto& v : x) out.vertices.push_back(point(v));
  for (const auto& q : mesh.quads) {
    for (const auto& t :
         {std::array<int, 3>{q[0], q[1], q[2]}, std::array<int, 3>{q[0], q[2], q[3]}}) {
      shape_msgs::MeshTriangle tri;
      for (int k = 0; k < 3; ++k) tri.vertex_indices[k] = static_cast<uint32_t>(t[k]);
      out.triangles.push_back(tri);
    }
  }
  return out;
}

}  // namespace chs_node
