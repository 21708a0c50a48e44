#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace chs::rod {

// Display strands interpolated from simulated guide strands, as games and film draw hair: each
// display strand is a fixed blend of three guides whose roots are near each other, vertex by
// vertex, x_i = sum_k w_k x^(g_k)_i with barycentric weights w_k >= 0, sum 1. The blend is set
// once from the guides' roots and then costs one weighted sum per vertex and frame, so the count
// drawn is a parameter independent of the count simulated.
struct DisplayStrand {
  std::array<int, 3> guides{};
  std::array<double, 3> weights{};
};

// `count` display strands over guides whose roots are `roots`: each picks a random guide (in
// turn) and its two nearest neighbours by root distance, and random barycentric weights, with a
// fixed seed so that the same groom draws the same way. Throws InputError for fewer than three
// guides, a non-finite root, or a count outside 0..kMaxDisplayStrands.
constexpr int kMaxDisplayStrands = 1000000;
std::vector<DisplayStrand> blendDisplayStrands(const std::vector<Eigen::Vector3d>& roots, int count,
                                               std::uint32_t seed = 1);

// The display strands' vertices now, one polyline per display strand. Every guide must have the
// same number of vertices; throws InputError otherwise or for a guide index out of range.
std::vector<std::vector<Eigen::Vector3d>> displayStrands(
    const std::vector<DisplayStrand>& blend,
    const std::vector<const std::vector<Eigen::Vector3d>*>& guides);

}  // namespace chs::rod
