#include "cloth_hair_sim/core/rod/display_strands.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include "cloth_hair_sim/core/common/input_error.h"

namespace chs::rod {

std::vector<DisplayStrand> blendDisplayStrands(const std::vector<Eigen::Vector3d>& roots, int count,
                                               std::uint32_t seed) {
  const int n = static_cast<int>(roots.size());
  if (n < 3)
    throw InputError("display strands: need at least three guides, got " + std::to_string(n));
  for (int g = 0; g < n; ++g)
    if (!roots[g].allFinite())
      throw InputError("display strands: root of guide " + std::to_string(g) + " is not finite");
  if (count < 0 || count > kMaxDisplayStrands)
    throw InputError("display strands: count " + std::to_string(count) + " outside 0.." +
                     std::to_string(kMaxDisplayStrands));
  // Each guide's two nearest neighbours (brute force: grooms have thousands of guides, and this
  // runs once).
  std::vector<std::array<int, 2>> near(n);
  for (int g = 0; g < n; ++g) {
    std::array<double, 2> d{INFINITY, INFINITY};
    std::array<int, 2> k{-1, -1};
    for (int h = 0; h < n; ++h) {
      if (h == g) continue;
      const double r = (roots[h] - roots[g]).squaredNorm();
      if (r < d[0]) {
        d = {r, d[0]};
        k = {h, k[0]};
      } else if (r < d[1]) {
        d[1] = r;
        k[1] = h;
      }
    }
    near[g] = k;
  }
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<DisplayStrand> out(count);
  for (int s = 0; s < count; ++s) {
    const int g = s % n;
    // Uniform on the triangle: fold the unit square's upper half back.
    double a = u(rng), b = u(rng);
    if (a + b > 1.0) {
      a = 1.0 - a;
      b = 1.0 - b;
    }
    out[s].guides = {g, near[g][0], near[g][1]};
    out[s].weights = {1.0 - a - b, a, b};
  }
  return out;
}

std::vector<std::vector<Eigen::Vector3d>> displayStrands(
    const std::vector<DisplayStrand>& blend,
    const std::vector<const std::vector<Eigen::Vector3d>*>& guides) {
  if (guides.empty()) throw InputError("display strands: no guides");
  const std::size_t nv = guides[0]->size();
  for (std::size_t g = 0; g < guides.size(); ++g)
    if (guides[g]->size() != nv)
      throw InputError("display strands: guide " + std::to_string(g) + " has " +
                       std::to_string(guides[g]->size()) + " vertices, guide 0 has " +
                       std::to_string(nv));
  std::vector<std::vector<Eigen::Vector3d>> out(blend.size(), std::vector<Eigen::Vector3d>(nv));
  for (std::size_t s = 0; s < blend.size(); ++s) {
    for (int g : blend[s].guides)
      if (g < 0 || g >= static_cast<int>(guides.size()))
        throw InputError("display strands: strand " + std::to_string(s) + " blends guide " +
                         std::to_string(g) + " of " + std::to_string(guides.size()));
    for (std::size_t i = 0; i < nv; ++i) {
      Eigen::Vector3d x = Eigen::Vector3d::Zero();
      for (int k = 0; k < 3; ++k) x += blend[s].weights[k] * (*guides[blend[s].guides[k]])[i];
      out[s][i] = x;
    }
  }
  return out;
}

}  // namespace chs::rod
