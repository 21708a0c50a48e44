#include "cloth_hair_sim/core/io/drape_plots.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>
#include <stdexcept>

#include "cloth_hair_sim/core/io/gnuplot.h"

namespace chs {

namespace {

// pm3d draws a quad from two scans of two points: (p0 p1) then (p3 p2).
void appendQuad(std::ostringstream& s, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                const Eigen::Vector3d& c, const Eigen::Vector3d& d) {
  s << a.x() << ' ' << a.y() << ' ' << a.z() << '\n'
    << b.x() << ' ' << b.y() << ' ' << b.z() << "\n\n"
    << d.x() << ' ' << d.y() << ' ' << d.z() << '\n'
    << c.x() << ' ' << c.y() << ' ' << c.z() << "\n\n\n";
}

}  // namespace

void plotConvergence(const DrapeResult& result, const std::string& png_path,
                     const std::string& title, double tolerance) {
  if (result.history.empty())
    throw std::runtime_error("convergence plot: the solve recorded no iterations");
  std::ostringstream s;
  s << std::setprecision(10);
  s << "$hist << EOD\n";
  // Iterations count from 1 in each load step (the particle method reports every n-th one):
  // add up the last count of every finished step.
  long offset = 0, last = 0;
  int step = result.history.front().load_step;
  for (const auto& e : result.history) {
    if (e.load_step != step || e.iteration < last) offset += last, step = e.load_step;
    last = e.iteration;
    s << offset + e.iteration << ' ' << std::max(e.residual, 1e-300) << ' ' << e.load_factor << ' '
      << e.load_step << ' ' << e.coarser_grids << '\n';
  }
  s << "EOD\n"
    << "set terminal pngcairo size 1000,600 enhanced font 'DejaVu Sans,11'\n"
    << "set output " << gnuplotQuote(png_path) << "\n"
    << "set title " << gnuplotQuote(title) << " noenhanced\n"
    << "set xlabel 'cumulative iteration'\n"
    << "set ylabel 'relative residual'\nset logscale y\nset format y '10^{%L}'\n"
    << "set y2label 'load factor {/Symbol l}'\nset y2tics\nset ytics nomirror\n"
    << "set y2range [0:1.05 < * ]\nset grid\nset key top right box opaque\n";
  if (tolerance > 0.0)
    s << "set arrow from graph 0, first " << tolerance << " to graph 1, first " << tolerance
      << " nohead dt 2 lc rgb 'gray40'\n"
      << "set label 'tolerance' at graph 0.01, first " << tolerance * 1.8 << " tc rgb 'gray40'\n";
  // A nested start's coarser grids (their residuals on their own grids) in another colour.
  const bool nested = std::any_of(result.history.begin(), result.history.end(),
                                  [](const ProgressEvent& e) { return e.coarser_grids > 0; });
  if (nested) s << "set key below\nset bmargin 6\n";  // its first points stand where the key would
  s << "plot $hist using 1:($5 == 0 ? $2 : 1/0) with linespoints pt 7 ps 0.5 lc rgb '#1f77b4' "
       "title 'residual', ";
  if (nested)
    s << "$hist using 1:($5 > 0 ? $2 : 1/0) with linespoints pt 7 ps 0.5 lc rgb '#2ca02c' "
         "title 'residual on the coarser grids', ";
  s << "$hist using 1:3 axes x1y2 with steps lw 2 lc rgb '#d62728' title 'load factor'\n";
  runGnuplot(s.str());
}

void plotDrape(const QuadMesh& mesh, const std::vector<Eigen::Vector3d>& positions,
               const std::vector<ColliderSpec>& colliders, const std::string& png_path,
               const std::string& title) {
  if (positions.size() != mesh.vertices.size() || positions.empty())
    throw std::runtime_error("drape picture: positions do not match the mesh");
  Eigen::Vector3d lo = positions.front(), hi = lo;
  for (const auto& p : positions) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const double extent = std::max((hi - lo).head<2>().maxCoeff(), 1e-12);
  const double z_floor = lo.z() - 0.1 * extent;

  std::ostringstream s;
  s << std::setprecision(8);
  s << "$cloth << EOD\n";
  for (const auto& q : mesh.quads)
    appendQuad(s, positions[q[0]], positions[q[1]], positions[q[2]], positions[q[3]]);
  s << "EOD\n$solid << EOD\n";
  // Obstacle faces split to about the cloth's element size: pm3d sorts quads by their centres,
  // so a large face would hide cloth in front of it.
  double edge = 0.0;
  for (const auto& q : mesh.quads) edge += (positions[q[1]] - positions[q[0]]).norm();
  edge = std::max(edge / mesh.numQuads(), 1e-3 * extent);
  bool any_solid = false;
  for (const auto& c : colliders)
    for (const auto& q : sketchCollider(c, z_floor, 0.6 * extent)) {
      const double size = std::max((q[2] - q[0]).norm(), (q[3] - q[1]).norm());
      const int n = std::clamp(static_cast<int>(std::ceil(size / edge)), 1, 64);
      // Drawn a little low: cloth resting on a face would otherwise fight with it for depth.
      const Eigen::Vector3d drop(0.0, 0.0, -0.02 * extent);
      auto at = [&](int i, int j) {
        const double u = static_cast<double>(i) / n, v = static_cast<double>(j) / n;
        return Eigen::Vector3d((1 - u) * (1 - v) * q[0] + u * (1 - v) * q[1] + u * v * q[2] +
                               (1 - u) * v * q[3] + drop);
      };
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i)
          appendQuad(s, at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
      any_solid = true;
    }
  s << "EOD\n";
  // A flat result has no z span: gnuplot refuses an empty colour range, and one below the
  // 8 printed digits of lo.z is empty too. A span of 1e-3 of the extent (or 1e-6 of |z|) keeps
  // it open while the colours still show any real height difference.
  const double zspan = std::max({hi.z() - lo.z(), 1e-3 * extent, 1e-6 * std::abs(lo.z())});
  s << "set terminal pngcairo size 1400,700 enhanced font 'DejaVu Sans,11'\n"
    << "set output " << gnuplotQuote(png_path) << "\n"
    << "set multiplot layout 1,2 title " << gnuplotQuote(title) << " noenhanced\n"
    << "set palette defined (0 '#30123b', 0.25 '#4686fb', 0.5 '#1ae4b6', 0.75 '#faba39', "
       "1 '#7a0403')\n"
    << "set cbrange [" << lo.z() << ":" << lo.z() + zspan << "]\nset cblabel 'z'\n"
    << "set pm3d depthorder border lc rgb '#303030' lw 0.4\n"
    << "set xlabel 'x'\nset ylabel 'y'\nset zlabel 'z'\nset tics font ',9'\n"
    << "set view 58, 35\nset view equal xyz\nset xyplane 0\n"
    << "set zrange [" << z_floor << ":*]\n"
    << "set title '3D view'\n"
    << "splot $cloth with pm3d notitle";
  if (any_solid) s << ", $solid with pm3d fc rgb '#b8b8b8' notitle";
  s << "\nset title 'top view'\nset view 0, 0, 1, 1\nset view equal xy\nunset zlabel\n"
    << "unset ztics\n"
    << "splot $cloth with pm3d notitle";
  if (any_solid) s << ", $solid with pm3d fc rgb '#b8b8b8' notitle";
  s << "\nunset multiplot\n";
  runGnuplot(s.str());
}

}  // namespace chs
