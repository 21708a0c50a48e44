#pragma once
#include <vector>

#include <Eigen/Core>

#include "cloth_hair_sim/core/mesh/polygon_mesh.h"
#include "cloth_hair_sim/core/mesh/quad_mesh.h"

namespace chs {

// An all-quad control mesh with the same Catmull-Clark limit surface (Han section 5.4: "we may
// assume that all input meshes have quadrilateral faces by replacing the control mesh with its
// first subdivision if necessary").
//
// An all-quad mesh is returned unchanged (same vertices, same quads, same order). Otherwise the
// mesh is refined once by Catmull-Clark with the EDGE_AND_CORNER boundary rule of LimitSurface:
// every n-gon becomes n quads around its face point, so V' = V + E + F vertices and
// sum_f n_f quads. Orientation is inherited from the parent faces. Vertex order: the original
// vertices keep their indices 0..V-1 (moved by the vertex rule, so vertex selections carry
// over), then face f's point at V + f, then the edge points.
//
// Throws InputError for the same bad topology as LimitSurface (empty, out of range, repeated
// corners, faces with fewer than 3 corners, non-manifold or inconsistently oriented).
QuadMesh toQuadControlMesh(const PolygonMesh& mesh);

}  // namespace chs
