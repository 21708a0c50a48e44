#pragma once
#include <array>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "cloth_hair_sim/core/mesh/quad_mesh.h"
#include "cloth_hair_sim/core/subdiv/surface_stencil.h"

namespace chs {

// A point of the limit surface: parameters (u, v) in [0, 1]^2 of one control-mesh face.
struct SurfacePoint {
  int face;
  double u, v;
};

// Triangles over limit-surface samples, for display. A sample on a face edge or at a corner
// is stored once, so the triangle mesh is watertight wherever the control mesh is closed.
// Face f owns triangles [2 n^2 f, 2 n^2 (f + 1)) for n segments per edge, oriented like the quad.
struct LimitTessellation {
  std::vector<SurfacePoint> samples;
  std::vector<std::array<int, 3>> triangles;
};

// The Catmull-Clark limit surface of a quad control mesh, x(u, v) = sum_p x_p N_p^SD(u, v)
// (Han section 5.4), evaluated by OpenSubdiv's Bfr as stencils over the ORIGINAL control
// points, so that the shell's generalised forces land on x_p directly (Han (5.32)).
//
// Boundaries: EDGE_AND_CORNER. The limit boundary curve is the cubic B-spline of the boundary
// control points and valence-2 boundary corners are interpolated, which is what a garment
// panel's hem needs.
//
// Parameters of face f with corners c0 c1 c2 c3 (counter-clockwise seen from the normal side):
// (0,0) at c0, (1,0) at c1, (1,1) at c2, (0,1) at c3; u runs along c0 -> c1 and v along
// c0 -> c3. Hence x_u x x_v points to the side the quad's counter-clockwise normal points to.
//
// Faces whose corners are all regular (valence 4 inside, 2 or 3 on the boundary) are single
// uniform bicubic B-spline patches, evaluated exactly. A face touching an extraordinary vertex
// is refined adaptively towards it `extraordinary_level` times: everything outside the corner
// square [0, 2^-level]^2 at that vertex is exact B-spline, the square itself is a Gregory patch
// (the only irregular basis Bfr 3.5 offers) whose derivatives are approximate: against
// differences of its own positions, ~1e-2 off in Du, Dv and ~1e-1 in Duu, Duv, Dvv at any level.
// So the level must put the quadrature points outside the square. Default 4 (side 1/16): all
// points of the 2x2, 3x3 and 4x4 Gauss rules (nearest corner 0.211, 0.113, 0.069) are exact;
// levels 1-3 put 3x3 Gauss points in it and miss the bending integral of H^2 by 3e-4 to 1e-2
// (test_subdiv_limit_surface, ExtraordinaryLevelStudy); deeper levels only cost build time.
// A 5x5 rule (0.047) needs level 5.
//
// Thread safety: one Bfr::Surface per face is built in the constructor; stencil() only reads
// them (and shared, immutable patch trees), so any number of threads may call it at once.
class LimitSurface {
 public:
  static constexpr int kDefaultExtraordinaryLevel = 4;

  // Only the topology of `control` is used: the stencils hold for any control positions.
  // Throws InputError for an empty mesh, corner indices out of range or repeated, a vertex on
  // no quad, non-manifold edges or vertices, inconsistently oriented quads, or a level outside
  // [1, 10].
  explicit LimitSurface(const QuadMesh& control,
                        int extraordinary_level = kDefaultExtraordinaryLevel);
  ~LimitSurface();
  LimitSurface(LimitSurface&&) noexcept;
  LimitSurface& operator=(LimitSurface&&) noexcept;

  int numFaces() const;
  int numControlPoints() const;

  // Whether face f is a single B-spline patch (no extraordinary vertex among its corners).
  bool isRegular(int face) const;

  // Weights N_p and their first and second (u, v) derivatives at (u, v) of face `face`; each
  // control point appears once. Throws InputError for a face or (u, v) out of range.
  SurfaceStencil stencil(int face, double u, double v) const;
  SurfaceStencil stencil(const SurfacePoint& p) const { return stencil(p.face, p.u, p.v); }

  // Each face cut into segments_per_edge^2 cells of two triangles each (segments >= 1).
  LimitTessellation tessellate(int segments_per_edge) const {
    return tessellate(segments_per_edge, numFaces());
  }
  // The same over faces [0, num_faces) only (a mesh's own faces before ghost faces).
  LimitTessellation tessellate(int segments_per_edge, int num_faces) const;

 private:
  struct Faces;
  std::unique_ptr<const Faces> faces_;
};

// The limit surface's point at each control vertex of `mesh` (its parameter position, a corner of
// a face it belongs to; every such corner gives the same point): the surface's own grid over the
// control net, on which a stretch is measured as the cloth has it rather than its net (in folds
// the net stretches where the surface does not). `surface` is the limit surface of `mesh`, whose
// faces come first in it (ghost faces after them).
std::vector<SurfaceStencil> vertexStencils(const QuadMesh& mesh, const LimitSurface& surface);

// Positions x(u, v) = sum_k w_k x_{p_k} of each stencil over the given control positions.
std::vector<Eigen::Vector3d> evaluate(const std::vector<SurfaceStencil>& stencils,
                                      const std::vector<Eigen::Vector3d>& control_positions);

}  // namespace chs
