#include "cloth_hair_sim/core/particle/particle_network.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <utility>

#include <Eigen/Geometry>

namespace chs {

namespace {
using Vec3 = Eigen::Vector3d;
using EdgeKey = std::pair<int, int>;

EdgeKey key(int a, int b) {
  return a < b ? EdgeKey(a, b) : EdgeKey(b, a);
}

double quadArea(const QuadMesh& m, const std::array<int, 4>& q) {
  const Vec3 d1 = m.vertices[q[2]] - m.vertices[q[0]];
  const Vec3 d2 = m.vertices[q[3]] - m.vertices[q[1]];
  return 0.5 * d1.cross(d2).norm();
}

// The corner of quad q next to v that is not `not_this`, i.e. the other edge of q at v.
int otherNeighbour(const std::array<int, 4>& q, int v, int not_this) {
  for (int k = 0; k < 4; ++k)
    if (q[k] == v) {
      const int prev = q[(k + 3) % 4], next = q[(k + 1) % 4];
      return prev == not_this ? next : prev;
    }
  return -1;
}

// Unsigned angle between e1 and e2 and its gradients with respect to e1 and e2.
// Returns false where the direction of the gradient is undefined (straight or folded back).
bool angleGradient(const Vec3& e1, const Vec3& e2, double* theta, Vec3* g1, Vec3* g2) {
  const double l1 = e1.norm(), l2 = e2.norm();
  if (l1 <= 0.0 || l2 <= 0.0) return false;
  const Vec3 u1 = e1 / l1, u2 = e2 / l2;
  const double c = u1.dot(u2), s = u1.cross(u2).norm();
  *theta = std::atan2(s, c);
  if (s < 1e-14) return false;
  // d theta / d e1 = -(u2 - c u1) / (s l1), and symmetrically for e2.
  *g1 = -(u2 - c * u1) / (s * l1);
  *g2 = -(u1 - c * u2) / (s * l2);
  return true;
}
}  // namespace

ParticleNetwork::ParticleNetwork(const QuadMesh& mesh, const ShellMaterial& material,
                                 const std::vector<int>& clamped,
                                 const ParticleNetworkOptions& options)
    : material_(material) {
  const int n = mesh.numVertices();
  tributary_area_.assign(n, 0.0);
  neighbours_.assign(n, {});

  // Edges with the quads on either side, and the width each edge stands for: a rectangle
  // a x c gives its edge of length a the strip width c/2 (area / (2 a)).
  std::map<EdgeKey, std::vector<int>> edge_quads;
  std::vector<double> area(mesh.numQuads());
  for (int qi = 0; qi < mesh.numQuads(); ++qi) {
    const auto& q = mesh.quads[qi];
    area[qi] = quadArea(mesh, q);
    for (int k = 0; k < 4; ++k) {
      tributary_area_[q[k]] += 0.25 * area[qi];
      edge_quads[key(q[k], q[(k + 1) % 4])].push_back(qi);
    }
  }
  std::map<EdgeKey, double> edge_width;
  const double eh = material.young * material.thickness;
  double total_length = 0.0;
  for (const auto& [e, quads] : edge_quads) {
    const double len = (mesh.vertices[e.second] - mesh.vertices[e.first]).norm();
    double width = 0.0;
    for (int qi : quads) width += area[qi] / (2.0 * len);
    edge_width[e] = width;
    total_length += len;
    neighbours_[e.first].push_back(e.second);
    neighbours_[e.second].push_back(e.first);
    // seed 000 eq. (38): F = D' E A (db / b) with A = width * h.
    stretch_.push_back({e.first, e.second, len, eh * width / len, options.stretch_compression});
  }
  mean_edge_ = edge_quads.empty() ? 0.0 : total_length / edge_quads.size();

  // seed 000 eq. (43): F_shear = B' E A / (2 b (1 + nu)) dd = G h dd for a square cell. For an
  // a x c cell the stiffness G h d^2 / (2 a c) gives the same shear energy G h gamma^2 a c / 2.
  const double gh = material.shearModulus() * material.thickness;
  for (int qi = 0; qi < mesh.numQuads(); ++qi) {
    const auto& q = mesh.quads[qi];
    for (int k = 0; k < 2; ++k) {
      const double d = (mesh.vertices[q[k + 2]] - mesh.vertices[q[k]]).norm();
      shear_.push_back(
          {q[k], q[k + 2], d, gh * d * d / (2.0 * area[qi]), options.shear_compression});
    }
  }

  // Grid lines: the continuation of edge (v, a) through v is the edge two quads further round
  // v. Accept it only when every way round agrees (valence-4 interior vertex, or a boundary
  // vertex along the boundary); irregular vertices get no hinge for that pair.
  auto continuation = [&](int v, int a) {
    std::set<int> found;
    for (int q1 : edge_quads.at(key(v, a))) {
      const int b = otherNeighbour(mesh.quads[q1], v, a);
      for (int q2 : edge_quads.at(key(v, b)))
        if (q2 != q1) found.insert(otherNeighbour(mesh.quads[q2], v, b));
    }
    return found.size() == 1 ? *found.begin() : -1;
  };
  auto addHinge = [&](int a, int v, int c, const Vec3& e1, const Vec3& e2, double width,
                      double length) {
    ParticleHinge h;
    h.a = a;
    h.v = v;
    h.c = c;
    h.rest_angle = std::atan2(e1.cross(e2).norm(), e1.dot(e2));
    h.width = width;
    h.length = length;
    h.edge1 = e1.norm();
    h.edge2 = e2.norm();
    hinges_.push_back(h);
    return &hinges_.back();
  };
  std::vector<std::set<int>> hinged(n);  // neighbours already in a hinge at v
  for (int v = 0; v < n; ++v)
    for (int a : neighbours_[v]) {
      const int c = continuation(v, a);
      if (c < 0 || c < a) continue;  // none, or added as (c, v, a)
      const Vec3 e1 = mesh.vertices[v] - mesh.vertices[a];
      const Vec3 e2 = mesh.vertices[c] - mesh.vertices[v];
      const double width = 0.5 * (edge_width[key(a, v)] + edge_width[key(v, c)]);
      addHinge(a, v, c, e1, e2, width, 0.5 * (e1.norm() + e2.norm()));
      hinged[v].insert(a);
      hinged[v].insert(c);
    }

  // Clamps: a grid line that ends at a clamped vertex continues into a held ghost edge, so the
  // hinge there resists the rotation of the first edge. It stands for the half edge between the
  // clamp and the next vertex only (Voronoi length b/2), which keeps the root curvature
  // second-order accurate instead of doubling the root rotation.
  std::vector<char> is_clamped(n, 0);
  for (int v : clamped) is_clamped[v] = 1;
  for (int v : clamped)
    for (int c : neighbours_[v]) {
      if (is_clamped[c] || hinged[v].count(c)) continue;
      const Vec3 e = mesh.vertices[c] - mesh.vertices[v];
      ParticleHinge* h = addHinge(-1, v, c, e, e, edge_width[key(v, c)], 0.5 * e.norm());
      h->rest_angle = 0.0;
      h->ghost_offset = e;
    }
}

double ParticleNetwork::bendingMoment(const ParticleHinge& h, double dphi) const {
  // seed 000 eqs. (44)-(47): M = F_bend b = D w dphi / b with D = E h^3 / (12 (1 - nu^2)).
  const double kappa = dphi / h.length;
  const double m =
      material_.kawabata ? material_.kawabata->moment(kappa) : material_.bendingStiffness() * kappa;
  return m * h.width;
}

double ParticleNetwork::bendingEnergy(const ParticleHinge& h, double dphi) const {
  if (!material_.kawabata) {
    const double k = material_.bendingStiffness() * h.width / h.length;
    return 0.5 * k * dphi * dphi;
  }
  // Integral of M d(phi) by Simpson's rule; the Kawabata law is smooth on each side of 0.
  const int steps = 16;
  double sum = 0.0;
  for (int i = 0; i <= steps; ++i) {
    const double w = (i == 0 || i == steps) ? 1.0 : (i % 2 ? 4.0 : 2.0);
    sum += w * bendingMoment(h, dphi * i / steps);
  }
  return sum * dphi / (3.0 * steps);
}

double ParticleNetwork::bendingTangent() const {
  if (!material_.kawabata) return material_.bendingStiffness();
  double t = 0.0;
  const auto& kb = *material_.kawabata;
  for (int i = 0; i <= 100; ++i)
    t = std::max(t, kb.stiffness(i * kb.k_max / 100.0 / kb.curvature_to_fit));
  return t;
}

void ParticleNetwork::addForces(const std::vector<Vec3>& x, std::vector<Vec3>& f) const {
  auto spring = [&](const ParticleSpring& s) {
    const Vec3 d = x[s.b] - x[s.a];
    const double len = d.norm();
    if (len <= 0.0) return;
    double stretch = len - s.rest_length;
    if (stretch < 0.0) stretch *= s.compression_factor;
    const Vec3 fb = -(s.stiffness * stretch / len) * d;
    f[s.b] += fb;
    f[s.a] -= fb;
  };
  for (const auto& s : stretch_) spring(s);
  for (const auto& s : shear_) spring(s);
  for (const auto& h : hinges_) {
    const Vec3 xa = h.a >= 0 ? x[h.a] : Vec3(x[h.v] - h.ghost_offset);
    double theta;
    Vec3 g1, g2;
    if (!angleGradient(x[h.v] - xa, x[h.c] - x[h.v], &theta, &g1, &g2)) continue;
    const double m = bendingMoment(h, theta - h.rest_angle);
    // Two force pairs of magnitude M / b (eq. 44): f = -M d theta / dx.
    // A ghost moves with v, so e1 is then fixed and only e2 pulls on v.
    if (h.a >= 0) {
      f[h.a] += m * g1;
      f[h.v] -= m * (g1 - g2);
    } else {
      f[h.v] += m * g2;
    }
    f[h.c] -= m * g2;
  }
}

double ParticleNetwork::elasticEnergy(const std::vector<Vec3>& x) const {
  double e = 0.0;
  auto spring = [&](const ParticleSpring& s) {
    double stretch = (x[s.b] - x[s.a]).norm() - s.rest_length;
    const double k = stretch < 0.0 ? s.stiffness * s.compression_factor : s.stiffness;
    e += 0.5 * k * stretch * stretch;
  };
  for (const auto& s : stretch_) spring(s);
  for (const auto& s : shear_) spring(s);
  for (const auto& h : hinges_) {
    const Vec3 xa = h.a >= 0 ? x[h.a] : Vec3(x[h.v] - h.ghost_offset);
    const Vec3 e1 = x[h.v] - xa, e2 = x[h.c] - x[h.v];
    const double theta = std::atan2(e1.cross(e2).norm(), e1.dot(e2));
    e += bendingEnergy(h, theta - h.rest_angle);
  }
  return e;
}

std::vector<double> ParticleNetwork::stiffnessBound() const {
  std::vector<double> bound(numVertices(), 0.0);
  auto spring = [&](const ParticleSpring& s) {
    const double k = s.stiffness * std::max(1.0, s.compression_factor);
    bound[s.a] += 2.0 * k;
    bound[s.b] += 2.0 * k;
  };
  for (const auto& s : stretch_) spring(s);
  for (const auto& s : shear_) spring(s);
  const double tangent = bendingTangent();
  for (const auto& h : hinges_) {
    // K ~ k grad(theta) grad(theta)^T with |grad_a| = 1/l1, |grad_c| = 1/l2, |grad_v| <= sum.
    const double k = tangent * h.width / h.length;
    const double ga = 1.0 / h.edge1, gc = 1.0 / h.edge2;
    const double gv = ga + gc, sum = (h.a >= 0 ? ga : 0.0) + gv + gc;
    if (h.a >= 0) bound[h.a] += k * ga * sum;
    bound[h.v] += k * gv * sum;
    bound[h.c] += k * gc * sum;
  }
  return bound;
}

}  // namespace chs
