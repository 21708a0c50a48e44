#pragma once
#include <vector>

#include <Eigen/Core>

namespace chs::rod {

// Rest shapes of a strand as polylines of `segments` segments of equal length, starting at the
// root. All throw InputError for a non-positive or non-finite length, size or direction, or
// fewer than one segment.

// Straight along `direction`.
std::vector<Eigen::Vector3d> straightStrand(const Eigen::Vector3d& root,
                                            const Eigen::Vector3d& direction, double length,
                                            int segments);

// A helix (a curl) about an axis through root + radius * (root side), rising `pitch` per turn
// along `axis`: curvature kappa = R / (R^2 + c^2), torsion tau = c / (R^2 + c^2) with
// c = pitch / 2 pi. The first segment leaves the root along the helix tangent.
std::vector<Eigen::Vector3d> helicalStrand(const Eigen::Vector3d& root, const Eigen::Vector3d& axis,
                                           double radius, double pitch, double length,
                                           int segments);

// A planar wave root + s direction + amplitude sin(2 pi s / wavelength) normal, resampled to
// equal arc length.
std::vector<Eigen::Vector3d> wavyStrand(const Eigen::Vector3d& root,
                                        const Eigen::Vector3d& direction,
                                        const Eigen::Vector3d& normal, double amplitude,
                                        double wavelength, double length, int segments);

}  // namespace chs::rod
