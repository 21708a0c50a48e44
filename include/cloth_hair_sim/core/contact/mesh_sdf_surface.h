#pragma once
#include <memory>
#include <string>

#include <Eigen/Geometry>

#include "cloth_hair_sim/core/contact/rigid_surface.h"
#include "cloth_hair_sim/core/mesh/triangle_mesh.h"

namespace chs {

// Grid spacing and narrow band of a mesh's signed distance field, in meters; 0 picks the
// default. With L the longest and l the shortest side of the mesh's bounding box:
//   voxel_size    = min(L / 128, l / 4), but at least L / 512: at most ~128 voxels along the
//                   body, at least 4 through its thinnest part so that its inside is resolved,
//                   and never more than 512 along it (a thin plate then needs an explicit size)
//   exterior_band = 3 voxels, the exact-distance zone outside the surface: it must exceed the
//                   cloth's contact margin plus a node's travel in one step
//   interior_band = the whole solid (as deep as it is), so that a node that went deep in still
//                   gets the true depth and the way out; bound it for large, finely gridded solids
struct MeshSdfResolution {
  double voxel_size = 0.0;
  double exterior_band = 0.0;
  double interior_band = 0.0;
};

// A rigid obstacle bounded by a closed triangle mesh, given by a narrow-band signed distance
// field (OpenVDB meshToSignedDistanceField) sampled on a voxel grid in the mesh's own frame.
// Place it in the world with PosedSurface: the grid is built once and shared by every pose.
//  - In the band the gap is the trilinear interpolant of the grid values (exact distances at
//    the voxel centres to float precision); the normal is the trilinear interpolant of the
//    central-difference gradients at the 8 surrounding voxels, normalised, and normal_gradient
//    is the exact derivative of that normal field (I - n n^T) dg/dx / |g|, symmetrised: the
//    finite-difference Hessian of the distance, continuous across voxel faces in its value.
//  - Beyond the band the grid holds only the clamped band value, read as the band's edge on its
//    side (+exterior band, -interior band) so the interpolant stays continuous. Outside the
//    mesh's bounding box the distance to the box is a lower bound of the true gap: where it
//    exceeds the grid's value it is reported instead, with the box's outward normal and a zero
//    normal gradient. So far away the gap is positive and grows with the distance; between the
//    band and the box (a concavity) it is the exterior band with the normal away from the box
//    centre, and no contact acts at such a gap. With a bounded interior band, a point deeper
//    inside gets gap = -interior band and the normal away from the box centre.
class MeshSdfSurface : public RigidSurface {
 public:
  // Throws InputError for a mesh that does not bound a solid (checkClosedSurface) or a
  // non-finite or negative resolution.
  explicit MeshSdfSurface(const TriangleMesh& mesh, const MeshSdfResolution& resolution = {});
  // readTriangleMesh(path, scale, parts) then the constructor; errors name the file.
  static std::shared_ptr<const MeshSdfSurface> fromFile(
      const std::string& path, const Eigen::Vector3d& scale = Eigen::Vector3d::Ones(),
      const MeshSdfResolution& resolution = {}, const std::vector<std::string>& parts = {});
  ~MeshSdfSurface() override;

  SurfaceProjection project(const Eigen::Vector3d& x) const override;
  std::string describe() const override;

  double voxelSize() const { return voxel_; }
  double exteriorBand() const { return exterior_; }
  double interiorBand() const { return interior_; }
  const Eigen::AlignedBox3d& bounds() const { return bounds_; }
  const TriangleMesh& mesh() const { return mesh_; }  // for drawing
  long activeVoxels() const;
  // Fields built by this process: lets tests check that moving a collider reuses its field.
  static long buildCount();

 private:
  struct Grid;  // the OpenVDB grid, kept out of this header
  // The distance to the bounding box is a lower bound of the gap outside the box: it replaces a
  // smaller (clamped or interpolated) gap, with the box's normal and a zero normal gradient.
  SurfaceProjection boundedByBox(const Eigen::Vector3d& x, SurfaceProjection p) const;
  Eigen::Vector3d awayFromCentre(const Eigen::Vector3d& x) const;

  TriangleMesh mesh_;
  Eigen::AlignedBox3d bounds_;
  double voxel_ = 0.0, exterior_ = 0.0, interior_ = 0.0;
  std::unique_ptr<const Grid> grid_;
};

}  // namespace chs
