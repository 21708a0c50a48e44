#include "cloth_hair_sim/core/solid_shell/adaptive_mesh.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <stdexcept>
#include <string>
#include <tuple>

#include <Eigen/Geometry>

#include "cloth_hair_sim/core/common/input_error.h"

namespace chs {

namespace {

// Local labels of a cell: corners 0-3, midpoints 4-7 (of edge k, k + 1), centre 8; their
// positions in the cell's unit square.
constexpr double kLabelXY[9][2] = {{0, 0},   {1, 0},   {1, 1},   {0, 1},    {0.5, 0},
                                   {1, 0.5}, {0.5, 1}, {0, 0.5}, {0.5, 0.5}};
constexpr int C0 = 0, C1 = 1, C2 = 2, C3 = 3, M0 = 4, M1 = 5, M2 = 6, M3 = 7, Z = 8;

// Label after rotating the cell's numbering by r quarter turns.
int rotated(int label, int r) {
  if (label < 4) return (label + r) % 4;
  if (label < 8) return 4 + (label - 4 + r) % 4;
  return label;
}

using Key = std::tuple<int, int, int, int>;
Key key(const AdaptiveQuadMesh::Cell& c) {
  return {c.quad, c.level, c.i, c.j};
}

// Shape functions of element `labels` (local labels) at the cell point p, if p lies in it.
bool shapeAt(const std::array<int, 4>& labels, const Eigen::Vector2d& p, double N[4]) {
  auto at = [](int l) { return Eigen::Vector2d(kLabelXY[l][0], kLabelXY[l][1]); };
  constexpr double tol = 1e-9;
  if (labels[3] < 0) {
    const Eigen::Vector2d a = at(labels[0]), b = at(labels[1]), c = at(labels[2]);
    Eigen::Matrix2d J;
    J << b - a, c - a;
    const Eigen::Vector2d st = J.inverse() * (p - a);
    N[0] = 1 - st.sum(), N[1] = st[0], N[2] = st[1], N[3] = 0;
    return N[0] > -tol && N[1] > -tol && N[2] > -tol;
  }
  // Inverse bilinear map by Newton (the cell's quads are convex).
  Eigen::Vector2d xi(0, 0);
  const double sx[4] = {-1, 1, 1, -1}, sy[4] = {-1, -1, 1, 1};
  for (int it = 0; it < 20; ++it) {
    Eigen::Vector2d x = Eigen::Vector2d::Zero();
    Eigen::Matrix2d J = Eigen::Matrix2d::Zero();
    for (int i = 0; i < 4; ++i) {
      const Eigen::Vector2d pi = at(labels[i]);
      x += 0.25 * (1 + sx[i] * xi[0]) * (1 + sy[i] * xi[1]) * pi;
      J.col(0) += 0.25 * sx[i] * (1 + sy[i] * xi[1]) * pi;
      J.col(1) += 0.25 * sy[i] * (1 + sx[i] * xi[0]) * pi;
    }
    const Eigen::Vector2d step = J.inverse() * (p - x);
    xi += step;
    if (step.norm() < 1e-14) break;
  }
  for (int i = 0; i < 4; ++i) N[i] = 0.25 * (1 + sx[i] * xi[0]) * (1 + sy[i] * xi[1]);
  return std::abs(xi[0]) < 1 + tol && std::abs(xi[1]) < 1 + tol;
}

}  // namespace

AdaptiveQuadMesh::AdaptiveQuadMesh(const QuadMesh& level0,
                                   const std::vector<Eigen::Vector3d>& directors, int levels)
    : levels_(levels), level0_(level0) {
  if (levels < 1 || levels > kMaxAdaptiveLevels)
    throw InputError("solid_shell.adaptive_levels must lie in [1, " +
                     std::to_string(kMaxAdaptiveLevels) + "] (each level quadruples the " +
                     "background mesh), got " + std::to_string(levels));
  if (directors.size() != level0.vertices.size())
    throw InputError("adaptive mesh: one director per level-0 vertex");
  size_ = 1 << levels;
  const int n = size_;
  // Level-0 vertices keep their numbers: their boundary conditions and loads stay where they are.
  background_.vertices = level0.vertices;
  directors_ = directors;
  edge_of_node_.assign(level0.vertices.size(), {-1, -1});
  auto addNode = [&](const Eigen::Vector3d& x, const Eigen::Vector3d& d, std::array<int, 2> edge) {
    background_.vertices.push_back(x);
    directors_.push_back(d.normalized());
    edge_of_node_.push_back(edge);
    return background_.numVertices() - 1;
  };
  std::map<std::pair<int, int>, std::vector<int>> edge_nodes;
  // Node t of n along the level-0 edge from u to w (0 < t < n), made once per edge.
  auto edgeNode = [&](int u, int w, int t) {
    const int lo = std::min(u, w), hi = std::max(u, w);
    auto [it, fresh] = edge_nodes.try_emplace({lo, hi});
    if (fresh)
      for (int k = 1; k < n; ++k) {
        const double s = static_cast<double>(k) / n;
        it->second.push_back(addNode((1 - s) * level0.vertices[lo] + s * level0.vertices[hi],
                                     (1 - s) * directors[lo] + s * directors[hi], {lo, hi}));
      }
    return it->second[u == lo ? t - 1 : n - t - 1];
  };
  lattice_.resize(level0.quads.size());
  for (std::size_t q = 0; q < level0.quads.size(); ++q) {
    const auto& v = level0.quads[q];
    auto& L = lattice_[q];
    L.assign((n + 1) * (n + 1), -1);
    for (int a = 0; a <= n; ++a)
      for (int b = 0; b <= n; ++b) {
        int id;
        if ((a == 0 || a == n) && (b == 0 || b == n))
          id = v[a == 0 ? (b == 0 ? 0 : 3) : (b == 0 ? 1 : 2)];
        else if (b == 0)
          id = edgeNode(v[0], v[1], a);
        else if (a == n)
          id = edgeNode(v[1], v[2], b);
        else if (b == n)
          id = edgeNode(v[3], v[2], a);
        else if (a == 0)
          id = edgeNode(v[0], v[3], b);
        else {
          const double s = static_cast<double>(a) / n, r = static_cast<double>(b) / n;
          const double w[4] = {(1 - s) * (1 - r), s * (1 - r), s * r, (1 - s) * r};
          Eigen::Vector3d x = Eigen::Vector3d::Zero(), d = Eigen::Vector3d::Zero();
          for (int k = 0; k < 4; ++k)
            x += w[k] * level0.vertices[v[k]], d += w[k] * directors[v[k]];
          id = addNode(x, d, {-1, -1});
        }
        L[a * (n + 1) + b] = id;
      }
    for (int a = 0; a < n; ++a)
      for (int b = 0; b < n; ++b)
        background_.quads.push_back(
            {node(q, a, b), node(q, a + 1, b), node(q, a + 1, b + 1), node(q, a, b + 1)});
    leaves_.push_back({static_cast<int>(q), 0, 0, 0});
  }
}

std::array<int, 9> AdaptiveQuadMesh::labels(const Cell& c) const {
  const int s = size_ >> c.level, h = s / 2, a = c.i * s, b = c.j * s;
  std::array<int, 9> l;
  l.fill(-1);
  l[C0] = node(c.quad, a, b), l[C1] = node(c.quad, a + s, b);
  l[C2] = node(c.quad, a + s, b + s), l[C3] = node(c.quad, a, b + s);
  if (c.level < levels_) {
    l[M0] = node(c.quad, a + h, b), l[M1] = node(c.quad, a + s, b + h);
    l[M2] = node(c.quad, a + h, b + s), l[M3] = node(c.quad, a, b + h);
    l[Z] = node(c.quad, a + h, b + h);
  }
  return l;
}

std::array<int, 4> AdaptiveQuadMesh::corners(const Cell& c) const {
  const auto l = labels(c);
  return {l[C0], l[C1], l[C2], l[C3]};
}

int AdaptiveQuadMesh::centre(const Cell& c) const {
  return labels(c)[Z];
}

double AdaptiveQuadMesh::sideLength(const Cell& c) const {
  const auto k = corners(c);
  double sum = 0.0;
  for (int e = 0; e < 4; ++e)
    sum += (background_.vertices[k[e]] - background_.vertices[k[(e + 1) % 4]]).norm();
  return sum / 4;
}

std::vector<bool> AdaptiveQuadMesh::leafCorners() const {
  std::vector<bool> corner(numNodes(), false);
  for (const Cell& c : leaves_)
    for (int v : corners(c)) corner[v] = true;
  return corner;
}

std::vector<std::array<int, 4>> AdaptiveQuadMesh::pattern(const Cell& c,
                                                          const std::vector<bool>& corner) const {
  const auto l = labels(c);
  int hanging = 0, count = 0;
  for (int k = 0; k < 4; ++k)
    if (l[4 + k] >= 0 && corner[l[4 + k]]) hanging |= 1 << k, ++count;
  // Canonical patterns (Fig. 16(b) in spirit): rotate so that the hanging midpoints are M0...
  std::vector<std::array<int, 4>> canonical;
  int r = 0;
  auto has = [&](int k) { return (hanging >> (k % 4)) & 1; };
  if (count == 0) {
    canonical = {{C0, C1, C2, C3}};
  } else if (count == 4) {
    canonical = {{C0, M0, Z, M3}, {M0, C1, M1, Z}, {Z, M1, C2, M2}, {M3, Z, M2, C3}};
  } else if (count == 1) {
    while (!has(r)) ++r;
    canonical = {{C0, M0, Z, C3}, {M0, C1, C2, Z}, {Z, C2, C3, -1}};
  } else if (count == 2 && has(0) == has(2)) {
    while (!has(r)) ++r;
    canonical = {{C0, M0, M2, C3}, {M0, C1, C2, M2}};
  } else if (count == 2) {
    while (!(has(r) && has(r + 1))) ++r;
    canonical = {{C0, M0, Z, C3}, {M0, C1, M1, Z}, {Z, M1, C2, C3}};
  } else {
    while (has(r + 3)) ++r;  // the edge without a midpoint is M3
    canonical = {{M0, C1, M1, Z}, {Z, M1, C2, M2}, {C0, M0, Z, C3}, {Z, M2, C3, -1}};
  }
  for (auto& e : canonical)
    for (int& label : e)
      if (label >= 0) label = rotated(label, r);
  return canonical;
}

std::vector<AdaptiveQuadMesh::Element> AdaptiveQuadMesh::elements() const {
  const std::vector<bool> corner = leafCorners();
  std::vector<Element> out;
  for (std::size_t leaf = 0; leaf < leaves_.size(); ++leaf) {
    const auto l = labels(leaves_[leaf]);
    for (const auto& e : pattern(leaves_[leaf], corner)) {
      Element el;
      for (int k = 0; k < 4; ++k) el.nodes[k] = e[k] < 0 ? -1 : l[e[k]];
      el.leaf = static_cast<int>(leaf);
      out.push_back(el);
    }
  }
  return out;
}

std::vector<bool> AdaptiveQuadMesh::activeNodes() const {
  std::vector<bool> active(numNodes(), false);
  for (const Element& e : elements())
    for (int v : e.nodes)
      if (v >= 0) active[v] = true;
  return active;
}

int AdaptiveQuadMesh::numActiveNodes() const {
  const std::vector<bool> a = activeNodes();
  return static_cast<int>(std::count(a.begin(), a.end(), true));
}

bool AdaptiveQuadMesh::balance() {
  bool changed = false;
  for (;;) {
    const std::vector<bool> corner = leafCorners();
    std::vector<Cell> next;
    bool split = false;
    for (const Cell& c : leaves_) {
      bool coarse = false;
      if (c.level + 2 <= levels_) {
        // A corner of a leaf two levels finer at a quarter point of an edge.
        const int s = size_ >> c.level, q = s / 4, a = c.i * s, b = c.j * s;
        for (int t : {q, 3 * q})
          coarse = coarse || corner[node(c.quad, a + t, b)] || corner[node(c.quad, a + s, b + t)] ||
                   corner[node(c.quad, a + t, b + s)] || corner[node(c.quad, a, b + t)];
      }
      if (!coarse) {
        next.push_back(c);
        continue;
      }
      split = true;
      for (int dj = 0; dj < 2; ++dj)
        for (int di = 0; di < 2; ++di)
          next.push_back({c.quad, c.level + 1, 2 * c.i + di, 2 * c.j + dj});
    }
    leaves_ = std::move(next);
    if (!split) return changed;
    changed = true;
  }
}

bool AdaptiveQuadMesh::adapt(const std::vector<int>& flags) {
  if (flags.size() != leaves_.size())
    throw std::invalid_argument("AdaptiveQuadMesh::adapt: one flag per leaf");
  const std::vector<bool> corner = leafCorners();
  // Merges: four sibling leaves all flagged -1 whose parent no neighbour outruns by two levels.
  std::map<Key, std::vector<std::size_t>> siblings;
  for (std::size_t k = 0; k < leaves_.size(); ++k) {
    const Cell& c = leaves_[k];
    if (c.level > 0 && flags[k] < 0) siblings[{c.quad, c.level - 1, c.i / 2, c.j / 2}].push_back(k);
  }
  std::vector<bool> gone(leaves_.size(), false);
  std::vector<Cell> next;
  bool changed = false;
  for (const auto& [parent_key, children] : siblings) {
    if (children.size() != 4) continue;
    const Cell parent{std::get<0>(parent_key), std::get<1>(parent_key), std::get<2>(parent_key),
                      std::get<3>(parent_key)};
    bool blocked = false;
    if (parent.level + 2 <= levels_) {
      const int s = size_ >> parent.level, q = s / 4, a = parent.i * s, b = parent.j * s;
      for (int t : {q, 3 * q})
        blocked = blocked || corner[node(parent.quad, a + t, b)] ||
                  corner[node(parent.quad, a + s, b + t)] ||
                  corner[node(parent.quad, a + t, b + s)] || corner[node(parent.quad, a, b + t)];
    }
    if (blocked) continue;
    for (std::size_t k : children) gone[k] = true;
    next.push_back(parent);
    changed = true;
  }
  // Splits.
  for (std::size_t k = 0; k < leaves_.size(); ++k) {
    if (gone[k]) continue;
    const Cell& c = leaves_[k];
    if (flags[k] > 0 && c.level < levels_) {
      for (int dj = 0; dj < 2; ++dj)
        for (int di = 0; di < 2; ++di)
          next.push_back({c.quad, c.level + 1, 2 * c.i + di, 2 * c.j + dj});
      changed = true;
    } else {
      next.push_back(c);
    }
  }
  leaves_ = std::move(next);
  changed = balance() || changed;
  // Deterministic order: by level-0 quad, then position in the quadtree.
  std::sort(leaves_.begin(), leaves_.end(), [&](const Cell& x, const Cell& y) {
    const int sx = size_ >> x.level, sy = size_ >> y.level;
    return std::make_tuple(x.quad, x.j * sx, x.i * sx, x.level) <
           std::make_tuple(y.quad, y.j * sy, y.i * sy, y.level);
  });
  return changed;
}

void AdaptiveQuadMesh::fillSwitchedOnNodes(const std::vector<bool>& was_active,
                                           std::vector<Eigen::Vector3d>& u,
                                           std::vector<Eigen::Vector3d>& un,
                                           bool discrete_kirchhoff) const {
  if (was_active.size() != static_cast<std::size_t>(numNodes()) || u.size() != was_active.size() ||
      un.size() != was_active.size())
    throw std::invalid_argument("AdaptiveQuadMesh::fillSwitchedOnNodes: one value per node");
  const std::vector<bool> now = activeNodes();
  std::vector<bool> known = was_active;
  // The cells that need their midpoints or centre, level by level: parents of leaves (their
  // children use all five) and transition leaves (their centre). A node's value comes from the
  // coarsest cell that has it as midpoint or centre, whose corners are known by then.
  std::set<Key> parents;
  for (const Cell& c : leaves_)
    for (Cell p = c; p.level > 0;) {
      p = {p.quad, p.level - 1, p.i / 2, p.j / 2};
      if (!parents.insert(key(p)).second) break;
    }
  const auto& X = background_.vertices;
  for (int level = 0; level < levels_; ++level) {
    auto fill = [&](const Cell& c, bool with_centre) {
      const auto l = labels(c);
      // Midpoints not known are derived (in place: an inactive node's value is scratch): the
      // centre's serendipity interpolation needs all four (seed 001 5.4).
      for (int k = 0; k < 4; ++k) {
        const int m = l[4 + k];
        if (known[m]) continue;
        if (discrete_kirchhoff) {
          insertMidEdgeNode(X, directors_, l[k], l[(k + 1) % 4], l[(k + 2) % 4], m, u, un);
        } else {
          u[m] = 0.5 * (u[l[k]] + u[l[(k + 1) % 4]]);
          un[m] = 0.5 * (un[l[k]] + un[l[(k + 1) % 4]]);
        }
        if (now[m]) known[m] = true;
      }
      if (with_centre && !known[l[Z]] && now[l[Z]]) {
        insertCentreNode({l[C0], l[C1], l[C2], l[C3]}, {l[M0], l[M1], l[M2], l[M3]}, l[Z], u, un);
        known[l[Z]] = true;
      }
    };
    for (const Key& k : parents)
      if (std::get<1>(k) == level)
        fill({std::get<0>(k), std::get<1>(k), std::get<2>(k), std::get<3>(k)}, true);
    for (const Cell& c : leaves_)
      if (c.level == level && !known[centre(c)] && now[centre(c)]) fill(c, true);
  }
}

void AdaptiveQuadMesh::interpolateInactive(std::vector<Eigen::Vector3d>& values) const {
  if (values.size() != static_cast<std::size_t>(numNodes()))
    throw std::invalid_argument("AdaptiveQuadMesh::interpolateInactive: one value per node");
  const std::vector<bool> corner = leafCorners(), active = activeNodes();
  std::vector<bool> done = active;
  for (const Cell& c : leaves_) {
    const auto l = labels(c);
    const auto elements = pattern(c, corner);
    const int s = size_ >> c.level, a0 = c.i * s, b0 = c.j * s;
    for (int a = 0; a <= s; ++a)
      for (int b = 0; b <= s; ++b) {
        const int v = node(c.quad, a0 + a, b0 + b);
        if (done[v]) continue;
        const Eigen::Vector2d p(static_cast<double>(a) / s, static_cast<double>(b) / s);
        for (const auto& e : elements) {
          double N[4];
          if (!shapeAt(e, p, N)) continue;
          Eigen::Vector3d x = Eigen::Vector3d::Zero();
          for (int k = 0; k < 4; ++k)
            if (e[k] >= 0) x += N[k] * values[l[e[k]]];
          values[v] = x;
          done[v] = true;
          break;
        }
      }
  }
}

BoundaryConditions AdaptiveQuadMesh::boundaryConditions(const BoundaryConditions& level0) const {
  BoundaryConditions bc = level0;
  const int nv0 = level0_.numVertices();
  std::vector<bool> clamped(nv0, false), pinned(nv0, false);
  std::vector<std::array<bool, 3>> fixed(nv0, {false, false, false});
  for (int v : level0.clamped) clamped[v] = pinned[v] = true, fixed[v] = {true, true, true};
  for (int v : level0.pinned) pinned[v] = true, fixed[v] = {true, true, true};
  for (const auto& f : level0.fixed_components) fixed[f.vertex][f.axis] = true;
  for (int v = nv0; v < numNodes(); ++v) {
    const auto [p, q] = edge_of_node_[v];
    if (p < 0) continue;
    if (clamped[p] && clamped[q])
      bc.clamped.push_back(v);
    else if (pinned[p] && pinned[q])
      bc.pinned.push_back(v);
    else
      for (int axis = 0; axis < 3; ++axis)
        if (fixed[p][axis] && fixed[q][axis]) bc.fixed_components.push_back({v, axis});
  }
  return bc;
}

SolidShellMesh AdaptiveQuadMesh::activeMesh(const BoundaryConditions& background_bc) const {
  SolidShellMesh m;
  m.X = background_.vertices;
  m.Xn = directors_;
  for (const Element& e : elements()) m.elements.push_back(e.nodes);
  m.bc = background_bc;
  return m;
}

void insertMidEdgeNode(const std::vector<Eigen::Vector3d>& X,
                       const std::vector<Eigen::Vector3d>& Xn, int A, int B, int E, int M,
                       std::vector<Eigen::Vector3d>& u, std::vector<Eigen::Vector3d>& un) {
  // Co-rotated frames (x', y', z') of the edge: origin A, y' along AB, E in the x'-y' plane, z'
  // on the side of the element's directors (A, B, E counter-clockwise).
  auto frame = [](const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& e) {
    Eigen::Matrix3d F;  // columns n_x', n_y', n_z'
    F.col(1) = (b - a).normalized();
    F.col(2) = (b - a).cross(e - a).normalized();
    F.col(0) = F.col(1).cross(F.col(2));
    return F;
  };
  const Eigen::Vector3d xA = X[A] + u[A], xB = X[B] + u[B], xE = X[E] + u[E];
  const Eigen::Matrix3d F0 = frame(X[A], X[B], X[E]), F = frame(xA, xB, xE);
  const Eigen::Matrix3d R = F * F0.transpose();  // the edge's rigid rotation
  const double L = (X[B] - X[A]).norm();
  // Eqs. (30)-(31): local director displacements from the co-rotated reference directors.
  const Eigen::Vector3d dA = F.transpose() * (Xn[A] + un[A]) - F0.transpose() * Xn[A];
  const Eigen::Vector3d dB = F.transpose() * (Xn[B] + un[B]) - F0.transpose() * Xn[B];
  const double chord = (xB - xA).norm(), v_oB = chord - L;
  // Eq. (32): u_o, w_o of A and B vanish in this frame. The thin-beam deflection is capped where
  // A-M-B would outgrow the edge's reference length: the linear (small-strain) condition ignores
  // the stretch a deflection adds, and a coarse element's directors can turn more than its chord
  // (measured: a 6 x 6 wool sheet on a table, mid-edge nodes 1.7 mm off the chord, 0.7 % stretch
  // and forces 100 x the sheet's weight). Nearly inextensible fabric bends, it does not stretch.
  const double deflection = -L / 8 * (dA.y() - dB.y());
  const double room = chord < L ? 0.5 * std::sqrt(L * L - chord * chord) : 0.0;
  const Eigen::Vector3d uoM(0.0, 0.5 * v_oB, std::clamp(deflection, -room, room));
  const Eigen::Vector3d unM(0.5 * (dA.x() + dB.x()), -0.25 * (dA.y() + dB.y()),
                            0.5 * (dA.z() + dB.z()));
  // Eqs. (33)-(34): the co-rotated node plus its local displacement.
  u[M] = xA + R * (X[M] - X[A]) + F * uoM - X[M];
  // The director's direction as eq. (32) gives it, its length the mean of A's and B's: averaging
  // u_n and w_n alone shortens the director of a bent edge by 1 - cos(theta / 2) (a thickness
  // strain of 3 % for 0.5 rad across the edge, in the element's stiffest mode).
  const Eigen::Vector3d nM = R * Xn[M] + F * unM;
  const double length = 0.5 * ((Xn[A] + un[A]).norm() + (Xn[B] + un[B]).norm());
  un[M] = length * nM.normalized() - Xn[M];
}

void insertCentreNode(const std::array<int, 4>& corners, const std::array<int, 4>& midpoints,
                      int centre, std::vector<Eigen::Vector3d>& u,
                      std::vector<Eigen::Vector3d>& un) {
  Eigen::Vector3d uc = Eigen::Vector3d::Zero(), unc = Eigen::Vector3d::Zero();
  for (int k = 0; k < 4; ++k) {
    uc += 0.5 * u[midpoints[k]] - 0.25 * u[corners[k]];
    unc += 0.5 * un[midpoints[k]] - 0.25 * un[corners[k]];
  }
  u[centre] = uc;
  un[centre] = unc;
}

}  // namespace chs
