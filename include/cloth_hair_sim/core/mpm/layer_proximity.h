#pragma once
#include <utility>
#include <vector>

#include "cloth_hair_sim/core/mesh/quad_mesh.h"
#include "cloth_hair_sim/core/mpm/sparse_grid.h"
#include "cloth_hair_sim/core/mpm/support_nodes.h"

namespace chs::mpm {

// Which particles of one surface share a grid node with another layer of the same surface: a
// fold, a rolled or stacked garment, the pinched neck of a twisted tube. Han's contact fibres
// (5.21)-(5.30) stand for the gap between layers: on a lone layer their compression is the
// kernel's smoothing of a curved sheet's motion, not contact, and it made the Lagrangian step's
// contact solve take 3-12 force evaluations per step where nothing touches.
//
// Two particles at one node lie on two layers when they are farther apart along the surface than
// in space, by more than curvature and stretch explain: path - diameter > 1.25 |x_p - x_q| (a
// sheet curved to a radius of two cells has arc / chord < 1.05 over the kernel's reach). The
// surface distance is measured once, in the rest state, along paths between face centroids
// through faces sharing a vertex, which overestimate it by at most a face diameter. So a fold
// tighter than the kernel reach, which the grid cannot resolve as two layers anyway, counts as
// one layer, and the pinched neck of a tube 24 faces round as two (12 faces along the surface,
// 1.5 cells in space); a tube narrower than the reach is near itself everywhere, since its
// opposite sides share nodes.
class LayerProximity {
 public:
  // mesh: the surface's faces in their rest state; particle_face: the face each particle lies
  // on; reach: the largest distance at which two particles share a grid node. Throws InputError
  // for a face index out of range or a reach that is not positive.
  LayerProximity(const QuadMesh& mesh, std::vector<int> particle_face, double reach);

  // near[p] = 1 where a grid node in particle p's support also lies in the support of a particle
  // on another layer (supports: as recorded by the transfer of these particles at x).
  void find(const SparseGrid& grid, const SupportNodes& supports,
            const std::vector<Eigen::Vector3d>& x, std::vector<char>& near) const;

  // Whether particles p and q at x lie on one layer.
  bool sameLayer(int p, int q, const std::vector<Eigen::Vector3d>& x) const;
  // The same for any two points on faces face_a and face_b, `distance` apart in space.
  bool facesOnOneLayer(int face_a, int face_b, double distance) const;

 private:
  static constexpr double kCurvatureSlack = 1.25;
  std::vector<int> particle_face_;
  double radius_slack_ = 0.0;  // the largest face diameter
  // Per face, the faces within the radius along the surface, sorted, with their path lengths.
  std::vector<std::vector<std::pair<int, double>>> neighbourhood_;
};

}  // namespace chs::mpm
