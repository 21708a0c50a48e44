#pragma once
#include <array>
#include <vector>

#include <Eigen/Core>

namespace chs {

// A triangulated surface: the boundary of a rigid collider (robot link, mannequin, furniture).
// Unlike the cloth's QuadMesh it carries no material, only geometry.
struct TriangleMesh {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<std::array<int, 3>> triangles;

  int numVertices() const { return static_cast<int>(vertices.size()); }
  int numTriangles() const { return static_cast<int>(triangles.size()); }
};

// Rejects a mesh that cannot bound a solid, throwing InputError naming the first offending
// vertex, triangle or edge: empty mesh, non-finite coordinates, corner indices out of range,
// and holes. Closedness is checked as "every edge is shared by an even number of triangles" (the
// mod-2 boundary of the surface is empty): an edge used once borders a hole, while two solids
// touching along an edge (4 uses) still enclose a volume. Orientation is not required, since the
// sign of the distance field comes from a flood fill of the outside, not from face normals.
// Triangles with a repeated corner (zero area) are allowed and bound nothing.
void checkClosedSurface(const TriangleMesh& mesh);

}  // namespace chs
