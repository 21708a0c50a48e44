#include "cloth_hair_sim/core/mpm/layer_proximity.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <string>
#include <utility>

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "cloth_hair_sim/core/common/input_error.h"

namespace chs::mpm {

using Vec3 = Eigen::Vector3d;

LayerProximity::LayerProximity(const QuadMesh& mesh, std::vector<int> particle_face, double reach)
    : particle_face_(std::move(particle_face)) {
  if (!(reach > 0.0 && std::isfinite(reach)))
    throw InputError("layer proximity: the reach must be positive, got " + std::to_string(reach));
  const int nf = mesh.numQuads();
  for (int f : particle_face_)
    if (f < 0 || f >= nf)
      throw InputError("layer proximity: particle on face " + std::to_string(f) + " of " +
                       std::to_string(nf));
  std::vector<Vec3> centroid(nf, Vec3::Zero());
  double diameter = 0.0;
  std::vector<std::vector<int>> vertex_faces(mesh.numVertices());
  for (int f = 0; f < nf; ++f) {
    const auto& q = mesh.quads[f];
    for (int c = 0; c < 4; ++c) {
      centroid[f] += 0.25 * mesh.vertices[q[c]];
      vertex_faces[q[c]].push_back(f);
    }
    diameter = std::max({diameter, (mesh.vertices[q[0]] - mesh.vertices[q[2]]).norm(),
                         (mesh.vertices[q[1]] - mesh.vertices[q[3]]).norm()});
  }
  // Two particles that share a node are at most `reach` apart; the neighbourhoods reach so far
  // along the surface (plus the slack of sameLayer) that a pair beyond them lies on two layers.
  radius_slack_ = diameter;
  const double radius = kCurvatureSlack * reach + diameter;
  neighbourhood_.resize(nf);
  // Per thread: tentative distances of all faces (infinite but for those touched, reset after).
  tbb::enumerable_thread_specific<std::vector<double>> distances(
      [nf] { return std::vector<double>(nf, std::numeric_limits<double>::infinity()); });
  tbb::parallel_for(0, nf, [&](int source) {
    // Dijkstra over faces sharing a vertex, within the radius.
    std::vector<double>& dist = distances.local();
    std::vector<int> near;
    using Item = std::pair<double, int>;
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
    dist[source] = 0.0;
    near.push_back(source);
    queue.push({0.0, source});
    while (!queue.empty()) {
      const auto [d, f] = queue.top();
      queue.pop();
      if (d > dist[f]) continue;
      for (int c = 0; c < 4; ++c)
        for (int g : vertex_faces[mesh.quads[f][c]]) {
          const double dg = d + (centroid[g] - centroid[f]).norm();
          if (dg > radius || dg >= dist[g]) continue;
          if (dist[g] == std::numeric_limits<double>::infinity()) near.push_back(g);
          dist[g] = dg;
          queue.push({dg, g});
        }
    }
    std::sort(near.begin(), near.end());
    for (int f : near) {
      neighbourhood_[source].push_back({f, dist[f]});
      dist[f] = std::numeric_limits<double>::infinity();
    }
  });
}

bool LayerProximity::sameLayer(int p, int q, const std::vector<Vec3>& x) const {
  return facesOnOneLayer(particle_face_[p], particle_face_[q], (x[p] - x[q]).norm());
}

bool LayerProximity::facesOnOneLayer(int a, int b, double distance) const {
  if (a == b) return true;
  const std::vector<std::pair<int, double>>& near = neighbourhood_[a];
  const auto it = std::lower_bound(near.begin(), near.end(), std::make_pair(b, -1.0));
  if (it == near.end() || it->first != b) return false;
  // The centroid path overestimates the points' surface distance by up to a face diameter.
  return it->second - radius_slack_ <= kCurvatureSlack * distance;
}

void LayerProximity::find(const SparseGrid& grid, const SupportNodes& supports,
                          const std::vector<Vec3>& x, std::vector<char>& near) const {
  const int np = static_cast<int>(particle_face_.size());
  if (supports.numParticles() != np || static_cast<int>(x.size()) != np)
    throw InputError("layer proximity: supports of " + std::to_string(supports.numParticles()) +
                     " and " + std::to_string(x.size()) + " positions for " + std::to_string(np) +
                     " particles");
  const int k = supports.per_particle;
  // The first particle to reach a node stands for its layer there; a particle of another layer
  // at that node marks the node (a third layer differs from the first or from the second).
  std::vector<int> first(grid.size(), -1);
  for (int p = 0; p < np; ++p)
    for (const int* i = supports.of(p); i != supports.of(p) + k; ++i)
      if (first[*i] < 0) first[*i] = p;
  // Marks are only ever set, so threads may race to set one: relaxed atomics suffice.
  std::vector<char> shared(grid.size(), 0);
  tbb::parallel_for(0, np, [&](int p) {
    for (const int* i = supports.of(p); i != supports.of(p) + k; ++i)
      if (!__atomic_load_n(&shared[*i], __ATOMIC_RELAXED) && !sameLayer(first[*i], p, x))
        __atomic_store_n(&shared[*i], char{1}, __ATOMIC_RELAXED);
  });
  near.assign(np, 0);
  tbb::parallel_for(0, np, [&](int p) {
    for (const int* i = supports.of(p); i != supports.of(p) + k; ++i)
      if (shared[*i]) {
        near[p] = 1;
        return;
      }
  });
}

}  // namespace chs::mpm
