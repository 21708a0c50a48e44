#pragma once
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "cloth_hair_sim/core/mesh/triangle_mesh.h"

namespace chs::rod {

// A groom: the strands' polylines from root to tip, as a scalp builder or a strand file
// (io/strand_file.h) gives them, before they become rods.
using Polylines = std::vector<std::vector<Eigen::Vector3d>>;

// Limits of a groom: more is refused as a typo or a file not meant as guides (Yuksel's models
// hold 10 000-15 000 strands of up to 1.5 M points; as guides they are resampled).
constexpr int kMaxGroomStrands = 100000;
constexpr long kMaxGroomVertices = 1000000;  // HairSettings::max_vertices
// A strand file may hold more points (Yuksel's natural.hair has 1.5 M) when it is resampled to
// guides before it is simulated.
constexpr long kMaxStrandFileVertices = 4000000;

// A scalp patch on an ellipsoid centre + diag(radii) u, |u| = 1: the directions u within
// cone_angle of `direction`, uniform in solid angle.
struct ScalpPatch {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  Eigen::Vector3d radii = Eigen::Vector3d::Constant(0.1);  // [m] semi-axes along x, y, z
  Eigen::Vector3d direction = Eigen::Vector3d::UnitZ();
  double cone_angle = 1.0471975511965976;  // [rad] half angle, in (0, pi]; pi: the whole surface
};

struct GroomSettings {
  ScalpPatch scalp;
  int strands = 100;
  double length = 0.1;  // [m] each strand's arc length
  int segments = 10;
  // A curl (strand_shapes.h helicalStrand) about the surface normal; radius 0: straight.
  double curl_radius = 0.0;  // [m]
  double curl_pitch = 0.0;   // [m] rise per turn along the normal
  std::uint32_t seed = 1;    // the roots' (and curls' phases') random draw
};

// Strands rooted on the scalp patch, each leaving the surface along its normal (a curl's axis is
// the normal: its first segment leaves at the helix angle to it). Throws InputError for a bad
// setting (non-positive sizes, a cone angle outside (0, pi], a count beyond the limits).
Polylines groomScalp(const GroomSettings& settings);

// Strands rooted on a scalp region of a triangle mesh (a head model): the triangles whose
// centroids lie within the patch's cone_angle of its direction seen from its centre (its radii
// are not used), roots uniform in area over them, each strand leaving along the mesh's normal
// there (area-weighted vertex normals, interpolated), turned to point away from the centre so
// that the winding of the file does not matter. Throws InputError for a bad setting (as
// groomScalp), an empty or non-finite mesh, or a cone that holds no triangle of positive area.
Polylines groomMesh(const TriangleMesh& mesh, const GroomSettings& settings);

// The polyline resampled to `segments` segments of equal arc length (root and tip kept). Throws
// InputError for fewer than one segment or a strand checkStrands refuses.
std::vector<Eigen::Vector3d> resampleStrand(const std::vector<Eigen::Vector3d>& strand,
                                            int segments);

// Throws InputError naming the strand (and vertex) unless the groom has 1..kMaxGroomStrands
// strands of at least two vertices, max_vertices in all, every vertex finite, no strand of
// zero length and no two consecutive vertices closer than 1e-9 m (duplicates: a zero edge has no
// tangent).
void checkStrands(const Polylines& strands, long max_vertices = kMaxGroomVertices);

}  // namespace chs::rod
