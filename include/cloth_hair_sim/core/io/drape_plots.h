#pragma once
#include <string>
#include <vector>

#include <Eigen/Core>

#include "cloth_hair_sim/core/drape/drape_problem.h"
#include "cloth_hair_sim/core/io/collider_spec.h"
#include "cloth_hair_sim/core/mesh/quad_mesh.h"

namespace chs {

// Pictures of a drape, drawn by gnuplot (see runGnuplot); throw std::runtime_error on failure.

// Convergence history as PNG: log10 relative residual against cumulative iteration, the load
// factor on the second axis; tolerance > 0 draws the convergence threshold.
void plotConvergence(const DrapeResult& result, const std::string& png_path,
                     const std::string& title, double tolerance = 0.0);

// Draped shape as PNG: a 3D view and a top view (to count folds), quads coloured by height,
// equal axes, obstacles in grey.
void plotDrape(const QuadMesh& mesh, const std::vector<Eigen::Vector3d>& positions,
               const std::vector<ColliderSpec>& colliders, const std::string& png_path,
               const std::string& title);

}  // namespace chs
