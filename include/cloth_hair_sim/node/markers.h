#pragma once
#include <string>
#include <vector>

#include <shape_msgs/Mesh.h>
#include <visualization_msgs/Marker.h>
#include <Eigen/Core>

#include "cloth_hair_sim/core/dynamics/cloth_dynamics.h"
#include "cloth_hair_sim/core/mesh/quad_mesh.h"
#include "cloth_hair_sim/node/collider_tracker.h"

namespace chs_node {

// A garment's surface as TRIANGLE_LISTs: the front faces at the surface's vertices in namespace
// "garments", the back faces (reversed winding, a darker shade) in "garments_back". rviz lights
// a triangle list per vertex: two windings at the same place get opposite normals and render
// black, so the back layer sits back_offset behind the front along the vertex normals.
std::vector<visualization_msgs::Marker> garmentMarkers(const chs::DisplaySurface& surface, int id,
                                                       int colour, double back_offset);

// A collider as a primitive marker in namespace "colliders" (a plane as a thin 4 x 4 m slab, a
// capsule or mesh as a TRIANGLE_LIST).
visualization_msgs::Marker colliderMarker(const TrackedCollider& collider, int id);

// The mesh at positions, each quad split into two triangles with the quad's winding.
shape_msgs::Mesh meshMessage(const chs::QuadMesh& mesh,
                             const std::vector<Eigen::Vector3d>& positions);

}  // namespace chs_node
