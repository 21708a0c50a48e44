#include "cloth_hair_sim/core/shell/kirchhoff_love_quadrature.h"

#include <cmath>
#include <functional>
#include <memory>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/shell/midsurface_frame.h"

namespace chs {

void gaussLegendreUnit(int n, std::vector<double>& nodes, std::vector<double>& weights) {
  nodes.assign(n, 0.0);
  weights.assign(n, 0.0);
  for (int i = 0; i < n; ++i) {
    // Newton on the Legendre polynomial P_n from the Chebyshev-like initial guess.
    double t = std::cos(M_PI * (i + 0.75) / (n + 0.5));
    double dp = 1.0;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1.0, p1 = t;
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2.0 * k - 1.0) * t * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      dp = n * (t * p1 - p0) / (t * t - 1.0);
      const double step = p1 / dp;
      t -= step;
      if (std::abs(step) < 1e-16) break;
    }
    nodes[i] = 0.5 * (1.0 - t);
    weights[i] = 1.0 / ((1.0 - t * t) * dp * dp);  // 2/((1-t^2) P_n'^2) scaled to [0,1]
  }
}

std::vector<KirchhoffLovePoint> buildKirchhoffLovePoints(
    int num_faces, const FaceStencilFunction& stencil_at,
    const std::vector<Eigen::Vector3d>& reference_positions, double thickness,
    const KirchhoffLoveQuadrature& rule) {
  if (!std::isfinite(thickness) || thickness <= 0.0)
    throw InputError("buildKirchhoffLovePoints: thickness must be positive, got " +
                     std::to_string(thickness));
  if (rule.in_plane_order < 1)
    throw InputError("buildKirchhoffLovePoints: in-plane Gauss order must be >= 1, got " +
                     std::to_string(rule.in_plane_order));
  if (num_faces < 0 || !stencil_at)
    throw InputError("buildKirchhoffLovePoints: needs a face count >= 0 and a stencil source");
  std::vector<double> uv, w;
  gaussLegendreUnit(rule.in_plane_order, uv, w);
  const double h = rule.thickness_rule == ThicknessRule::kGauss ? thickness / (2.0 * std::sqrt(3.0))
                                                                : thickness / 4.0;
  const double xi3[2] = {-h, h};
  std::vector<KirchhoffLovePoint> points;
  points.reserve(static_cast<std::size_t>(num_faces) * uv.size() * uv.size() * 2);
  for (int f = 0; f < num_faces; ++f)
    for (std::size_t i = 0; i < uv.size(); ++i)
      for (std::size_t j = 0; j < uv.size(); ++j) {
        // One stencil object per fibre: its points share the mid-surface evaluation.
        const auto stencil = std::make_shared<const SurfaceStencil>(stencil_at(f, uv[i], uv[j]));
        for (double z : xi3)
          points.emplace_back(stencil, f, Eigen::Vector2d(uv[i], uv[j]), z,
                              w[i] * w[j] * 0.5 * thickness, reference_positions);
      }
  return points;
}

namespace {

// Calls fibre(first, last) for each run [first, last) of points on one fibre (sharing a stencil)
// whose first point lies in [begin, end): a blocked range may cut a fibre, which then belongs to
// the range that holds its first point.
template <class Fibre>
void forFibres(const std::vector<KirchhoffLovePoint>& points, int begin, int end, Fibre&& fibre) {
  const int n = static_cast<int>(points.size());
  int first = begin;
  while (first < end && first > 0 && points[first].sharesFibreWith(points[first - 1])) ++first;
  while (first < end) {
    int last = first + 1;
    while (last < n && points[last].sharesFibreWith(points[first])) ++last;
    fibre(first, last);
    first = last;
  }
}

}  // namespace

double kirchhoffLoveEnergy(const std::vector<KirchhoffLovePoint>& points,
                           const HenckyLamina& material, const std::vector<Eigen::Vector3d>& x,
                           std::vector<Eigen::Vector3d>* gradient) {
  const int n = static_cast<int>(points.size());
  if (!gradient)
    return tbb::parallel_reduce(
        tbb::blocked_range<int>(0, n), 0.0,
        [&](const tbb::blocked_range<int>& r, double e) {
          forFibres(points, r.begin(), r.end(), [&](int first, int last) {
            const MidSurfaceFrame frame = MidSurfaceFrame::evaluate(points[first].stencil(), x);
            for (int q = first; q < last; ++q) e += points[q].energy(material, frame);
          });
          return e;
        },
        std::plus<double>());
  // Threads scatter into private gradients that are summed afterwards: no races.
  struct Local {
    double energy = 0.0;
    std::vector<Eigen::Vector3d> gradient;
  };
  const std::size_t nx = x.size();
  tbb::enumerable_thread_specific<Local> local([nx] {
    return Local{0.0, std::vector<Eigen::Vector3d>(nx, Eigen::Vector3d::Zero())};
  });
  tbb::parallel_for(tbb::blocked_range<int>(0, n), [&](const tbb::blocked_range<int>& r) {
    Local& l = local.local();
    forFibres(points, r.begin(), r.end(), [&](int first, int last) {
      // One mid-surface frame and one pull-back per fibre: the pull-back is linear in the
      // adjoints dPsi/dg_i of its points, so they are summed first.
      const SurfaceStencil& stencil = points[first].stencil();
      const MidSurfaceFrame frame = MidSurfaceFrame::evaluate(stencil, x);
      Eigen::Matrix3d dpsi_da = Eigen::Matrix3d::Zero(), dpsi_dg;
      Eigen::Matrix<double, 3, 2> dpsi_da3d = Eigen::Matrix<double, 3, 2>::Zero();
      for (int q = first; q < last; ++q) {
        l.energy += points[q].energy(material, frame, &dpsi_dg);
        dpsi_da += dpsi_dg;  // g_alpha = a_alpha + xi3 a_{3,alpha}, g_3 = a_3
        dpsi_da3d += points[q].xi3() * dpsi_dg.leftCols<2>();
      }
      frame.addPullBack(stencil, dpsi_da, dpsi_da3d, l.gradient);
    });
  });
  gradient->assign(nx, Eigen::Vector3d::Zero());
  double energy = 0.0;
  for (const Local& l : local) {
    energy += l.energy;
    for (std::size_t p = 0; p < nx; ++p) (*gradient)[p] += l.gradient[p];
  }
  return energy;
}

int updateKirchhoffLovePlasticity(std::vector<KirchhoffLovePoint>& points,
                                  const HenckyLamina& material,
                                  const std::vector<Eigen::Vector3d>& x) {
  if (material.isElastic()) return 0;  // nothing can yield
  return tbb::parallel_reduce(
      tbb::blocked_range<int>(0, static_cast<int>(points.size())), 0,
      [&](const tbb::blocked_range<int>& r, int yielded) {
        for (int q = r.begin(); q < r.end(); ++q)
          yielded += points[q].updatePlasticity(material, x) ? 1 : 0;
        return yielded;
      },
      std::plus<int>());
}

}  // namespace chs
