#pragma once
#include <optional>
#include <string>
#include <vector>

#include "cloth_hair_sim/core/drape/drape_problem.h"
#include "cloth_hair_sim/core/fem_shell/shell_element.h"

namespace chs {

// The start of a static drape from the drape of the same garment on a mesh of every second
// grid line (nested iteration, as multigrid's full cycle starts each level from the one below):
// the flat sheet's Newton path falls, buckles and folds at the fine mesh's cost per iteration;
// from the coarse drape interpolated the fine mesh's Newton only corrects it. For a quad mesh
// that is a 2 x 2 refinement of a coarser one (a rectangle's grid with even cell counts, the
// disc's O-grid with even block sizes), recognised from its connectivity alone: every quad has
// one coarse corner, two edge midpoints and one face centre, in that order round it. Without
// seams or nodal loads. A drape has several stable equilibria (a tablecloth's corners fold deep
// or shallow): the one found from the coarse drape need not be the one the flat sheet's path
// finds, and the fold pattern is the coarse mesh's.
class GridCoarsening {
 public:
  // Empty where the mesh is no such refinement, the coarse mesh would have fewer than
  // min_quads quads, or its mean edge would be longer than 3/4 of the sheet's bending length
  // (D / (rho_A g))^(1/3) (none for Kawabata bending or without gravity); then *why says which.
  static std::optional<GridCoarsening> of(const DrapeProblem& fine, int min_quads,
                                          std::string* why = nullptr);

  // The same garment, material, gravity and colliders on the coarse mesh; a fine vertex held
  // (clamped, pinned, a fixed component) holds a coarse vertex next to it.
  const DrapeProblem& coarse() const { return coarse_; }

  // The fine nodes from the coarse drape (positions, unit directors): each fine vertex moves by
  // the mean displacement of the coarse vertices it lies between (one, the two ends of its coarse
  // edge, or the four corners of its coarse quad: bilinear, exact for an affine map), directors
  // their normalised mean; a node that lands inside a collider moved out to its surface (the
  // chord between two nodes draped round an edge cuts the corner); held components and
  // directors kept from `reference` (the fine model's own nodes).
  std::vector<ShellNode> prolong(const std::vector<Eigen::Vector3d>& positions,
                                 const std::vector<Eigen::Vector3d>& directors,
                                 const std::vector<ShellNode>& reference,
                                 const DrapeProblem& fine) const;

 private:
  DrapeProblem coarse_;
  std::vector<std::vector<int>> parents_;  // of each fine vertex: coarse vertices
};

}  // namespace chs
