#pragma once
#include <string>
#include <vector>

#include <shape_msgs/Mesh.h>
#include <visualization_msgs/Marker.h>
#include <Eigen/Core>

#include "cloth_hair_sim/core/mesh/quad_mesh.h"
#include "cloth_hair_sim/node/collider_tracker.h"

namespace chs_node {

// A garment as a TRIANGLE_LIST in namespace "garments". rviz culls back faces, so every
// triangle is emitted in both windings to keep the cloth visible from both sides.
visualization_msgs::Marker garmentMarker(const chs::QuadMesh& mesh,
                                         const std::vector<Eigen::Vector3d>& positions, int id,
                                         int colour);

// A collider as a primitive marker in namespace "colliders" (a plane as a thin 4 x 4 m slab, a
// capsule or mesh as a TRIANGLE_LIST).
visualization_msgs::Marker colliderMarker(const TrackedCollider& collider, int id);

// The mesh at positions, each quad split into two triangles with the quad's winding.
shape_msgs::Mesh meshMessage(const chs::QuadMesh& mesh,
                             const std::vector<Eigen::Vector3d>& positions);

}  // namespace chs_node
