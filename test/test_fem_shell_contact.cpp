// FEM shell with penalty contact (seed 000 sections 2.2.2 and 4.3): the overhanging beam against
// small-deflection theory, and Newton's quadratic convergence.
#include <array>
#include <cmath>
#include <cstdio>
#include <vector>

#include <gtest/gtest.h>

#include "cloth_hair_sim/core/fem_shell/fem_shell_solver.h"
#include "cloth_hair_sim/core/particle/particle_static_solver.h"

namespace chs {
namespace {

// L = 6 cm, a = 1.5 cm past the edge, EA = 2809 gf, EI = 0.386 gf cm^2, w = 0.0255 gf/cm,
// 24 elements; units gf and cm (g = 1).
constexpr double kL = 6.0, kA = 1.5, kEA = 2809.0, kEI = 0.386, kW = 0.0255;

DrapeProblem overhangingBeam(int n) {
  DrapeProblem p;
  for (int j = 0; j <= 1; ++j)
    for (int i = 0; i <= n; ++i) p.mesh.vertices.emplace_back(kL * i / n, j - 0.5, 0.0);
  for (int i = 0; i < n; ++i) p.mesh.quads.push_back({i, i + 1, n + 2 + i, n + 1 + i});
  const double h = std::sqrt(12.0 * kEI / kEA);  // width 1 cm: EA = E h, EI = E h^3 / 12
  p.material.young = kEA / h;
  p.material.poisson = 0.0;
  p.material.thickness = h;
  p.material.areal_density = kW;  // per cm^2 of a 1 cm wide strip
  p.gravity = Eigen::Vector3d(0, 0, -1);
  // Frictionless table top at z = 0 whose edge is a = 1.5 cm short of the tip, rounded with
  // 0.1 mm, a twenty-fifth of an element.
  p.colliders.push_back(std::make_shared<BoxSurface>(Eigen::Vector3d(-1, -2, -1),
                                                     Eigen::Vector3d(kL - kA, 2, 0), 0.01));
  // Nothing balances the small horizontal part of the edge reaction on a frictionless table
  // (benchmarks.md): hold one end in x and y, and the other root node in x.
  p.bc.fixed_components = {{0, 0}, {0, 1}, {n + 1, 0}};
  return p;
}

struct OverhangFigures {
  double p, dy, Rb, Rc, Rb_from_reactions;
};

// Small-deflection theory (derived in docs/VALIDATION.md).
const OverhangFigures kTheory = {
    std::sqrt(2.0) * kA, (std::sqrt(2.0) / 12.0 + 0.125) * kW* std::pow(kA, 4) / kEI,
    kW* std::sqrt(2.0) * kA / 4.0, kW*(kA + 0.75 * std::sqrt(2.0) * kA), 0.0};

struct OverhangErrors {
  double p, dy, Rb, Rc;  // relative to kTheory
};

OverhangErrors errorsOf(const OverhangFigures& f) {
  return {std::abs(f.p - kTheory.p) / kTheory.p, std::abs(f.dy - kTheory.dy) / kTheory.dy,
          std::abs(f.Rb - kTheory.Rb) / kTheory.Rb, std::abs(f.Rc - kTheory.Rc) / kTheory.Rc};
}

// Lift-off length p and reaction R_b from the shape of the free span B-C, which small-deflection
// theory gives exactly: g(s) = (R_b s^3/6 - w s^4/24)/EI, s = x - x_B (zero deflection, slope and
// moment at B). Fitting x_B and R_b to the nodal gaps resolves B inside an element, whereas the
// nodal reaction at the last contact node lumps R_b with the tributary weight of its elements.
OverhangFigures extract(const DrapeResult& r, int n) {
  const double le = kL / n, xc = kL - kA;
  // Nodes up to the edge (the one on it, if any): the free span's fit uses those before it.
  const int edge = static_cast<int>(std::floor(xc / le + 1e-9));
  auto gap = [&](int i) { return 0.5 * (r.positions[i].z() + r.positions[n + 1 + i].z()); };
  OverhangFigures f{};
  double best = HUGE_VAL;
  for (double xb = 0.5 * xc; xb < xc - le; xb += 1e-4) {
    // Linear least squares for R_b at this x_B over the nodes in (x_B, x_C).
    double sxx = 0, sxy = 0, sr = 0;
    std::vector<std::pair<double, double>> pts;
    for (int i = 0; i < edge; ++i) {
      const double x = r.positions[i].x(), s = x - xb;
      if (s <= 0) continue;
      const double basis = s * s * s / 6.0 / kEI, rest = -kW * s * s * s * s / 24.0 / kEI;
      pts.push_back({basis, gap(i) - rest});
      sxx += basis * basis;
      sxy += basis * (gap(i) - rest);
    }
    if (pts.size() < 3) continue;
    const double Rb = sxy / sxx;
    for (auto& [b, y] : pts) sr += (y - Rb * b) * (y - Rb * b);
    // Nodes before x_B must lie on the table.
    for (int i = 0; i < edge; ++i)
      if (r.positions[i].x() <= xb) sr += gap(i) * gap(i);
    if (sr < best) best = sr, f.Rb = Rb, f.p = xc - xb;
  }
  f.dy = -gap(n);
  // Reactions past the middle of the free span act at the edge (at its nodes, or at the element
  // edges that cross it, shared by their two nodes); those before it on the flat top.
  double flat = 0.0;
  const double middle = xc - 0.5 * f.p;
  for (const auto& c : r.reactions) {
    if (r.positions[c.vertex].x() > middle)
      f.Rc += c.force.z();
    else
      flat += c.force.z();
  }
  f.Rb_from_reactions = flat - kW * (xc - f.p);
  return f;
}

TEST(FemShellContact, OverhangingBeamMatchesSmallDeflectionTheory) {
  const int n = 24;
  const DrapeResult r = solveFemShell(overhangingBeam(n), FemShellSettings());
  ASSERT_TRUE(r.converged) << r.status;
  const OverhangFigures f = extract(r, n);
  const OverhangErrors e = errorsOf(f);
  const OverhangFigures& t = kTheory;
  std::printf("overhanging beam, %d elements (%d steps, %d iterations)\n", n, r.load_steps,
              r.iterations);
  std::printf("          p [cm]   dy [cm]   R_b [gf]  R_c [gf]\n");
  std::printf("theory    %.4f   %.5f   %.5f   %.5f\n", t.p, t.dy, t.Rb, t.Rc);
  std::printf("FEM       %.4f   %.5f   %.5f   %.5f\n", f.p, f.dy, f.Rb, f.Rc);
  std::printf("error %%   %.2f     %.2f      %.2f      %.2f\n", 100 * e.p, 100 * e.dy, 100 * e.Rb,
              100 * e.Rc);
  std::printf("R_b from the contact reactions (flat sum - w (L - a - p)): %.5f gf (%.2f %%)\n",
              f.Rb_from_reactions, 100 * std::abs(f.Rb_from_reactions - t.Rb) / t.Rb);
  EXPECT_LT(e.p, 0.03);
  EXPECT_LT(e.dy, 0.03);
  EXPECT_LT(e.Rb, 0.03);
  EXPECT_LT(e.Rc, 0.03);
}

// The table edge between two nodes: the element edges that cross it carry the edge reaction
// (ShellModel's edge contact). The figures must not depend on where the edge falls. In each set
// the first two meshes have a node on the edge, the other three put it at 0.75, 0.5 and 0.25 of
// an element. On ~100 elements each must match small-deflection theory, and the node-on-edge
// meshes, within 1 %; on ~50 elements the tip deflection misses that by up to 0.17 % when the
// edge is mid-element (the element across it cannot put the moment's kink inside itself).
void edgeBetweenNodes(const std::array<int, 5>& meshes, double tolerance) {
  std::printf(" n   edge at    p [cm]   dy [cm]   R_b [gf]  R_c [gf]   errors %% (p dy R_b R_c)\n");
  std::vector<OverhangFigures> on_node;
  for (int n : meshes) {
    const DrapeResult r = solveFemShell(overhangingBeam(n), FemShellSettings());
    ASSERT_TRUE(r.converged) << r.status;
    const OverhangFigures f = extract(r, n);
    const OverhangErrors e = errorsOf(f);
    const double at = (kL - kA) / (kL / n);
    std::printf("%3d  %6.2f    %.4f   %.5f   %.5f   %.5f   %.2f %.2f %.2f %.2f\n", n,
                at - std::floor(at + 1e-9), f.p, f.dy, f.Rb, f.Rc, 100 * e.p, 100 * e.dy,
                100 * e.Rb, 100 * e.Rc);
    EXPECT_LT(e.p, tolerance) << n;
    EXPECT_LT(e.dy, tolerance) << n;
    EXPECT_LT(e.Rb, tolerance) << n;
    EXPECT_LT(e.Rc, tolerance) << n;
    if (on_node.size() < 2) {
      on_node.push_back(f);
      continue;
    }
    for (const auto& g : on_node) {
      EXPECT_LT(std::abs(f.dy - g.dy) / g.dy, tolerance) << n;
      EXPECT_LT(std::abs(f.Rc - g.Rc) / g.Rc, tolerance) << n;
      EXPECT_LT(std::abs(f.p - g.p) / g.p, tolerance) << n;
      EXPECT_LT(std::abs(f.Rb - g.Rb) / g.Rb, tolerance) << n;
    }
  }
}

TEST(FemShellContact, OverhangingBeamWithTheEdgeBetweenNodes) {
  edgeBetweenNodes({96, 100, 97, 98, 99}, 0.01);
  edgeBetweenNodes({48, 56, 49, 50, 51}, 0.015);
  // Without the edge contact the nodes alone meet the table: the beam sinks over the edge.
  FemShellSettings nodes_only;
  nodes_only.edge_contact = false;
  const DrapeResult r = solveFemShell(overhangingBeam(26), nodes_only);
  const OverhangErrors e = errorsOf(extract(r, 26));
  std::printf("26 elements, node contact only: errors %% %.2f %.2f %.2f %.2f\n", 100 * e.p,
              100 * e.dy, 100 * e.Rb, 100 * e.Rc);
}

// The particle method on the same beam and table, read out the same way, beside the seed's own
// particle figures (p 2.2499, dy 0.0966, R_b 0.0156, R_c 0.0813: errors 6.06/18.0/15.52/3.15 %).
TEST(ParticleContact, OverhangingBeamBesideTheSeed) {
  const int n = 24;
  const DrapeResult r = solveParticleStatic(overhangingBeam(n), ParticleSettings());
  ASSERT_TRUE(r.converged) << r.status;
  const OverhangFigures f = extract(r, n);
  const OverhangErrors e = errorsOf(f);
  std::printf("particle  %.4f   %.5f   %.5f   %.5f   (%d iterations)\n", f.p, f.dy, f.Rb, f.Rc,
              r.iterations);
  std::printf(
      "error %%   %.2f     %.2f      %.2f      %.2f   (seed particle: 6.06 18.0 15.52 3.15)\n",
      100 * e.p, 100 * e.dy, 100 * e.Rb, 100 * e.Rc);
  // The seed's particle model missed dy by 18 %; ours must do no worse than the seed on any figure.
  EXPECT_LT(e.p, 0.0606);
  EXPECT_LT(e.dy, 0.18);
  EXPECT_LT(e.Rb, 0.1552);
  EXPECT_LT(e.Rc, 0.0315);
}

// Near the solution Newton's residual falls quadratically: r_{k+1} <= C r_k^2.
TEST(FemShellContact, NewtonConvergesQuadratically) {
  FemShellSettings s;
  s.tolerance = 1e-11;
  const DrapeResult r = solveFemShell(overhangingBeam(24), s);
  ASSERT_TRUE(r.converged) << r.status;
  std::vector<double> last;
  for (const auto& e : r.history)
    if (e.load_step == r.history.back().load_step) last.push_back(e.residual);
  std::printf("residuals of the last load step:");
  for (double x : last) std::printf(" %.3e", x);
  std::printf("\n");
  int quadratic = 0;
  for (std::size_t k = 1; k < last.size(); ++k) {
    if (last[k - 1] > 1e-2 || last[k] < 1e-13) continue;
    const double rate = std::log(last[k]) / std::log(last[k - 1]);
    std::printf("  log r_%zu / log r_%zu = %.2f\n", k, k - 1, rate);
    if (rate > 1.8) ++quadratic;
  }
  EXPECT_GE(quadratic, 1);
}

}  // namespace
}  // namespace chs
