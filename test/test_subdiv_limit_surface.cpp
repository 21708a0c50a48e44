// Catmull-Clark limit surface (OpenSubdiv Bfr) for the Kirchhoff-Love shell, Han section 5.4:
// basis weights and derivatives over the original control points, boundaries, curvature,
// behaviour next to extraordinary vertices, tessellation, bad input and quad conversion.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/mesh/grid_generators.h"
#include "cloth_hair_sim/core/subdiv/first_order_stencils.h"
#include "cloth_hair_sim/core/subdiv/limit_surface.h"
#include "cloth_hair_sim/core/subdiv/quad_conversion.h"

namespace chs {
namespace {

using V3 = Eigen::Vector3d;

// 3-point Gauss-Legendre rule on [0, 1].
const std::array<double, 3> kGauss = {0.5 - 0.5 * std::sqrt(0.6), 0.5, 0.5 + 0.5 * std::sqrt(0.6)};
const std::array<double, 3> kGaussWeight = {5.0 / 18.0, 8.0 / 18.0, 5.0 / 18.0};

// Position and parametric derivatives of the limit surface at one stencil.
struct Jet {
  V3 x, xu, xv, xuu, xuv, xvv;
};

Jet jet(const SurfaceStencil& s, const std::vector<V3>& x) {
  return {s.combine(s.w, x),   s.combine(s.du, x),  s.combine(s.dv, x),
          s.combine(s.duu, x), s.combine(s.duv, x), s.combine(s.dvv, x)};
}

V3 unitNormal(const Jet& j) {
  return j.xu.cross(j.xv).normalized();
}

double angle(const V3& a, const V3& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

// Mean curvature H (positive where the surface bends away from its normal) and Gaussian
// curvature K from the first and second fundamental forms.
struct Curvatures {
  double H, K;
};

Curvatures curvatures(const Jet& j) {
  const V3 n = unitNormal(j);
  const double E = j.xu.dot(j.xu), F = j.xu.dot(j.xv), G = j.xv.dot(j.xv);
  const double e = j.xuu.dot(n), f = j.xuv.dot(n), g = j.xvv.dot(n);
  const double det = E * G - F * F;
  return {-(e * G - 2.0 * f * F + g * E) / (2.0 * det), (e * g - f * f) / det};
}

// Surface of the cube [-1, 1]^3, m x m quads a side, counter-clockwise seen from outside.
// Its 8 corners have valence 3. On every side, quad 0 has a cube corner as its corner 0.
QuadMesh boxMesh(int m) {
  QuadMesh mesh;
  std::map<std::array<int, 3>, int> id;
  const auto vertex = [&](const std::array<int, 3>& g) {
    const auto [it, is_new] = id.emplace(g, mesh.numVertices());
    if (is_new) mesh.vertices.push_back(V3(g[0], g[1], g[2]) * (2.0 / m) - V3::Ones());
    return it->second;
  };
  for (int a = 0; a < 3; ++a)
    for (int side = 0; side < 2; ++side) {
      const int b = (a + 1) % 3, c = (a + 2) % 3;  // e_b x e_c = e_a
      for (int i = 0; i < m; ++i)
        for (int j = 0; j < m; ++j) {
          const auto g = [&](int di, int dj) {
            std::array<int, 3> p{};
            p[a] = side * m;
            p[b] = i + di;
            p[c] = j + dj;
            return vertex(p);
          };
          std::array<int, 4> q = {g(0, 0), g(1, 0), g(1, 1), g(0, 1)};
          if (side == 0) std::swap(q[1], q[3]);
          mesh.quads.push_back(q);
        }
    }
  return mesh;
}

// Sectors of m x m rhombi (72 degrees each) around a centre vertex, lifted onto a curved
// surface so that bending is not trivial: 5 sectors close the fan (interior valence 5), 3 leave
// it open (boundary vertex of valence 3). Quad k m^2 has the centre as corner 0.
QuadMesh sectorMesh(int sectors, int m) {
  QuadMesh mesh;
  std::map<std::array<int, 3>, int> id;
  const auto vertex = [&](int k, int i, int j) {
    // Points on a sector's rays belong to two sectors: name them by ray.
    std::array<int, 3> key = {k, i, j};
    if (i == 0 && j == 0) key = {-1, 0, 0};
    if (i == 0 && j > 0) key = {(k + 1) % 5, j, 0};
    const auto [it, is_new] = id.emplace(key, mesh.numVertices());
    if (is_new) {
      const double t0 = 2.0 * M_PI * k / 5.0, t1 = 2.0 * M_PI * (k + 1) / 5.0;
      const double x = (i * std::cos(t0) + j * std::cos(t1)) / m;
      const double y = (i * std::sin(t0) + j * std::sin(t1)) / m;
      mesh.vertices.push_back(V3(x, y, 0.3 * x * x - 0.2 * y * y + 0.1 * x * y));
    }
    return it->second;
  };
  for (int k = 0; k < sectors; ++k)
    for (int i = 0; i < m; ++i)
      for (int j = 0; j < m; ++j)
        mesh.quads.push_back(
            {vertex(k, i, j), vertex(k, i + 1, j), vertex(k, i + 1, j + 1), vertex(k, i, j + 1)});
  return mesh;
}

// Open cylinder of radius r about z: n quads round, rows along z, square-ish quads,
// counter-clockwise seen from outside. Vertex (i, j) = j n + i.
QuadMesh cylinderMesh(double r, int n, int rows) {
  QuadMesh mesh;
  const double dz = 2.0 * M_PI * r / n;
  for (int j = 0; j <= rows; ++j)
    for (int i = 0; i < n; ++i) {
      const double t = 2.0 * M_PI * i / n;
      mesh.vertices.push_back(V3(r * std::cos(t), r * std::sin(t), j * dz));
    }
  for (int j = 0; j < rows; ++j)
    for (int i = 0; i < n; ++i)
      mesh.quads.push_back(
          {j * n + i, j * n + (i + 1) % n, (j + 1) * n + (i + 1) % n, (j + 1) * n + i});
  return mesh;
}

// Parameters of the point a fraction t along edge k (corner k -> corner k + 1) of a quad.
std::array<double, 2> edgePoint(int k, double t) {
  switch (k) {
    case 0:
      return {t, 0.0};
    case 1:
      return {1.0, t};
    case 2:
      return {1.0 - t, 1.0};
    default:
      return {0.0, 1.0 - t};
  }
}

// The quad across edge k of quad f and that edge's index in it (it runs the edge backwards).
std::pair<int, int> across(const QuadMesh& mesh, int f, int k) {
  const int a = mesh.quads[f][k], b = mesh.quads[f][(k + 1) % 4];
  for (int g = 0; g < mesh.numQuads(); ++g)
    for (int l = 0; l < 4; ++l)
      if (mesh.quads[g][l] == b && mesh.quads[g][(l + 1) % 4] == a) return {g, l};
  return {-1, -1};
}

// Largest angle between the unit normals of the two faces along edge k of quad f, sampled
// at `samples` points t in (t0, t1) measured from corner k.
double normalJump(const LimitSurface& s, const QuadMesh& mesh, int f, int k, double t0, double t1,
                  int samples) {
  const auto [g, l] = across(mesh, f, k);
  EXPECT_GE(g, 0);
  double worst = 0.0;
  for (int i = 0; i < samples; ++i) {
    const double t = t0 + (t1 - t0) * (i + 0.5) / samples;
    const auto a = edgePoint(k, t), b = edgePoint(l, 1.0 - t);
    const Jet ja = jet(s.stencil(f, a[0], a[1]), mesh.vertices);
    const Jet jb = jet(s.stencil(g, b[0], b[1]), mesh.vertices);
    EXPECT_LT((ja.x - jb.x).norm(), 1e-12) << "surface gap at t = " << t;
    worst = std::max(worst, angle(unitNormal(ja), unitNormal(jb)));
  }
  return worst;
}

// Largest |sum of weights - 1| and |sum of derivative weights| over a 5 x 5 grid of each face.
std::pair<double, double> unityDefects(const LimitSurface& s) {
  double w_err = 0.0, d_err = 0.0;
  for (int f = 0; f < s.numFaces(); ++f)
    for (int i = 0; i <= 4; ++i)
      for (int j = 0; j <= 4; ++j) {
        const SurfaceStencil st = s.stencil(f, 0.25 * i, 0.25 * j);
        double sum[6] = {};
        for (int k = 0; k < st.size(); ++k) {
          sum[0] += st.w[k];
          sum[1] += st.du[k];
          sum[2] += st.dv[k];
          sum[3] += st.duu[k];
          sum[4] += st.duv[k];
          sum[5] += st.dvv[k];
        }
        w_err = std::max(w_err, std::abs(sum[0] - 1.0));
        for (int d = 1; d < 6; ++d) d_err = std::max(d_err, std::abs(sum[d]));
      }
  return {w_err, d_err};
}

TEST(LimitSurface, PartitionOfUnity) {
  const double tol_w = 1e-13, tol_d = 1e-11;
  const std::vector<std::pair<const char*, QuadMesh>> meshes = {
      {"open 6x6 grid (regular + boundary)", makeRectangleMesh(6, 6, 6, 6)},
      {"cube 2x2 a side (valence 3)", boxMesh(2)},
      {"five sectors (valence 5)", sectorMesh(5, 2)},
      {"three sectors (boundary valence 3)", sectorMesh(3, 2)}};
  for (const auto& [name, mesh] : meshes) {
    const LimitSurface s(mesh);
    const auto [w_err, d_err] = unityDefects(s);
    std::printf(
        "[figure] partition of unity, %s: max |sum w - 1| = %.2e, max |sum dw| = %.2e "
        "(tol %.0e, %.0e)\n",
        name, w_err, d_err, tol_w, tol_d);
    EXPECT_LT(w_err, tol_w) << name;
    EXPECT_LT(d_err, tol_d) << name;
  }
}

// vertexStencils: a control vertex's limit point is the same from every face around it (the
// surface is continuous), on a bent net with boundary and extraordinary vertices; a control net
// scaled by s scales the distances between those points by s (what simulate's stretch reads).
TEST(LimitSurface, VertexStencilsAgreeOverTheFacesAroundAVertex) {
  static constexpr double kCornerUV[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  for (const QuadMesh& mesh : {makeRectangleMesh(0.3, 0.2, 6, 4), sectorMesh(5, 2), boxMesh(2)}) {
    const LimitSurface s(mesh);
    const std::vector<SurfaceStencil> at = vertexStencils(mesh, s);
    ASSERT_EQ(at.size(), mesh.vertices.size());
    std::vector<V3> x = mesh.vertices;
    for (V3& p : x) p += V3(0.1 * p.y() * p.y(), 0.2 * std::sin(3.0 * p.x()), 0.3 * p.x() * p.y());
    const std::vector<V3> points = evaluate(at, x);
    double largest = 0.0;
    for (int f = 0; f < mesh.numQuads(); ++f)
      for (int k = 0; k < 4; ++k)
        largest = std::max(largest, (s.stencil(f, kCornerUV[k][0], kCornerUV[k][1]).position(x) -
                                     points[mesh.quads[f][k]])
                                        .norm());
    std::vector<V3> scaled = x;
    for (V3& p : scaled) p *= 1.7;
    const std::vector<V3> far = evaluate(at, scaled);
    double ratio_error = 0.0;
    for (const auto& q : mesh.quads)
      for (int k = 0; k < 4; ++k) {
        const int a = q[k], b = q[(k + 1) % 4];
        ratio_error = std::max(
            ratio_error, std::abs((far[a] - far[b]).norm() / (points[a] - points[b]).norm() - 1.7));
      }
    std::printf(
        "[figure] vertex stencils, %d vertices: largest disagreement between faces %.2e m; "
        "scaled net's distance ratio off by %.2e\n",
        static_cast<int>(mesh.vertices.size()), largest, ratio_error);
    EXPECT_LT(largest, 1e-12);
    EXPECT_LT(ratio_error, 1e-12);
  }
}

// The contact particles' flat stencils give the same positions and tangents as the full ones,
// at regular and extraordinary faces, over a bent control net.
TEST(LimitSurface, FirstOrderStencilsMatchTheFullStencils) {
  const QuadMesh mesh = sectorMesh(5, 2);
  const LimitSurface s(mesh);
  std::vector<SurfaceStencil> full;
  for (int f = 0; f < s.numFaces(); ++f)
    for (double u : {0.1, 0.5, 0.9}) full.push_back(s.stencil(f, u, 1.0 - u));
  const FirstOrderStencils flat(full);
  ASSERT_EQ(flat.size(), static_cast<int>(full.size()));
  std::vector<V3> x = mesh.vertices;
  for (V3& p : x) p.z() = 0.3 * p.x() * p.x() - 0.2 * p.y();
  double largest = 0.0;
  for (int i = 0; i < flat.size(); ++i) {
    V3 a1, a2;
    flat.tangents(i, x, a1, a2);
    largest = std::max({largest, (flat.position(i, x) - full[i].position(x)).norm(),
                        (a1 - full[i].combine(full[i].du, x)).norm(),
                        (a2 - full[i].combine(full[i].dv, x)).norm()});
  }
  std::printf("[figure] first-order stencils against the full ones: largest difference %.1e\n",
              largest);
  EXPECT_LT(largest, 1e-14);
}

// Uniform cubic B-spline basis on [0, 1] and its first two derivatives.
std::array<double, 4> bspline(double t) {
  const double s = 1.0 - t;
  return {s * s * s / 6.0, (3 * t * t * t - 6 * t * t + 4) / 6.0,
          (-3 * t * t * t + 3 * t * t + 3 * t + 1) / 6.0, t * t * t / 6.0};
}
std::array<double, 4> bsplineD1(double t) {
  const double s = 1.0 - t;
  return {-s * s / 2.0, (3 * t * t - 4 * t) / 2.0, (-3 * t * t + 2 * t + 1) / 2.0, t * t / 2.0};
}
std::array<double, 4> bsplineD2(double t) {
  return {1.0 - t, 3 * t - 2, -3 * t + 1, t};
}

TEST(LimitSurface, FlatGridIsTheUniformBicubicBSplineAndReproducesThePlane) {
  const int n = 6;
  const QuadMesh mesh =
      makeRectangleMesh(6.0, 6.0, n, n, {3.0, 3.0, 0.0});  // vertex (i,j) at (i,j)
  const LimitSurface s(mesh);
  EXPECT_EQ(s.numFaces(), n * n);
  EXPECT_EQ(s.numControlPoints(), (n + 1) * (n + 1));

  // Interior face (2, 2): weights of control point (2 + a - 1, 2 + b - 1) are B_a(u) B_b(v).
  const int fi = 2, fj = 2, face = fj * n + fi;
  EXPECT_TRUE(s.isRegular(face));
  double basis_err = 0.0;
  for (double u : {0.0, 0.13, 0.5, 0.77, 1.0})
    for (double v : {0.0, 0.31, 0.62, 1.0}) {
      const SurfaceStencil st = s.stencil(face, u, v);
      const auto bu = bspline(u), bv = bspline(v), du = bsplineD1(u), dv = bsplineD1(v);
      const auto duu = bsplineD2(u), dvv = bsplineD2(v);
      std::map<int, std::array<double, 6>> expected;
      for (int a = 0; a < 4; ++a)
        for (int b = 0; b < 4; ++b)
          expected[(fj + b - 1) * (n + 1) + fi + a - 1] = {bu[a] * bv[b], du[a] * bv[b],
                                                           bu[a] * dv[b], duu[a] * bv[b],
                                                           du[a] * dv[b], bu[a] * dvv[b]};
      EXPECT_EQ(st.size(), 16);
      for (int k = 0; k < st.size(); ++k) {
        ASSERT_TRUE(expected.count(st.points[k])) << "unexpected control point " << st.points[k];
        const auto& e = expected[st.points[k]];
        const double got[6] = {st.w[k], st.du[k], st.dv[k], st.duu[k], st.duv[k], st.dvv[k]};
        for (int d = 0; d < 6; ++d) basis_err = std::max(basis_err, std::abs(got[d] - e[d]));
      }
    }
  const double tol_basis = 1e-13;
  std::printf(
      "[figure] interior face vs closed-form bicubic B-spline basis (w and all "
      "derivatives): max error %.2e (tol %.0e)\n",
      basis_err, tol_basis);
  EXPECT_LT(basis_err, tol_basis);

  // Linear precision on every face, boundary faces included (EDGE_AND_CORNER extrapolates the
  // phantom points linearly): x(u, v) = corner 0 + (u, v), x_u = e_x, x_v = e_y.
  double plane_err = 0.0;
  for (int f = 0; f < s.numFaces(); ++f) {
    const V3 x0 = mesh.vertices[mesh.quads[f][0]];
    for (double u : {0.0, 0.3, 0.9})
      for (double v : {0.0, 0.45, 1.0}) {
        const Jet j = jet(s.stencil(f, u, v), mesh.vertices);
        plane_err =
            std::max({plane_err, (j.x - (x0 + V3(u, v, 0))).norm(), (j.xu - V3::UnitX()).norm(),
                      (j.xv - V3::UnitY()).norm(), j.xuu.norm(), j.xuv.norm(), j.xvv.norm()});
      }
  }
  const double tol_plane = 1e-13;
  std::printf(
      "[figure] flat grid: max deviation from the plane x = x0 + (u, v) and its "
      "derivatives over all faces: %.2e (tol %.0e)\n",
      plane_err, tol_plane);
  EXPECT_LT(plane_err, tol_plane);
}

TEST(LimitSurface, ParameterConventionAndOrientation) {
  // u along corner 0 -> 1, v along corner 0 -> 3, x_u x x_v along the quad's CCW normal, on a
  // closed cube whose quads face outwards (every face touches an extraordinary vertex).
  const QuadMesh mesh = boxMesh(1);
  const LimitSurface s(mesh);
  for (int f = 0; f < mesh.numQuads(); ++f) {
    const auto& c = mesh.quads[f];
    const auto& p = mesh.vertices;
    const Jet j = jet(s.stencil(f, 0.5, 0.5), p);
    const V3 quad_normal = (p[c[2]] - p[c[0]]).cross(p[c[3]] - p[c[1]]).normalized();
    EXPECT_GT(unitNormal(j).dot(quad_normal), 0.99) << "face " << f;
    EXPECT_GT(j.xu.normalized().dot((p[c[1]] - p[c[0]]).normalized()), 0.99) << "face " << f;
    EXPECT_GT(j.xv.normalized().dot((p[c[3]] - p[c[0]]).normalized()), 0.99) << "face " << f;
    // Each corner of the parameter square is the limit point of the matching control corner,
    // which on this symmetric cube lies on the ray from the centre through it.
    for (int k = 0; k < 4; ++k) {
      const auto uv = edgePoint(k, 0.0);
      const V3 x = s.stencil(f, uv[0], uv[1]).position(p);
      EXPECT_GT(x.normalized().dot(p[c[k]].normalized()), 1.0 - 1e-12) << f << " " << k;
    }
  }
  std::printf(
      "[figure] cube: x_u x x_v agrees with the CCW quad normal on all %d faces "
      "(tol: cosine > 0.99)\n",
      mesh.numQuads());
}

// Largest error of the stencil's derivatives against central differences of its positions,
// each relative to the largest norm of that derivative order over the sampled points.
std::array<double, 2> finiteDifferenceErrors(const LimitSurface& s, const QuadMesh& mesh, int f,
                                             const std::vector<double>& params) {
  const auto pos = [&](double u, double v) { return s.stencil(f, u, v).position(mesh.vertices); };
  const double h1 = 1e-5, h2 = 1e-4;
  double e1 = 0, e2 = 0, n1 = 0, n2 = 0;
  for (double u : params)
    for (double v : params) {
      const Jet j = jet(s.stencil(f, u, v), mesh.vertices);
      const V3 xu = (pos(u + h1, v) - pos(u - h1, v)) / (2 * h1);
      const V3 xv = (pos(u, v + h1) - pos(u, v - h1)) / (2 * h1);
      const V3 xuu = (pos(u + h2, v) - 2 * j.x + pos(u - h2, v)) / (h2 * h2);
      const V3 xvv = (pos(u, v + h2) - 2 * j.x + pos(u, v - h2)) / (h2 * h2);
      const V3 xuv =
          (pos(u + h2, v + h2) - pos(u + h2, v - h2) - pos(u - h2, v + h2) + pos(u - h2, v - h2)) /
          (4 * h2 * h2);
      e1 = std::max({e1, (xu - j.xu).norm(), (xv - j.xv).norm()});
      e2 = std::max({e2, (xuu - j.xuu).norm(), (xuv - j.xuv).norm(), (xvv - j.xvv).norm()});
      n1 = std::max({n1, j.xu.norm(), j.xv.norm()});
      n2 = std::max({n2, j.xuu.norm(), j.xuv.norm(), j.xvv.norm()});
    }
  return {e1 / n1, e2 / n2};
}

TEST(LimitSurface, DerivativesMatchFiniteDifferences) {
  // Points off the dyadic knots of the adaptive refinement (so that each difference stays on
  // one polynomial piece) and outside the corner square of side 2^-4 at the extraordinary
  // vertex, where the default level evaluates exactly.
  const std::vector<double> params = {0.15, 0.3, 0.7, 0.85};
  const double tol1 = 1e-8, tol2 = 1e-6;

  QuadMesh bumpy = makeRectangleMesh(1.0, 1.0, 6, 6);
  for (auto& x : bumpy.vertices) x.z() = 0.2 * std::sin(5 * x.x()) * std::cos(3 * x.y());
  const QuadMesh cube = boxMesh(2), star = sectorMesh(5, 2), wedge = sectorMesh(3, 2);
  struct Case {
    const char* name;
    const QuadMesh* mesh;
    int face;
  };
  for (const Case& c : {Case{"regular face of a curved grid", &bumpy, 14},
                        Case{"cube face at a valence-3 vertex", &cube, 0},
                        Case{"face at a valence-5 vertex", &star, 0},
                        Case{"face at a boundary vertex of valence 3", &wedge, 0}}) {
    const LimitSurface s(*c.mesh);
    const auto [e1, e2] = finiteDifferenceErrors(s, *c.mesh, c.face, params);
    std::printf(
        "[figure] %s (regular patch: %s): relative error vs central differences "
        "Du,Dv %.2e (tol %.0e), Duu,Duv,Dvv %.2e (tol %.0e)\n",
        c.name, s.isRegular(c.face) ? "yes" : "no", e1, tol1, e2, tol2);
    EXPECT_LT(e1, tol1) << c.name;
    EXPECT_LT(e2, tol2) << c.name;
  }
}

TEST(LimitSurface, NormalContinuityAcrossEdges) {
  // Edge 0 of face 0 starts at the extraordinary vertex. Outside the Gregory corner square
  // (t > 2^-level) both sides are exact B-spline patches; inside it both are Gregory patches,
  // whose derivatives are approximate but which still meet with a common tangent plane.
  const QuadMesh cube = boxMesh(2), star = sectorMesh(5, 2);
  const double gregory = std::ldexp(1.0, -LimitSurface::kDefaultExtraordinaryLevel);
  const double tol_exact = 1e-12, tol_gregory = 1e-10;
  for (const auto& [name, mesh] : {std::pair<const char*, const QuadMesh*>{"valence 3", &cube},
                                   std::pair<const char*, const QuadMesh*>{"valence 5", &star}}) {
    const LimitSurface s(*mesh);
    const double outside = normalJump(s, *mesh, 0, 0, gregory, 1.0, 200);
    const double inside = normalJump(s, *mesh, 0, 0, 0.0, gregory, 50);
    std::printf(
        "[figure] normal jump across an edge from a %s vertex: %.2e rad for t in "
        "(2^-%d, 1) (tol %.0e), %.2e rad inside the Gregory square (tol %.0e)\n",
        name, outside, LimitSurface::kDefaultExtraordinaryLevel, tol_exact, inside, tol_gregory);
    EXPECT_LT(outside, tol_exact) << name;
    EXPECT_LT(inside, tol_gregory) << name;
  }
}

TEST(LimitSurface, OpenBoundaryInterpolatesCornersAndIsTheBSplineOfBoundaryPoints) {
  const int nx = 5, ny = 4;
  QuadMesh mesh = makeRectangleMesh(5.0, 4.0, nx, ny);
  for (auto& x : mesh.vertices) x.z() = 0.3 * std::sin(2.0 * x.x() + x.y()) + 0.1 * x.x() * x.y();
  const LimitSurface s(mesh);
  const auto& p = mesh.vertices;

  // Corners of the sheet: corner 0 of quad 0, corner 1 of quad nx-1, and so on.
  const std::array<std::array<int, 2>, 4> sheet_corners = {
      {{0, 0}, {nx - 1, 1}, {nx * ny - 1, 2}, {nx * (ny - 1), 3}}};
  double corner_err = 0.0;
  for (const auto& [f, k] : sheet_corners) {
    const auto uv = edgePoint(k, 0.0);
    corner_err =
        std::max(corner_err, (s.stencil(f, uv[0], uv[1]).position(p) - p[mesh.quads[f][k]]).norm());
  }

  // Bottom edge (v = 0 of quads 0..nx-1): cubic B-spline of the boundary points P_0..P_nx with
  // the phantom ends 2 P_0 - P_1 and 2 P_nx - P_nx-1 of EDGE_AND_CORNER.
  std::vector<V3> b(nx + 3);
  for (int i = 0; i <= nx; ++i) b[i + 1] = p[i];
  b[0] = 2 * p[0] - p[1];
  b[nx + 2] = 2 * p[nx] - p[nx - 1];
  double curve_err = 0.0, interior_weight = 0.0;
  for (int f = 0; f < nx; ++f)
    for (double t : {0.0, 0.2, 0.5, 0.9, 1.0}) {
      const SurfaceStencil st = s.stencil(f, t, 0.0);
      const auto B = bspline(t);
      V3 expected = V3::Zero();
      for (int a = 0; a < 4; ++a) expected += B[a] * b[f + a];
      curve_err = std::max(curve_err, (st.position(p) - expected).norm());
      for (int k = 0; k < st.size(); ++k)
        if (st.points[k] > nx) interior_weight = std::max(interior_weight, std::abs(st.w[k]));
    }
  const double tol = 1e-13;
  std::printf(
      "[figure] open boundary: corner interpolation error %.2e, boundary curve vs cubic "
      "B-spline of boundary points %.2e, largest weight of an off-boundary point %.2e "
      "(tol %.0e each)\n",
      corner_err, curve_err, interior_weight, tol);
  EXPECT_LT(corner_err, tol);
  EXPECT_LT(curve_err, tol);
  EXPECT_LT(interior_weight, tol);
}

TEST(LimitSurface, CylinderMeanCurvature) {
  // Mean curvature 1/(2R) at Gauss points of the middle row, away from the open ends. The limit
  // of an N-gon control ring is slightly smaller than R (by ~ (2 pi / N)^2 / 6), so the error
  // must fall like N^-2.
  const double R = 0.7;
  double previous = 1.0;
  for (int n : {16, 32, 64}) {
    const int rows = 8;
    const QuadMesh mesh = cylinderMesh(R, n, rows);
    const LimitSurface s(mesh);
    double worst = 0.0, gauss_curv = 0.0;
    for (int i = 0; i < n; ++i)
      for (double u : kGauss)
        for (double v : kGauss) {
          const Jet j = jet(s.stencil((rows / 2) * n + i, u, v), mesh.vertices);
          const Curvatures c = curvatures(j);
          worst = std::max(worst, std::abs(c.H * 2.0 * R - 1.0));
          gauss_curv = std::max(gauss_curv, std::abs(c.K) * R * R);
        }
    const double tol = std::pow(2.0 * M_PI / n, 2) / 3.0;  // twice the ring shrinkage
    std::printf(
        "[figure] cylinder R = %.1f, %d segments: max |H 2R - 1| = %.2e (tol %.1e), "
        "max |K| R^2 = %.2e\n",
        R, n, worst, tol, gauss_curv);
    EXPECT_LT(worst, tol) << n;
    EXPECT_LT(worst, previous) << n;
    EXPECT_LT(gauss_curv, tol) << n;
    previous = worst;
  }
}

TEST(LimitSurface, TessellationIsSharedWatertightAndOriented) {
  for (int m : {1, 2}) {
    const QuadMesh mesh = boxMesh(m);
    const LimitSurface s(mesh);
    const int n = 4;
    const LimitTessellation t = s.tessellate(n);
    const int V = mesh.numVertices(), F = mesh.numQuads(), E = 2 * F;  // closed quad mesh
    EXPECT_EQ(static_cast<int>(t.samples.size()), V + E * (n - 1) + F * (n - 1) * (n - 1));
    EXPECT_EQ(static_cast<int>(t.triangles.size()), 2 * n * n * F);

    // Watertight and consistently oriented: every directed edge once, its reverse once.
    std::map<std::pair<int, int>, int> directed;
    for (const auto& tri : t.triangles)
      for (int k = 0; k < 3; ++k) ++directed[{tri[k], tri[(k + 1) % 3]}];
    int bad = 0;
    for (const auto& [e, count] : directed) {
      const auto rev = directed.find({e.second, e.first});
      bad += count != 1 || rev == directed.end() || rev->second != 1;
    }
    EXPECT_EQ(bad, 0);

    // Each face's grid points coincide with the sample the tessellation stored for them (which
    // may have been created by a neighbouring face): shared samples are the same surface point.
    std::vector<SurfaceStencil> stencils;
    for (const SurfacePoint& p : t.samples) stencils.push_back(s.stencil(p));
    const std::vector<V3> x = evaluate(stencils, mesh.vertices);
    double mismatch = 0.0;
    for (int f = 0; f < F; ++f)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          const auto& lower = t.triangles[2 * n * n * f + 2 * (j * n + i)];
          const auto& upper = t.triangles[2 * n * n * f + 2 * (j * n + i) + 1];
          const std::array<std::pair<int, std::array<int, 2>>, 4> cell = {
              {{lower[0], {i, j}},
               {lower[1], {i + 1, j}},
               {lower[2], {i + 1, j + 1}},
               {upper[2], {i, j + 1}}}};
          for (const auto& [sample, ij] : cell) {
            const V3 here =
                s.stencil(f, double(ij[0]) / n, double(ij[1]) / n).position(mesh.vertices);
            mismatch = std::max(mismatch, (here - x[sample]).norm());
          }
        }
    EXPECT_LT(mismatch, 1e-13);

    // Outward orientation: the enclosed volume (divergence theorem) is positive and below the
    // control cube's 8.
    double volume = 0.0;
    for (const auto& tri : t.triangles) volume += x[tri[0]].dot(x[tri[1]].cross(x[tri[2]])) / 6.0;
    std::printf(
        "[figure] tessellated cube (%d quads a side, %d segments): %zu samples, %zu "
        "triangles, %d unmatched edges, shared-sample mismatch %.2e (tol 1e-13), "
        "volume %.4f (0 < V < 8)\n",
        m, n, t.samples.size(), t.triangles.size(), bad, mismatch, volume);
    EXPECT_GT(volume, 0.0);
    EXPECT_LT(volume, 8.0);
  }

  // Open sheet: boundary edges appear once, and every triangle faces +z like the quads.
  const QuadMesh sheet = makeRectangleMesh(3.0, 2.0, 3, 2);
  const LimitSurface s(sheet);
  const LimitTessellation t = s.tessellate(3);
  double min_nz = 1.0;
  for (const auto& tri : t.triangles) {
    const V3 a = s.stencil(t.samples[tri[0]]).position(sheet.vertices);
    const V3 b = s.stencil(t.samples[tri[1]]).position(sheet.vertices);
    const V3 c = s.stencil(t.samples[tri[2]]).position(sheet.vertices);
    min_nz = std::min(min_nz, (b - a).cross(c - a).normalized().z());
  }
  std::printf(
      "[figure] open sheet: %zu samples (expected %d), min triangle normal z %.3f "
      "(tol > 0.999)\n",
      t.samples.size(), (3 * 3 + 1) * (2 * 3 + 1), min_nz);
  EXPECT_EQ(static_cast<int>(t.samples.size()), (3 * 3 + 1) * (2 * 3 + 1));
  EXPECT_GT(min_nz, 0.999);
}

TEST(LimitSurface, WrappedPatchesListEachControlPointOnce) {
  // A 3 x 3 torus: every vertex has valence 4, but each 4x4 patch ring wraps onto itself.
  QuadMesh torus;
  const int n = 3;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double a = 2 * M_PI * i / n, b = 2 * M_PI * j / n;
      torus.vertices.push_back(
          V3((2 + std::cos(b)) * std::cos(a), (2 + std::cos(b)) * std::sin(a), std::sin(b)));
    }
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      torus.quads.push_back(
          {j * n + i, j * n + (i + 1) % n, ((j + 1) % n) * n + (i + 1) % n, ((j + 1) % n) * n + i});
  const LimitSurface s(torus);
  int max_points = 0;
  for (int f = 0; f < s.numFaces(); ++f) {
    const SurfaceStencil st = s.stencil(f, 0.4, 0.6);
    EXPECT_EQ(std::set<int>(st.points.begin(), st.points.end()).size(), st.points.size());
    max_points = std::max(max_points, st.size());
  }
  const auto [w_err, d_err] = unityDefects(s);
  std::printf(
      "[figure] 3x3 torus: at most %d distinct control points per stencil (<= 9), "
      "|sum w - 1| = %.2e, |sum dw| = %.2e (tol 1e-13, 1e-11)\n",
      max_points, w_err, d_err);
  EXPECT_LE(max_points, 9);
  EXPECT_LT(w_err, 1e-13);
  EXPECT_LT(d_err, 1e-11);
}

TEST(LimitSurface, ConcurrentStencilsMatchSerial) {
  const QuadMesh mesh = sectorMesh(5, 3);
  const LimitSurface s(mesh);
  const auto all = [&] {
    std::vector<SurfaceStencil> out;
    for (int f = 0; f < s.numFaces(); ++f)
      for (double u : kGauss)
        for (double v : kGauss) out.push_back(s.stencil(f, u, v));
    return out;
  };
  const std::vector<SurfaceStencil> serial = all();
  const int threads = 4;
  std::vector<std::vector<SurfaceStencil>> parallel(threads);
  std::vector<std::thread> pool;
  for (int t = 0; t < threads; ++t)
    pool.emplace_back([&, t] {
      for (int repeat = 0; repeat < 20; ++repeat) parallel[t] = all();
    });
  for (auto& th : pool) th.join();
  int differing = 0;
  for (const auto& p : parallel)
    for (size_t i = 0; i < serial.size(); ++i)
      differing += p[i].points != serial[i].points || p[i].w != serial[i].w ||
                   p[i].duu != serial[i].duu || p[i].duv != serial[i].duv;
  std::printf(
      "[figure] %d threads x 20 passes over %zu stencils: %d differ from the serial "
      "ones (tol 0, bitwise)\n",
      threads, serial.size(), differing);
  EXPECT_EQ(differing, 0);
}

// Integral of H^2 dA (the Willmore / bending energy density integral) over the given faces by
// the 3x3 Gauss rule, as the Kirchhoff-Love bending term sees it.
double bendingIntegral(const LimitSurface& s, const QuadMesh& mesh, const std::vector<int>& faces) {
  double sum = 0.0;
  for (int f : faces)
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) {
        const Jet j = jet(s.stencil(f, kGauss[a], kGauss[b]), mesh.vertices);
        sum += kGaussWeight[a] * kGaussWeight[b] * std::pow(curvatures(j).H, 2) *
               j.xu.cross(j.xv).norm();
      }
  return sum;
}

TEST(LimitSurface, ExtraordinaryLevelStudy) {
  // Why the default level is 4: the faces around an extraordinary vertex are exact B-spline
  // patches except the corner square [0, 2^-level]^2, a Gregory patch with approximate
  // derivatives. Compare stencils at the 3x3 Gauss points and at the 4-point rule's point
  // nearest the corner, and the bending integral, with level 10.
  const std::vector<double> probes = {0.5 - 0.5 * 0.8611363115940526, kGauss[0], kGauss[1],
                                      kGauss[2]};
  const QuadMesh cube = boxMesh(2), star = sectorMesh(5, 2), wedge = sectorMesh(3, 2);
  for (const auto& [name, mesh] :
       {std::pair<const char*, const QuadMesh*>{"valence 3", &cube},
        std::pair<const char*, const QuadMesh*>{"valence 5", &star},
        std::pair<const char*, const QuadMesh*>{"boundary valence 3", &wedge}}) {
    std::vector<int> ev_faces;  // faces with the extraordinary vertex as corner 0
    for (int f = 0; f < mesh->numQuads(); f += 4) ev_faces.push_back(f);
    const LimitSurface reference(*mesh, 10);
    const double ref_bending = bendingIntegral(reference, *mesh, ev_faces);
    double ref_scale = 0.0;
    for (int f : ev_faces)
      for (double u : probes)
        for (double v : probes)
          for (double d : reference.stencil(f, u, v).duu)
            ref_scale = std::max(ref_scale, std::abs(d));

    for (int level = 1; level <= 6; ++level) {
      const auto t0 = std::chrono::steady_clock::now();
      const LimitSurface s(*mesh, level);
      const auto t1 = std::chrono::steady_clock::now();
      double stencil_err = 0.0;
      for (int f : ev_faces)
        for (double u : probes)
          for (double v : probes) {
            const SurfaceStencil a = s.stencil(f, u, v), b = reference.stencil(f, u, v);
            EXPECT_EQ(a.points, b.points);
            for (int k = 0; k < a.size(); ++k)
              for (const auto& [x, y] :
                   {std::pair{a.du[k], b.du[k]}, std::pair{a.dv[k], b.dv[k]},
                    std::pair{a.duu[k], b.duu[k]}, std::pair{a.duv[k], b.duv[k]},
                    std::pair{a.dvv[k], b.dvv[k]}, std::pair{a.w[k], b.w[k]}})
                stencil_err = std::max(stencil_err, std::abs(x - y) / ref_scale);
          }
      const auto t2 = std::chrono::steady_clock::now();
      const double bending_err = std::abs(bendingIntegral(s, *mesh, ev_faces) / ref_bending - 1.0);
      const double jump = normalJump(s, *mesh, 0, 3, 0.0, 1.0, 400);  // edge 3 ends at the vertex
      // Inside the Gregory square: derivatives against differences of positions.
      const double square = std::ldexp(1.0, -level);
      const auto [fd1, fd2] = finiteDifferenceErrors(s, *mesh, 0, {0.35 * square, 0.6 * square});
      const double us_build = std::chrono::duration<double, std::micro>(t1 - t0).count();
      const double us_eval = std::chrono::duration<double, std::micro>(t2 - t1).count() /
                             (2.0 * probes.size() * probes.size() * ev_faces.size());
      std::printf(
          "[figure] %s, level %d: Gauss-point (3x3 and 4x4 corner) stencil error %.2e, 3x3-Gauss "
          "bending "
          "integral error %.2e, max normal jump along an edge %.2e rad; inside the Gregory "
          "square, Du/Dv vs differences %.1e, 2nd derivatives %.1e; build %.0f us "
          "(%d faces), %.1f us per stencil\n",
          name, level, stencil_err, bending_err, jump, fd1, fd2, us_build, mesh->numQuads(),
          us_eval);
      if (level >= LimitSurface::kDefaultExtraordinaryLevel) {
        // All probes lie outside the Gregory square: exact up to round-off.
        EXPECT_LT(stencil_err, 1e-12) << name << " level " << level;
        EXPECT_LT(bending_err, 1e-12) << name << " level " << level;
      }
    }
  }
}

TEST(LimitSurface, BadInputThrows) {
  const QuadMesh good = makeRectangleMesh(2, 2, 2, 2);
  const auto rejects = [](const QuadMesh& m, const std::string& fragment,
                          int level = LimitSurface::kDefaultExtraordinaryLevel) {
    try {
      const LimitSurface s(m, level);
      ADD_FAILURE() << "accepted, expected: " << fragment;
    } catch (const InputError& e) {
      std::printf("  rejected: %s\n", e.what());
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
  };
  rejects(QuadMesh{}, "empty");
  QuadMesh m = good;
  m.quads[1][2] = 9;
  rejects(m, "names vertex 9");
  m = good;
  m.quads[2][3] = m.quads[2][0];
  rejects(m, "repeats vertex");
  m = good;
  std::swap(m.quads[3][1], m.quads[3][3]);  // flipped quad
  rejects(m, "inconsistent orientation");
  m = good;  // a third quad on edge 4-5 (the middle of the bottom row)
  m.vertices.push_back({0.5, 0.0, 1.0});
  m.vertices.push_back({0.0, 0.0, 1.0});
  m.quads.push_back({5, 4, 10, 9});
  rejects(m, "more than two faces");
  m = good;  // bow tie: a separate quad touching vertex 8 only
  for (const V3& x : {V3(2, 2, 1), V3(2, 3, 1), V3(3, 2, 1)}) m.vertices.push_back(x);
  m.quads.push_back({8, 9, 11, 10});
  rejects(m, "non-manifold");
  m = good;
  m.vertices.push_back({5, 5, 5});
  rejects(m, "belongs to no face");
  rejects(good, "extraordinary_level", 0);

  const LimitSurface s(good);
  EXPECT_THROW(s.stencil(4, 0.5, 0.5), InputError);
  EXPECT_THROW(s.stencil(-1, 0.5, 0.5), InputError);
  EXPECT_THROW(s.stencil(0, 1.5, 0.5), InputError);
  EXPECT_THROW(s.stencil(0, 0.5, std::nan("")), InputError);
  EXPECT_THROW(s.tessellate(0), InputError);
  EXPECT_THROW(evaluate({s.stencil(0, 0.5, 0.5)}, {V3::Zero()}), InputError);
}

TEST(QuadConversion, TrianglesBecomeQuadsByOneCatmullClarkStep) {
  // Two triangles of the unit square: V' = V + E + F = 4 + 5 + 2, 3 quads per triangle.
  const PolygonMesh square = {{V3(0, 0, 0), V3(1, 0, 0), V3(1, 1, 0), V3(0, 1, 0)},
                              {{0, 1, 2}, {0, 2, 3}}};
  const QuadMesh q = toQuadControlMesh(square);
  EXPECT_EQ(q.numVertices(), 11);
  EXPECT_EQ(q.numQuads(), 6);
  double min_nz = 1.0;
  for (const auto& c : q.quads) {
    const auto& p = q.vertices;
    min_nz = std::min(min_nz, (p[c[2]] - p[c[0]]).cross(p[c[3]] - p[c[1]]).normalized().z());
  }
  EXPECT_GT(min_nz, 0.999);
  // Original vertices keep their indices: corners 1 and 3 (one face each) stay put, vertex 0
  // follows the boundary rule 3/4 P0 + 1/8 (P1 + P3); face points (centroids) come next.
  const auto& p0 = square.vertices;
  const double ordering_err =
      std::max({(q.vertices[1] - p0[1]).norm(), (q.vertices[3] - p0[3]).norm(),
                (q.vertices[0] - 0.125 * (p0[1] + p0[3])).norm(),
                (q.vertices[4] - (p0[0] + p0[1] + p0[2]) / 3.0).norm(),
                (q.vertices[5] - (p0[0] + p0[2] + p0[3]) / 3.0).norm()});
  EXPECT_LT(ordering_err, 1e-15);
  EXPECT_NO_THROW(LimitSurface{q});

  // Tetrahedron, faces outward: 4 + 6 + 4 = 14 vertices, 12 quads, closed and outward.
  const PolygonMesh tet = {{V3(1, 1, 1), V3(1, -1, -1), V3(-1, 1, -1), V3(-1, -1, 1)},
                           {{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 3, 2}}};
  const QuadMesh qt = toQuadControlMesh(tet);
  EXPECT_EQ(qt.numVertices(), 14);
  EXPECT_EQ(qt.numQuads(), 12);
  double min_outward = 1.0;
  for (const auto& c : qt.quads) {
    const auto& p = qt.vertices;
    const V3 centre = 0.25 * (p[c[0]] + p[c[1]] + p[c[2]] + p[c[3]]);
    min_outward = std::min(
        min_outward,
        (p[c[2]] - p[c[0]]).cross(p[c[3]] - p[c[1]]).normalized().dot(centre.normalized()));
  }
  EXPECT_GT(min_outward, 0.0);
  const LimitSurface tet_surface(qt);  // closed: each quad edge shared twice, else it throws
  EXPECT_EQ(tet_surface.tessellate(1).triangles.size(), 24u);

  // All quads: unchanged.
  const QuadMesh cube = boxMesh(2);
  PolygonMesh poly{cube.vertices, {}};
  for (const auto& c : cube.quads) poly.faces.push_back({c[0], c[1], c[2], c[3]});
  const QuadMesh same = toQuadControlMesh(poly);
  EXPECT_EQ(same.vertices, cube.vertices);
  EXPECT_EQ(same.quads, cube.quads);

  std::printf(
      "[figure] quad conversion: 2 triangles -> %d vertices, %d quads (expected 11, 6), "
      "min normal z %.3f (tol > 0.999), vertex-order error %.1e (tol 1e-15); tetrahedron "
      "-> %d vertices, %d quads (expected 14, 12), min outward cosine %.3f (tol > 0); "
      "all-quad cube unchanged\n",
      q.numVertices(), q.numQuads(), min_nz, ordering_err, qt.numVertices(), qt.numQuads(),
      min_outward);

  EXPECT_THROW(toQuadControlMesh({square.vertices, {{0, 1}}}), InputError);
  EXPECT_THROW(toQuadControlMesh({square.vertices, {{0, 1, 7}}}), InputError);
  EXPECT_THROW(toQuadControlMesh({}), InputError);
}

}  // namespace
}  // namespace chs
