#pragma once
#include <optional>
#include <string>
#include <vector>

#include "cloth_hair_sim/core/drape/drape_problem.h"
#include "cloth_hair_sim/core/fem_shell/shell_element.h"

namespace chs {

// The start of a static drape from the drape of the same garment on every second grid line
// (nested iteration, as multigrid's full cycle starts each level from the one below): the flat
// sheet's Newton path falls, buckles and folds at the fine grid's cost per iteration; from the
// coarse drape interpolated the fine grid's Newton only corrects it. For a rectangle's regular
// grid (makeRectangleMesh's numbering, checked quad by quad) with an even number of cells each
// way, without seams or nodal loads. A drape has several stable equilibria (a tablecloth's
// corners fold deep or shallow): the one found from the coarse drape need not be the one the
// flat sheet's path finds, and the fold pattern is the coarse grid's.
class GridCoarsening {
 public:
  // Empty where the problem is not such a grid, has fewer than 2 * min_cells cells along a side,
  // or the coarse cells would be longer than 3/4 of the sheet's bending length (D / (rho_A
  // g))^(1/3) (no coarse grid for Kawabata bending or without gravity); then *why says which.
  static std::optional<GridCoarsening> of(const DrapeProblem& fine, int min_cells,
                                          std::string* why = nullptr);

  // The same garment, material, gravity and colliders on every second grid line; a fine vertex
  // held (clamped, pinned, a fixed component) holds the coarse vertex nearest to it.
  const DrapeProblem& coarse() const { return coarse_; }
  int cellsX() const { return nx_; }
  int cellsY() const { return ny_; }

  // The fine nodes from the coarse drape (positions, unit directors): bilinear between the coarse
  // nodes, directors normalised; a node that lands inside a collider moved out to its surface
  // (the chord between two nodes draped round an edge cuts the corner); held components and
  // directors kept from `reference` (the fine model's own nodes).
  std::vector<ShellNode> prolong(const std::vector<Eigen::Vector3d>& positions,
                                 const std::vector<Eigen::Vector3d>& directors,
                                 const std::vector<ShellNode>& reference,
                                 const DrapeProblem& fine) const;

 private:
  int nx_ = 0, ny_ = 0;
  DrapeProblem coarse_;
};

}  // namespace chs
