#include "cloth_hair_sim/core/io/simulation_plots.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <iomanip>
#include <sstream>
#include <stdexcept>

#include "cloth_hair_sim/core/io/gnuplot.h"

namespace chs {

namespace {

using Vec3 = Eigen::Vector3d;
using Quad = std::array<Vec3, 4>;

// pm3d draws a quad from two scans of two points: (p0 p1) then (p3 p2); a triangle is a quad
// with its last corner repeated.
void appendQuad(std::ostringstream& s, const Quad& q) {
  auto row = [&](const Vec3& p) { s << p.x() << ' ' << p.y() << ' ' << p.z() << '\n'; };
  row(q[0]);
  row(q[1]);
  s << '\n';
  row(q[3]);
  row(q[2]);
  s << "\n\n";
}

constexpr double kPi = 3.14159265358979323846;
constexpr int kAround = 24;  // facets around a round shape

Vec3 onSphere(double r, double polar, double azimuth) {
  return r * Vec3(std::sin(polar) * std::cos(azimuth), std::sin(polar) * std::sin(azimuth),
                  std::cos(polar));
}

// Latitude bands from polar angle a0 to a1 of a sphere of radius r centred at c (local frame).
void sphereBands(std::vector<Quad>& out, const Vec3& c, double r, double a0, double a1) {
  const int bands = std::max(1, static_cast<int>(std::round((a1 - a0) / kPi * kAround / 2)));
  for (int i = 0; i < bands; ++i)
    for (int j = 0; j < kAround; ++j) {
      const double p0 = a0 + (a1 - a0) * i / bands, p1 = a0 + (a1 - a0) * (i + 1) / bands;
      const double q0 = 2 * kPi * j / kAround, q1 = 2 * kPi * (j + 1) / kAround;
      out.push_back({c + onSphere(r, p0, q0), c + onSphere(r, p0, q1), c + onSphere(r, p1, q1),
                     c + onSphere(r, p1, q0)});
    }
}

// The side of a z-axis cylinder of radius r between z0 and z1 (local frame).
void cylinderSide(std::vector<Quad>& out, double r, double z0, double z1) {
  for (int j = 0; j < kAround; ++j) {
    const double q0 = 2 * kPi * j / kAround, q1 = 2 * kPi * (j + 1) / kAround;
    const Vec3 a(r * std::cos(q0), r * std::sin(q0), 0.0), b(r * std::cos(q1), r * std::sin(q1), 0);
    out.push_back({a + z0 * Vec3::UnitZ(), b + z0 * Vec3::UnitZ(), b + z1 * Vec3::UnitZ(),
                   a + z1 * Vec3::UnitZ()});
  }
}

// Facets of a collider at a pose, for pictures only: a plane is a square of half-size extent
// around the point of it nearest to focus.
std::vector<Quad> sketchShape(const SimulationCollider& c, const Eigen::Isometry3d& pose,
                              const Vec3& focus, double extent) {
  const Eigen::Isometry3d frame = pose * c.shape.offset;
  const auto& d = c.shape.dimensions;
  std::vector<Quad> local;
  switch (c.shape.type) {
    case ColliderShape::Type::kPlane: {
      const Vec3 f = frame.inverse() * focus;
      const double x = f.x(), y = f.y(), e = extent;
      local.push_back({Vec3(x - e, y - e, 0), Vec3(x + e, y - e, 0), Vec3(x + e, y + e, 0),
                       Vec3(x - e, y + e, 0)});
      break;
    }
    case ColliderShape::Type::kSphere:
      sphereBands(local, Vec3::Zero(), d[0], 0.0, kPi);
      break;
    case ColliderShape::Type::kBox: {
      const Vec3 h = 0.5 * Vec3(d[0], d[1], d[2]);
      auto p = [&](int i, int j, int k) {
        return Vec3(i ? h.x() : -h.x(), j ? h.y() : -h.y(), k ? h.z() : -h.z());
      };
      local = {{p(0, 0, 1), p(1, 0, 1), p(1, 1, 1), p(0, 1, 1)},
               {p(0, 0, 0), p(0, 1, 0), p(1, 1, 0), p(1, 0, 0)},
               {p(0, 0, 0), p(1, 0, 0), p(1, 0, 1), p(0, 0, 1)},
               {p(0, 1, 0), p(0, 1, 1), p(1, 1, 1), p(1, 1, 0)},
               {p(0, 0, 0), p(0, 0, 1), p(0, 1, 1), p(0, 1, 0)},
               {p(1, 0, 0), p(1, 1, 0), p(1, 1, 1), p(1, 0, 1)}};
      break;
    }
    case ColliderShape::Type::kCylinder: {
      const double r = d[0], z = 0.5 * d[1];
      cylinderSide(local, r, -z, z);
      for (int j = 0; j < kAround; ++j) {
        const double q0 = 2 * kPi * j / kAround, q1 = 2 * kPi * (j + 1) / kAround;
        for (double zc : {-z, z}) {
          const Vec3 centre(0, 0, zc);
          local.push_back({centre, centre + Vec3(r * std::cos(q0), r * std::sin(q0), 0),
                           centre + Vec3(r * std::cos(q1), r * std::sin(q1), 0), centre});
        }
      }
      break;
    }
    case ColliderShape::Type::kCapsule: {
      const double r = d[0], z = 0.5 * d[1];
      cylinderSide(local, r, -z, z);
      sphereBands(local, Vec3(0, 0, z), r, 0.0, 0.5 * kPi);
      sphereBands(local, Vec3(0, 0, -z), r, 0.5 * kPi, kPi);
      break;
    }
    case ColliderShape::Type::kMesh: {
      const TriangleMesh& m = c.shape.meshField()->mesh();
      for (const auto& t : m.triangles)
        local.push_back({m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]], m.vertices[t[2]]});
      break;
    }
  }
  for (auto& q : local)
    for (auto& p : q) p = frame * p;
  return local;
}

const char* colour(std::size_t body) {
  static const char* colours[] = {"#4a7bd0", "#d0574a", "#3f9f5a", "#e0a030", "#8a5ac0", "#40a8b8"};
  return colours[body % (sizeof colours / sizeof *colours)];
}

}  // namespace

void plotSimulationFrame(const std::vector<DisplaySurface>& bodies,
                         const std::vector<rod::Polylines>& hair,
                         const std::vector<std::string>& body_names,
                         const std::vector<SimulationCollider>& colliders,
                         const std::vector<Eigen::Isometry3d>& collider_poses,
                         const std::string& png_path, const std::string& title) {
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  double edge = 0.0;
  long triangles = 0;
  for (const auto& b : bodies) {
    for (const auto& p : b.vertices)
      if (p.allFinite()) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
    for (const auto& t : b.triangles) edge += (b.vertices[t[1]] - b.vertices[t[0]]).norm();
    triangles += static_cast<long>(b.triangles.size());
  }
  long segments = 0;
  for (const auto& h : hair)
    for (const auto& strand : h) {
      for (const auto& p : strand)
        if (p.allFinite()) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
      for (std::size_t i = 1; i < strand.size(); ++i) edge += (strand[i] - strand[i - 1]).norm();
      segments += static_cast<long>(strand.size()) - 1;
    }
  if (triangles + segments == 0 || !lo.allFinite())
    throw std::runtime_error("frame picture: no finite body surface or strand to draw");
  const double extent = std::max((hi - lo).maxCoeff(), 1e-6);
  edge = std::max(edge / (triangles + segments), 1e-3 * extent);
  const Vec3 focus = 0.5 * (lo + hi);

  std::ostringstream s;
  s << std::setprecision(8);
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    s << "$body" << b << " << EOD\n";
    for (const auto& t : bodies[b].triangles) {
      const auto& v = bodies[b].vertices;
      appendQuad(s, {v[t[0]], v[t[1]], v[t[2]], v[t[2]]});
    }
    s << "EOD\n";
  }
  for (std::size_t h = 0; h < hair.size(); ++h) {
    s << "$hair" << h << " << EOD\n";
    for (const auto& strand : hair[h]) {
      for (const auto& p : strand) s << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
      s << "\n\n";  // two blank lines: a new line, not the next row of a grid surface
    }
    s << "EOD\n";
  }
  s << "$solid << EOD\n";
  bool any_solid = false;
  for (std::size_t i = 0; i < colliders.size() && i < collider_poses.size(); ++i)
    for (const Quad& q : sketchShape(colliders[i], collider_poses[i], focus, 0.75 * extent)) {
      // Faces split to about the cloth's element size: pm3d sorts facets by their centres, so a
      // large face would hide cloth in front of it.
      const double size = std::max((q[2] - q[0]).norm(), (q[3] - q[1]).norm());
      const int n = std::clamp(static_cast<int>(std::ceil(size / edge)), 1, 64);
      // Drawn a little low: cloth resting on a face would otherwise fight with it for depth.
      const Vec3 drop(0.0, 0.0, -0.02 * extent);
      auto at = [&](int a, int b) {
        const double u = static_cast<double>(a) / n, v = static_cast<double>(b) / n;
        return Vec3((1 - u) * (1 - v) * q[0] + u * (1 - v) * q[1] + u * v * q[2] +
                    (1 - u) * v * q[3] + drop);
      };
      for (int b = 0; b < n; ++b)
        for (int a = 0; a < n; ++a)
          appendQuad(s, {at(a, b), at(a + 1, b), at(a + 1, b + 1), at(a, b + 1)});
      any_solid = true;
    }
  s << "EOD\n";
  auto plots = [&] {
    std::ostringstream p;
    p << "splot ";
    for (std::size_t b = 0; b < bodies.size(); ++b)
      p << (b ? ", " : "") << "$body" << b << " with pm3d fc rgb '" << colour(b) << "' notitle";
    if (any_solid) p << (bodies.empty() ? "" : ", ") << "$solid with pm3d fc rgb '#b8b8b8' notitle";
    for (std::size_t h = 0; h < hair.size(); ++h)
      p << (bodies.empty() && !any_solid && h == 0 ? "" : ", ") << "$hair" << h
        << " with lines lw 1.2 lc rgb '" << colour(bodies.size() + h) << "' notitle";
    return p.str() + "\n";
  };
  // pm3d plots have no key samples: the names as labels in their bodies' colours.
  std::ostringstream labels;
  for (std::size_t b = 0; b < bodies.size() + hair.size(); ++b)
    labels << "set label " << b + 1 << " "
           << gnuplotQuote(b < body_names.size() ? body_names[b] : "body " + std::to_string(b))
           << " at screen 0.02, screen " << 0.9 - 0.04 * b << " tc rgb '" << colour(b)
           << "' font ',13' noenhanced\n";
  const Vec3 margin = Vec3::Constant(0.1 * extent);
  s << "set terminal pngcairo size 1400,700 enhanced font 'DejaVu Sans,11'\n"
    << "set output " << gnuplotQuote(png_path) << "\n"
    << "set multiplot layout 1,2 title " << gnuplotQuote(title) << " noenhanced\n"
    << "set pm3d depthorder border lc rgb '#303030' lw 0.2\n"
    << "set pm3d lighting primary 0.6 specular 0.1\n"
    << "unset colorbox\n"
    << labels.str() << "set xlabel 'x'\nset ylabel 'y'\nset zlabel 'z'\nset tics font ',9'\n"
    << "set xrange [" << (lo - margin).x() << ":" << (hi + margin).x() << "]\n"
    << "set yrange [" << (lo - margin).y() << ":" << (hi + margin).y() << "]\n"
    << "set zrange [" << (lo - margin).z() << ":" << (hi + margin).z() << "]\n"
    << "set view 62, 30\nset view equal xyz\nset xyplane 0\n"
    << "set title '3D view'\n"
    << plots() << "set title 'front view (x-z)'\nset view 90, 0\nunset ytics\nunset ylabel\n"
    << plots() << "unset multiplot\n";
  runGnuplot(s.str());
}

void plotEnergy(const std::vector<FrameRecord>& frames, const std::vector<std::string>& body_names,
                const std::string& png_path, const std::string& title) {
  if (frames.empty()) throw std::runtime_error("energy plot: no frames");
  std::ostringstream s;
  s << std::setprecision(10) << "$e << EOD\n";
  for (const auto& f : frames) {
    s << f.time << ' ' << (std::isfinite(f.kinetic_energy) ? f.kinetic_energy : 0.0);
    for (const auto& b : f.bodies)
      s << ' ' << (std::isfinite(b.kinetic_energy) ? b.kinetic_energy : 0.0);
    s << '\n';
  }
  s << "EOD\n"
    << "set terminal pngcairo size 1000,600 enhanced font 'DejaVu Sans,11'\n"
    << "set output " << gnuplotQuote(png_path) << "\n"
    << "set title " << gnuplotQuote(title + ": kinetic energy") << " noenhanced\n"
    << "set xlabel 'simulated time [s]'\nset ylabel 'kinetic energy [J]'\nset grid\n"
    << "set key top right box opaque noenhanced\n"
    << "plot $e using 1:2 with linespoints lw 2 pt 7 ps 0.4 lc rgb '#202020' title 'world'";
  const std::size_t n = frames.front().bodies.size();
  if (n > 1)
    for (std::size_t b = 0; b < n; ++b)
      s << ", $e using 1:" << b + 3 << " with lines lw 1.5 lc rgb '" << colour(b) << "' title "
        << gnuplotQuote(b < body_names.size() ? body_names[b] : "body " + std::to_string(b));
  s << "\n";
  runGnuplot(s.str());
}

void plotTiming(const std::vector<FrameRecord>& frames, const std::string& png_path,
                const std::string& title) {
  std::ostringstream s;
  s << std::setprecision(10) << "$t << EOD\n";
  int rows = 0;
  for (const auto& f : frames)
    if (f.frame > 0)
      s << f.frame << ' ' << 1e3 * f.wall_time_s << ' ' << f.substeps << '\n', ++rows;
  if (rows == 0) throw std::runtime_error("timing plot: no stepped frames");
  s << "EOD\n"
    << "set terminal pngcairo size 1000,600 enhanced font 'DejaVu Sans,11'\n"
    << "set output " << gnuplotQuote(png_path) << "\n"
    << "set title " << gnuplotQuote(title + ": wall time per frame") << " noenhanced\n"
    << "set xlabel 'frame'\nset ylabel 'wall time [ms]'\nset y2label 'substeps'\nset y2tics\n"
    << "set ytics nomirror\nset yrange [0:*]\nset y2range [0:*]\nset grid\n"
    << "set key top right box opaque\nset style fill solid 0.5\n"
    << "plot $t using 1:2 with boxes lc rgb '#4a7bd0' title 'wall time', "
    << "$t using 1:3 axes x1y2 with linespoints pt 7 ps 0.5 lw 2 lc rgb '#d0574a' "
       "title 'substeps'\n";
  runGnuplot(s.str());
}

}  // namespace chs
