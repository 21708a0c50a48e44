// Display strands blended from guides (core/rod/display_strands.h): barycentric blends of three
// neighbouring guides reproduce a translated copy exactly (linear precision), stay within the
// guides' root triangle, are reproducible from their seed, and bad input is refused.
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/rod/display_strands.h"
#include "cloth_hair_sim/core/rod/strand_shapes.h"

namespace chs::rod {
namespace {

using Vec3 = Eigen::Vector3d;

// A 10 x 10 patch of guides 5 mm apart, all the same curl translated to its root.
struct Groom {
  std::vector<Vec3> roots;
  std::vector<std::vector<Vec3>> strands;
  std::vector<const std::vector<Vec3>*> pointers() const {
    std::vector<const std::vector<Vec3>*> p;
    for (const auto& s : strands) p.push_back(&s);
    return p;
  }
};
Groom patch() {
  Groom g;
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j) {
      const Vec3 root(0.005 * i, 0.005 * j, 0.0);
      g.roots.push_back(root);
      g.strands.push_back(helicalStrand(root, Vec3(0, 0, -1), 0.003, 0.01, 0.1, 30));
    }
  return g;
}

TEST(DisplayStrands, BlendOfTranslatedGuidesIsTranslatedCopy) {
  const Groom g = patch();
  const std::vector<DisplayStrand> blend = blendDisplayStrands(g.roots, 1000, 7);
  const auto drawn = displayStrands(blend, g.pointers());
  ASSERT_EQ(drawn.size(), 1000u);
  double worst = 0.0, spread = 0.0;
  for (std::size_t s = 0; s < drawn.size(); ++s) {
    double wsum = 0.0;
    for (int k = 0; k < 3; ++k) {
      EXPECT_GE(blend[s].weights[k], 0.0);
      wsum += blend[s].weights[k];
    }
    EXPECT_NEAR(wsum, 1.0, 1e-15);
    const Vec3 shift = drawn[s][0] - g.roots[0];
    for (std::size_t i = 0; i < drawn[s].size(); ++i)
      worst = std::max(worst, (drawn[s][i] - (g.strands[0][i] + shift)).norm());
    // Within its guides' root triangle: no farther from its first guide than the farther
    // neighbour is.
    const Vec3 r0 = g.roots[blend[s].guides[0]];
    const double reach = std::max((g.roots[blend[s].guides[1]] - r0).norm(),
                                  (g.roots[blend[s].guides[2]] - r0).norm());
    spread = std::max(spread, (drawn[s][0] - r0).norm() / reach);
  }
  std::printf(
      "1000 display strands from 100 guides: largest deviation from a translated guide "
      "%.3e m; root at most %.3f of the neighbours' reach from its guide\n",
      worst, spread);
  EXPECT_LT(worst, 1e-15);
  EXPECT_LE(spread, 1.0 + 1e-12);
}

TEST(DisplayStrands, SeedMakesItReproducible) {
  const Groom g = patch();
  const auto a = blendDisplayStrands(g.roots, 200, 3), b = blendDisplayStrands(g.roots, 200, 3),
             c = blendDisplayStrands(g.roots, 200, 4);
  int same = 0, differ = 0;
  for (int s = 0; s < 200; ++s) {
    same += a[s].guides == b[s].guides && a[s].weights == b[s].weights;
    differ += a[s].weights != c[s].weights;
  }
  std::printf("display blends: %d of 200 identical with the same seed, %d differ with another\n",
              same, differ);
  EXPECT_EQ(same, 200);
  EXPECT_GT(differ, 190);
}

TEST(DisplayStrands, BadInputIsRefused) {
  const Groom g = patch();
  const auto refused = [](auto&& f, const char* what) {
    try {
      f();
      ADD_FAILURE() << "accepted " << what;
    } catch (const InputError& e) {
      std::printf("%-24s -> InputError: %s\n", what, e.what());
    }
  };
  refused([&] { blendDisplayStrands({Vec3::Zero(), Vec3::UnitX()}, 10); }, "two guides");
  std::vector<Vec3> roots = g.roots;
  roots[5].x() = std::nan("");
  refused([&] { blendDisplayStrands(roots, 10); }, "NaN root");
  refused([&] { blendDisplayStrands(g.roots, -1); }, "negative count");
  refused([&] { blendDisplayStrands(g.roots, kMaxDisplayStrands + 1); }, "count over the limit");
  Groom uneven = g;
  uneven.strands[3].pop_back();
  const auto blend = blendDisplayStrands(g.roots, 10);
  refused([&] { displayStrands(blend, uneven.pointers()); }, "guides of unequal length");
  std::vector<DisplayStrand> wrong = blend;
  wrong[0].guides[1] = 500;
  refused([&] { displayStrands(wrong, g.pointers()); }, "guide out of range");
}

}  // namespace
}  // namespace chs::rod
