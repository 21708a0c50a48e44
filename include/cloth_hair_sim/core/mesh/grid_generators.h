#pragma once
#include <Eigen/Core>

#include "cloth_hair_sim/core/mesh/quad_mesh.h"

namespace chs {

// Flat lx x ly rectangle of nx x ny quads in the plane z = centre.z(), normal +z.
// Vertex (i, j), i along x and j along y, has index j * (nx + 1) + i.
QuadMesh makeRectangleMesh(double lx, double ly, int nx, int ny,
                           const Eigen::Vector3d& centre = Eigen::Vector3d::Zero());

// Flat disc of the given radius in the plane z = centre.z(), normal +z, as an O-grid: a central
// square block and four blocks mapped onto the circle, so that no quad degenerates at the centre
// and elements are roughly uniform (longest / shortest edge 1.5-1.7 from 12 cells across up).
// cells_across (>= 3) is the number of quads along a diameter: k cells radially in each ring
// block and m = cells_across - 2k along each side of the square, k chosen for the most uniform
// edges; the rim has 4m vertices. Vertices are numbered block by block.
QuadMesh makeDiscMesh(double radius, int cells_across,
                      const Eigen::Vector3d& centre = Eigen::Vector3d::Zero());

}  // namespace chs
