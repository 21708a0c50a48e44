#pragma once
#include <vector>

#include <Eigen/Core>

#include "cloth_hair_sim/core/contact/rigid_surface.h"
#include "cloth_hair_sim/core/mesh/quad_mesh.h"

namespace chs {

struct ColliderSpec;

// The support a circular (or square) drape hangs from: its vertical axis and top area A_d.
struct DrapeSupport {
  Eigen::Vector2d axis_xy = Eigen::Vector2d::Zero();
  double area = 0.0;  // A_d (m^2)
};

// Top face of a pedestal (pi r^2) or table (sx sy); the rounded rim is not counted, it is within
// one edge radius. Throws InputError for planes and spheres, which have no top face.
DrapeSupport supportOf(const ColliderSpec& collider);

struct DrapeMetricsSettings {
  // Shadow area: the projected quads (two triangles each) are rasterised onto a square grid of
  // raster_cells x raster_cells covering the shadow's bounding box, a cell counting when its
  // centre is covered. Only cells cut by the outline can be wrong, so |error| <= P h sqrt(2) for
  // outline length P and cell size h; errors along the outline mostly cancel and the measured
  // error is far smaller (see test_drape_metrics).
  int raster_cells = 2048;
  // Fold count: the outline radius r(theta) is binned into angular_bins bins (maximum per bin:
  // the shadow's outer envelope), smoothed twice with a circular moving average of
  // smoothing_deg, and local maxima whose prominence exceeds
  // max(min_prominence, relative_prominence * mean r) are folds.
  int angular_bins = 720;
  double smoothing_deg = 6.0;
  double min_prominence = 1e-3;       // m
  double relative_prominence = 0.02;  // of the mean outline radius
};

struct DrapeMetrics {
  double flat_area = 0.0;                // A_D: area of the reference (flat) mesh
  double support_area = 0.0;             // A_d
  double shadow_area = 0.0;              // A_s
  double shadow_area_error_bound = 0.0;  // P h sqrt(2) of the rasterisation
  double drape_coefficient = 0.0;        // (A_s - A_d) / (A_D - A_d)
  int folds = 0;
  std::vector<double> fold_angles;  // polar angles of the fold crests (rad, in [-pi, pi))
  double lowest_z = 0.0;            // lowest node
  double highest_z = 0.0;
  double min_outline_radius = 0.0;  // of the smoothed outline r(theta)
  double max_outline_radius = 0.0;
  double mean_outline_radius = 0.0;
  double max_radius = 0.0;  // largest horizontal distance of any node from the axis
  std::vector<double>
      outline_radius;  // smoothed r(theta) of the bins, theta_k = -pi + (k+.5) dtheta
};

// Area of the horizontal projection (shadow) of a mesh: the union of its projected quads.
// error_bound, if given, receives P h sqrt(2) (see DrapeMetricsSettings::raster_cells).
double shadowArea(const QuadMesh& mesh, const std::vector<Eigen::Vector3d>& positions,
                  int raster_cells = 2048, double* error_bound = nullptr);

// Total area of a mesh (sum of its quads, each split into two triangles).
double surfaceArea(const QuadMesh& mesh, const std::vector<Eigen::Vector3d>& positions);

// Peaks of a periodic signal whose prominence (height above the higher of the two lowest points
// separating it from a higher peak, or the global minimum) is at least min_prominence.
std::vector<int> periodicPeaks(const std::vector<double>& signal, double min_prominence);

// Cusick drape coefficient, fold count and extents of a draped mesh; mesh holds the flat
// reference state and positions the draped nodes.
DrapeMetrics measureDrape(const QuadMesh& mesh, const std::vector<Eigen::Vector3d>& positions,
                          const DrapeSupport& support,
                          const DrapeMetricsSettings& settings = DrapeMetricsSettings());

// Deepest penetration of any node into any obstacle (>= 0; 0 when every gap is positive).
double maxPenetration(const std::vector<Eigen::Vector3d>& positions,
                      const RigidSurfaces& colliders);

}  // namespace chs
