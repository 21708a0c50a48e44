#include "cloth_hair_sim/node/garment_mesh.h"

#include <tf2_eigen/tf2_eigen.h>

namespace chs_node {

cloth_hair_sim::GarmentMesh garmentMeshMessage(const std::string& name,
                                               const chs::ClothDynamics& dynamics,
                                               const chs::DisplaySurface& surface) {
  cloth_hair_sim::GarmentMesh msg;
  msg.name = name;
  msg.vertices.reserve(surface.vertices.size());
  for (const auto& v : surface.vertices) msg.vertices.push_back(tf2::toMsg(v));
  msg.triangles.resize(surface.triangles.size());
  for (std::size_t t = 0; t < surface.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k)
      msg.triangles[t].vertex_indices[k] = static_cast<std::uint32_t>(surface.triangles[t][k]);
  const auto& x = dynamics.positions();
  const auto& v = dynamics.velocities();
  msg.control_points.reserve(x.size());
  msg.velocities.resize(v.size());
  for (const auto& p : x) msg.control_points.push_back(tf2::toMsg(p));
  for (std::size_t i = 0; i < v.size(); ++i) tf2::toMsg(v[i], msg.velocities[i]);
  return msg;
}

}  // namespace chs_node
