#pragma once
#include <vector>

#include <Eigen/Core>

#include "cloth_hair_sim/core/mesh/quad_mesh.h"

namespace chs {

// Clamped edges of a Catmull-Clark shell: the limit surface's position and tangent plane held
// along them (a cantilever's root, a gripper's jaws), its curvature free.
//
// Why ghosts: the open boundary (EDGE_AND_CORNER) continues the control net by the phantom
// point 2 B - N, so the limit surface has zero cross-boundary curvature at a hem. Pinning the
// first two control rows then holds position and tangent but also forbids the curvature a
// clamped root carries, and the error is first order in the control spacing (a cantilever
// 17 % too stiff at 8 quads). As in Cirak, Ortiz and Schroeder's subdivision shells, the mesh is
// extended instead by one row of ghost faces across each clamped edge, and each clamped
// (boundary) point B and its ghost G are slaved to B's interior neighbour N so that, with c the
// clamp point and t the unit clamp direction (into the shell):
//   limit point     (G + 4 B + N) / 6 = c
//   cross tangent   (N - G) / 2 parallel to t
//   cross curvature G - 2 B + N free.
// That is G = c + R (N - c) with R = I - 2 t t^T the reflection through the plane normal to t
// at c, and B = c - (I - t t^T)(N - c) / 2. The reference state keeps c = B and t along N - B,
// so G = 2 B - N is Catmull-Clark's own phantom point: the clamped mesh's reference surface is
// the free mesh's. Along a straight clamp (one t) the whole clamp line holds the tangent plane.
class ClampedEdges {
 public:
  struct Clamp {
    int boundary = -1;                 // B, a clamped vertex of the mesh
    int interior = -1;                 // N, its neighbour across the first face row
    int ghost = -1;                    // G, a ghost vertex appended after the mesh's vertices
    Eigen::Vector3d point, direction;  // c and t
  };

  // No clamped vertices: the extended mesh is `mesh`. A clamp runs along whole boundary edges,
  // corner to corner (a straight clamp holds its tangent plane exactly). Throws InputError
  // naming the vertex when a clamped vertex is not on the boundary, has no clamped neighbour
  // along the boundary, ends the clamp partway along an edge, has no unique interior neighbour N
  // (the edge into the shell; at a corner, the unclamped boundary edge: two clamped edges
  // meeting at a corner, or an irregular boundary vertex such as a triangle mesh's
  // Catmull-Clark step leaves), or has a clamped N; and when the mesh with its ghost faces
  // fails checkMesh.
  ClampedEdges(const QuadMesh& mesh, const std::vector<int>& clamped);

  // The mesh with one ghost vertex per clamp and one ghost face per clamped boundary edge
  // appended after its own vertices and faces.
  const QuadMesh& extendedMesh() const { return extended_; }
  int numMeshVertices() const { return mesh_vertices_; }
  int numMeshFaces() const { return mesh_faces_; }
  const std::vector<Clamp>& clamps() const { return clamps_; }
  bool empty() const { return clamps_.empty(); }
  // Whether a vertex of the extended mesh is slaved (a clamped vertex or a ghost).
  bool isSlaved(int vertex) const { return slaved_[vertex] != 0; }

  // x_B and x_G from x_N (positions of the extended mesh).
  void placePositions(std::vector<Eigen::Vector3d>& x) const;
  // v_B = -(I - t t^T) v_N / 2, v_G = R v_N (the clamp does not move).
  void placeVelocities(std::vector<Eigen::Vector3d>& v) const;
  // The generalised force on N of forces f_B, f_G on one clamp's B and G: J_B^T f_B + J_G^T f_G
  // with J_B = -(I - t t^T)/2 and J_G = R, the chain rule through the slaving.
  Eigen::Vector3d foldedForce(const Clamp& clamp, const Eigen::Vector3d& f_boundary,
                              const Eigen::Vector3d& f_ghost) const;
  // The mass N carries for B and G: the slaved kinetic energy gives J^T M J = m_G I +
  // m_B (I - t t^T) / 4, which an isotropic (grid) mass can only lump as m_G + m_B / 4 (the
  // inertia along t then exceeds the exact one by m_B / 4).
  static double carriedMass(double m_boundary, double m_ghost) {
    return m_ghost + 0.25 * m_boundary;
  }
  // The force the clamp exerts at one clamped point, from the residuals r = m a - f - m g of B
  // and G (what would be needed to move them as they move): the constraint force on N is
  // -(J_B^T r_B + J_G^T r_G), so the clamp's net force is r_B + r_G - J_B^T r_B - J_G^T r_G.
  Eigen::Vector3d reaction(const Clamp& clamp, const Eigen::Vector3d& r_boundary,
                           const Eigen::Vector3d& r_ghost) const;

 private:
  QuadMesh extended_;
  int mesh_vertices_ = 0, mesh_faces_ = 0;
  std::vector<Clamp> clamps_;
  std::vector<char> slaved_;
};

}  // namespace chs
