#include "cloth_hair_sim/core/rod/obstacle_contact.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace chs::rod {
namespace {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

Vec3 vertex(const Eigen::VectorXd& q, int i) {
  return q.segment<3>(4 * i);
}

}  // namespace

ObstacleContact::ObstacleContact(const std::vector<StrandObstacle>& obstacles,
                                 const ObstacleContactSettings& settings, double contact_distance,
                                 double dt, const std::vector<Vec3>& x_start)
    : obstacles_(obstacles),
      settings_(settings),
      distance_(contact_distance),
      dt_(dt),
      x_start_(x_start) {}

void ObstacleContact::setNearObstacles(
    std::function<const std::vector<int>&(const Eigen::Vector3d&)> near, double beyond) {
  near_ = std::move(near);
  near_beyond_ = beyond;
  near_move_.assign(x_start_.size(), 0.0);
  for (std::size_t i = 0; i < x_start_.size(); ++i)
    for (const StrandObstacle& o : obstacles_)
      near_move_[i] = std::max(near_move_[i], dt_ * o.velocity.at(x_start_[i]).norm());
}

double ObstacleContact::updateLag(const Eigen::VectorXd& q, double reach,
                                  const std::vector<char>& skip) {
  std::vector<LaggedContact> previous;
  previous.swap(contacts_);
  for (int i = 0; i < static_cast<int>(x_start_.size()); ++i) {
    if (!skip.empty() && skip[i]) continue;
    const Vec3 x = vertex(q, i);
    const std::vector<int>* near = nullptr;
    if (near_ && distance_ + reach + near_move_[i] <= near_beyond_) near = &near_(x);
    const int count = near ? static_cast<int>(near->size()) : static_cast<int>(obstacles_.size());
    for (int j = 0; j < count; ++j) {
      const int o = near ? (*near)[j] : j;
      LaggedContact c;
      c.vertex = i;
      c.obstacle = o;
      c.obstacle_motion = dt_ * obstacles_[o].velocity.at(x_start_[i]);
      c.gap = normalGap(c, x, &c.normal);
      if (c.gap >= distance_ + reach) continue;
      // The start's distance from the obstacle before its motion.
      const double start_gap = obstacles_[o].surface->project(x_start_[i]).gap;
      c.rest_distance = std::min(distance_, start_gap + dt_ * settings_.recovery_speed);
      c.normal_force = settings_.stiffness * std::max(0.0, c.rest_distance - c.gap);
      contacts_.push_back(c);
    }
  }
  // Only friction reads the lagged forces (the normal penalty acts at the iterate).
  const auto rubs = [&](const LaggedContact& c) { return obstacles_[c.obstacle].friction > 0.0; };
  double largest = 0.0, change = 0.0;
  for (const LaggedContact& c : contacts_)
    if (rubs(c)) largest = std::max(largest, c.normal_force);
  if (previous.empty()) return 0.0;
  const double omega = 1.0 / (1.0 + 2.0 * frictionGain(q));
  // Both lists are ordered by (vertex, obstacle).
  auto p = previous.begin();
  for (LaggedContact& c : contacts_) {
    while (p != previous.end() &&
           (p->vertex < c.vertex || (p->vertex == c.vertex && p->obstacle < c.obstacle)))
      ++p;
    const double before = p != previous.end() && p->vertex == c.vertex && p->obstacle == c.obstacle
                              ? p->normal_force
                              : 0.0;
    if (rubs(c)) change = std::max(change, std::abs(c.normal_force - before));
    c.normal_force = before + omega * (c.normal_force - before);
  }
  for (; p != previous.end(); ++p)  // let go
    if (rubs(*p)) change = std::max(change, p->normal_force);
  return largest > 0.0 ? change / largest : 0.0;
}

// mu theta over the contacts with friction: each contact vertex's turning angle between its two
// edges (the strand's vertices are consecutive unknowns) times its obstacle's mu.
double ObstacleContact::frictionGain(const Eigen::VectorXd& q) const {
  const int nv = static_cast<int>(x_start_.size());
  double gain = 0.0;
  for (const LaggedContact& c : contacts_) {
    const double mu = obstacles_[c.obstacle].friction;
    if (mu <= 0.0 || c.normal_force <= 0.0 || c.vertex == 0 || c.vertex == nv - 1) continue;
    const Vec3 a = vertex(q, c.vertex) - vertex(q, c.vertex - 1),
               b = vertex(q, c.vertex + 1) - vertex(q, c.vertex);
    gain += mu * std::atan2(a.cross(b).norm(), a.dot(b));
  }
  return gain;
}

// The signed distance from the obstacle where the step leaves it (moved by its motion at the
// vertex, exact for a translation).
double ObstacleContact::normalGap(const LaggedContact& c, const Vec3& x, Vec3* normal) const {
  const SurfaceProjection p = obstacles_[c.obstacle].surface->project(x - c.obstacle_motion);
  if (normal) *normal = p.normal;
  return p.gap;
}

double ObstacleContact::contactEnergy(const LaggedContact& c, const Vec3& x) const {
  double e = 0.0;
  const double gap = normalGap(c, x, nullptr);
  // A centreline crossing into the obstacle is refused (the line search shortens the step)
  // unless the lag already had it there.
  if (gap < 0.0 && c.gap >= 0.0) return std::numeric_limits<double>::infinity();
  const double depth = c.rest_distance - gap;
  if (depth > 0.0) e += 0.5 * settings_.stiffness * depth * depth;
  const double mu_lambda = obstacles_[c.obstacle].friction * c.normal_force;
  if (mu_lambda > 0.0) {
    const Vec3 slip = x - x_start_[c.vertex] - c.obstacle_motion;
    const double y = (slip - slip.dot(c.normal) * c.normal).norm();
    const double eps = settings_.slip_velocity * dt_;
    e += mu_lambda * (y < eps ? -y * y * y / (3.0 * eps * eps) + y * y / eps + eps / 3.0 : y);
  }
  return e;
}

void ObstacleContact::contactDerivatives(const LaggedContact& c, const Vec3& x, Vec3& g,
                                         Mat3* h) const {
  g.setZero();
  if (h) h->setZero();
  Vec3 n;
  const double depth = c.rest_distance - normalGap(c, x, &n);
  if (depth > 0.0) {
    g -= settings_.stiffness * depth * n;
    if (h) *h += settings_.stiffness * n * n.transpose();
  }
  const double mu_lambda = obstacles_[c.obstacle].friction * c.normal_force;
  if (mu_lambda <= 0.0) return;
  const Mat3 P = Mat3::Identity() - c.normal * c.normal.transpose();
  const Vec3 u = P * (x - x_start_[c.vertex] - c.obstacle_motion);
  const double y = u.norm(), eps = settings_.slip_velocity * dt_;
  // f1(y) / y and (f1'(y) y - f1(y)) / y^3, f1 = f0' (IPC (16)); both bounded at y = 0.
  const double f1_y = y < eps ? 2.0 / eps - y / (eps * eps) : 1.0 / y;
  g += mu_lambda * f1_y * u;
  if (!h || y == 0.0) {
    if (h) *h += mu_lambda * f1_y * P;
    return;
  }
  const double c_uu = y < eps ? -1.0 / (eps * eps * y) : -1.0 / (y * y * y);
  *h += mu_lambda * (c_uu * u * u.transpose() + f1_y * P);  // positive semi-definite
}

double ObstacleContact::energy(const Eigen::VectorXd& q) const {
  double e = 0.0;
  for (const LaggedContact& c : contacts_) e += contactEnergy(c, vertex(q, c.vertex));
  return e;
}

void ObstacleContact::addDerivatives(const Eigen::VectorXd& q, Eigen::VectorXd& gradient,
                                     SymmetricBandMatrix* hessian) const {
  Vec3 g;
  Mat3 h;
  for (const LaggedContact& c : contacts_) {
    contactDerivatives(c, vertex(q, c.vertex), g, hessian ? &h : nullptr);
    const int k = 4 * c.vertex;
    gradient.segment<3>(k) += g;
    if (hessian) hessian->addBlock(k, k, h);
  }
}

std::vector<Vec3> ObstacleContact::forces(const Eigen::VectorXd& q) const {
  std::vector<Vec3> f;
  Vec3 g;
  for (const LaggedContact& c : contacts_) {
    contactDerivatives(c, vertex(q, c.vertex), g, nullptr);
    f.push_back(-g);
  }
  return f;
}

}  // namespace chs::rod
