#include "cloth_hair_sim/core/rod/hair_dynamics.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <tbb/parallel_for.h>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/mpm/grid_forces.h"
#include "cloth_hair_sim/core/mpm/grid_interpolation.h"
#include "cloth_hair_sim/core/mpm/transfers.h"
#include "cloth_hair_sim/core/rod/parallel_transport.h"
#include "cloth_hair_sim/core/rod/strand_contact_share.h"

namespace chs::rod {
namespace {

using Vec3 = Eigen::Vector3d;

struct HairSnapshot : DynamicsSnapshot {
  std::vector<DiscreteElasticRod> rods;
  std::vector<std::vector<Vec3>> v, accel;
  std::vector<std::vector<double>> omega;
  std::vector<Eigen::Isometry3d> poses;
  std::map<int, Eigen::Isometry3d> grip_motions;
  std::vector<Eigen::Matrix3d> C, F;
  double time = 0.0;
};

}  // namespace

HairDynamics::HairDynamics(const HairSettings& settings)
    : settings_(settings), grid_(settings.grid_spacing), collisions_([&] {
        try {
          return StrandCollisions(settings.strand_collisions);
        } catch (const InputError& e) {
          throw InputError(std::string("hair: ") + e.what());
        }
      }()) {
  if (!(settings.grid_spacing > 0.0 && std::isfinite(settings.grid_spacing)))
    throw InputError("hair: grid_spacing must be positive and finite");
  if (settings.kernel_degree != 2 && settings.kernel_degree != 3)
    throw InputError("hair: kernel_degree must be 2 or 3");
  if (!(settings.pic_blend >= 0.0 && settings.pic_blend <= 1.0))
    throw InputError("hair: pic_blend (xi) must lie in [0, 1]");
  if (!settings.gravity.allFinite()) throw InputError("hair: gravity must be finite");
  if (!(settings.friction >= 0.0 && std::isfinite(settings.friction)))
    throw InputError("hair: friction must be >= 0 and finite");
  if (!(settings.cfl > 0.0 && settings.cfl <= 1.0))
    throw InputError("hair: cfl must lie in (0, 1]");
  if (!(settings.max_time_step > 0.0 && std::isfinite(settings.max_time_step)))
    throw InputError("hair: max_time_step must be positive and finite");
  if (!(settings.newton.tolerance > 0.0) || settings.newton.max_iterations < 1)
    throw InputError("hair: Newton tolerance must be positive, iterations at least 1");
  const ObstacleContactSettings& oc = settings.obstacle_contact;
  if (!(oc.stiffness > 0.0 && std::isfinite(oc.stiffness)))
    throw InputError("hair: obstacle contact stiffness must be positive and finite");
  if (!(oc.slip_velocity > 0.0 && std::isfinite(oc.slip_velocity)))
    throw InputError("hair: obstacle slip_velocity (eps_v) must be positive and finite");
  if (!(oc.recovery_speed > 0.0) || !std::isfinite(oc.recovery_speed))
    throw InputError("hair: obstacle recovery_speed must be positive and finite");
  if (oc.lag_passes < 1) throw InputError("hair: obstacle lag_passes must be at least 1");
  if (!(oc.lag_tolerance >= 0.0))
    throw InputError("hair: obstacle lag_tolerance must be >= 0, got " +
                     std::to_string(oc.lag_tolerance));
  if (!(settings.continuum.contact_blend >= 0.0 && settings.continuum.contact_blend <= 1.0))
    throw InputError("hair: strand continuum: contact_blend (xi in contact) must lie in [0, 1]");
  try {  // checked even when disabled: a typo is reported before someone enables it
    bulk_.emplace(settings.continuum.youngs_modulus, settings.continuum.poisson_ratio);
    bulk_return_.emplace(*bulk_, settings.continuum.friction);
  } catch (const InputError& e) {
    throw InputError(std::string("hair: strand continuum: ") + e.what());
  }
  if (!settings.continuum.enabled) {
    bulk_.reset();
    bulk_return_.reset();
  }
}

int HairDynamics::addStrand(const std::vector<Vec3>& rest, const RodMaterial& material,
                            bool clamped, const Vec3& first_director) {
  const int index = numStrands();
  if (particles_.size() + static_cast<int>(rest.size()) > settings_.max_vertices)
    throw InputError("hair: strand " + std::to_string(index) + " would bring the vertices to " +
                     std::to_string(particles_.size() + rest.size()) + ", over max_vertices " +
                     std::to_string(settings_.max_vertices));
  DiscreteElasticRod rod = [&] {
    try {
      return DiscreteElasticRod(rest, material, first_director);
    } catch (const InputError& e) {
      throw InputError("hair: strand " + std::to_string(index) + ": " + e.what());
    }
  }();
  Strand s(std::move(rod));
  const int nv = s.rod.numVertices();
  s.v.assign(nv, Vec3::Zero());
  s.accel.assign(nv, Vec3::Zero());
  s.omega.assign(s.rod.numEdges(), 0.0);
  s.force.assign(nv, Vec3::Zero());
  s.grip.assign(nv, -1);
  s.grip_x.assign(nv, Vec3::Zero());
  s.hold_force.assign(nv, Vec3::Zero());
  s.clamped = clamped;
  s.root_x0 = rest[0];
  s.root_x1 = rest[1];
  s.root_m1 = s.rod.materialDirector1(0);
  s.offset = particles_.size();
  // A vertex's share of the strands' bulk (Han's V_p^0) is its own volume, m / rho: the
  // continuum's force per mass then does not depend on how densely the strands lie.
  const double density = s.rod.material().density;
  for (int i = 0; i < nv; ++i) {
    const bool held = clamped && i < 2;
    const double m = held ? 0.0 : s.rod.vertexMass(i);
    particles_.add(rest[i], Vec3::Zero(), m, m / density);
  }
  if (bulk_) bulk_wave_speed_ = std::max(bulk_wave_speed_, bulk_->dilatationalWaveSpeed(density));
  if (strand_offsets_.empty()) strand_offsets_.push_back(0);
  strand_offsets_.push_back(particles_.size());
  strands_.push_back(std::move(s));
  return index;
}

void HairDynamics::checkStrand(int s) const {
  if (s < 0 || s >= numStrands())
    throw InputError("hair: no strand " + std::to_string(s) + " (" + std::to_string(numStrands()) +
                     " strands)");
}

void HairDynamics::setVelocities(int s, const std::vector<Vec3>& v) {
  checkStrand(s);
  if (static_cast<int>(v.size()) != strands_[s].rod.numVertices())
    throw InputError("hair: " + std::to_string(v.size()) + " velocities for strand " +
                     std::to_string(s) + " of " + std::to_string(strands_[s].rod.numVertices()) +
                     " vertices");
  for (const Vec3& u : v)
    if (!u.allFinite()) throw InputError("hair: velocities must be finite");
  strands_[s].v = v;
  strands_[s].accel.assign(v.size(), Vec3::Zero());  // no trend of the old velocities
}

void HairDynamics::setNaturalShape(int s, const std::vector<Eigen::Vector2d>& curvature,
                                   const std::vector<double>& twist) {
  checkStrand(s);
  strands_[s].rod.setNaturalShape(curvature, twist);
}

void HairDynamics::setRootFrame(int s, const Eigen::Isometry3d& pose) {
  checkStrand(s);
  if (!pose.matrix().allFinite()) throw InputError("hair: root frame must be finite");
  strands_[s].pose = pose;
}

HoldingWrench HairDynamics::clampWrench(int s) const {
  checkStrand(s);
  return strands_[s].clamp;
}

const HairDynamics::Grip& HairDynamics::grip(int id) const {
  const auto it = grips_.find(id);
  if (it == grips_.end()) throw InputError("hair: no grip " + std::to_string(id));
  return it->second;
}

int HairDynamics::addGrip(const std::vector<StrandVertex>& vertices) {
  std::vector<StrandVertex> taken;
  for (const StrandVertex& sv : vertices) {
    checkStrand(sv.strand);
    const Strand& s = strands_[sv.strand];
    if (sv.vertex < 0 || sv.vertex >= s.rod.numVertices())
      throw InputError("hair: strand " + std::to_string(sv.strand) + " has no vertex " +
                       std::to_string(sv.vertex));
    const bool repeated = std::any_of(taken.begin(), taken.end(), [&](const StrandVertex& t) {
      return t.strand == sv.strand && t.vertex == sv.vertex;
    });
    if (!held(s, sv.vertex) && !repeated) taken.push_back(sv);
  }
  if (taken.empty()) throw InputError("hair: a grip of no free vertex");
  const int id = next_grip_++;
  for (const StrandVertex& sv : taken) {
    Strand& s = strands_[sv.strand];
    s.grip[sv.vertex] = id;
    s.grip_x[sv.vertex] = s.rod.positions()[sv.vertex];
    s.hold_force[sv.vertex].setZero();
    particles_.mass[s.offset + sv.vertex] = 0.0;  // held: a boundary condition, as a clamp
  }
  grips_[id].vertices = std::move(taken);
  return id;
}

void HairDynamics::setGripFrame(int id, const Eigen::Isometry3d& motion) {
  grip(id);
  if (!motion.matrix().allFinite()) throw InputError("hair: grip frame must be finite");
  grips_[id].motion = motion;
}

void HairDynamics::removeGrip(int id) {
  for (const StrandVertex& sv : grip(id).vertices) {
    Strand& s = strands_[sv.strand];
    s.grip[sv.vertex] = -1;
    s.hold_force[sv.vertex].setZero();
    particles_.mass[s.offset + sv.vertex] = s.rod.vertexMass(sv.vertex);
  }
  grips_.erase(id);
}

const std::vector<StrandVertex>& HairDynamics::gripVertices(int id) const {
  return grip(id).vertices;
}

HoldingWrench HairDynamics::gripWrench(int id, const Vec3& origin) const {
  HoldingWrench w;
  for (const StrandVertex& sv : grip(id).vertices) {
    const Strand& s = strands_[sv.strand];
    const Vec3& f = s.hold_force[sv.vertex];
    w.force += f;
    w.torque += (s.rod.positions()[sv.vertex] - origin).cross(f);
  }
  return w;
}

std::vector<StrandVertex> HairDynamics::freeVerticesNear(const Vec3& centre, double radius) const {
  std::vector<StrandVertex> out;
  for (int k = 0; k < numStrands(); ++k) {
    const Strand& s = strands_[k];
    for (int i = 0; i < s.rod.numVertices(); ++i)
      if (!held(s, i) && (s.rod.positions()[i] - centre).norm() <= radius) out.push_back({k, i});
  }
  return out;
}

void HairDynamics::setVertexForce(int s, int vertex, const Vec3& force) {
  checkStrand(s);
  if (vertex < 0 || vertex >= strands_[s].rod.numVertices())
    throw InputError("hair: strand " + std::to_string(s) + " has no vertex " +
                     std::to_string(vertex));
  if (!force.allFinite()) throw InputError("hair: vertex force must be finite");
  strands_[s].force[vertex] = force;
}

void HairDynamics::setGravity(const Vec3& gravity) {
  if (!gravity.allFinite()) throw InputError("hair: gravity must be finite");
  settings_.gravity = gravity;
}

double HairDynamics::totalMass() const {
  double m = 0.0;
  for (const Strand& s : strands_)
    for (int i = 0; i < s.rod.numVertices(); ++i) m += s.rod.vertexMass(i);
  return m;
}

// Han (4.7), implicitly: the configuration minimising the incremental potential from
// q~ = q^n + dt qdot^n, the clamp's unknowns at their targets.
void HairDynamics::solveStrandStep(Strand& s, double dt, StrandNewtonResult& result) {
  DiscreteElasticRod& rod = s.rod;
  s.q_start = rod.configuration();
  Eigen::VectorXd target = s.q_start;
  for (int i = 0; i < rod.numVertices(); ++i)
    target.segment<3>(DiscreteElasticRod::vertexDof(i)) += dt * s.v[i];
  for (int j = 0; j < rod.numEdges(); ++j)
    target[DiscreteElasticRod::angleDof(j)] += dt * s.omega[j];
  StrandLoads loads;
  loads.dt = dt;
  loads.gravity = settings_.gravity;
  loads.vertex_forces = s.force;
  // Newton starts from the inertial target x^n + dt v^n (for a strand in motion much closer to
  // the step's end than x^n) plus the last step's acceleration carried on (gravity for a
  // falling strand, the swing's for a swinging one), its edges turned as that turns them but
  // kept at their lengths at x^n (a straight extrapolation of a turning strand stretches it,
  // which its stiff stretching would take several Newton iterations to undo). The acceleration
  // brings the start within a few hundredths of a segment of the solution instead of a fifth
  // (hair at 1/120 s: dt^2 g = 0.7 mm on 4 mm segments): 4.29 Newton iterations per
  // strand-step became 3.96 (hair_benchmarks). A jump in velocity (an impulse) is no trend: the
  // move it predicts is capped at a quarter segment.
  Eigen::VectorXd q = target;
  const double segment = rod.length() / rod.numEdges();
  for (int i = 0; i < rod.numVertices(); ++i) {
    Vec3 ahead = dt * dt * s.accel[i];
    if (ahead.norm() > 0.25 * segment) ahead *= 0.25 * segment / ahead.norm();
    q.segment<3>(DiscreteElasticRod::vertexDof(i)) += ahead;
  }
  const bool gripped = std::any_of(s.grip.begin(), s.grip.end(), [](int g) { return g >= 0; });
  if (s.clamped || gripped) loads.held.assign(rod.numDofs(), 0);
  if (s.clamped) {
    std::fill(loads.held.begin(), loads.held.begin() + 7, 1);
    q.segment<3>(0) = s.pose * s.root_x0;
    q.segment<3>(4) = s.pose * s.root_x1;
  }
  for (int j = s.clamped ? 1 : 0; j < rod.numEdges(); ++j) {
    const int a = DiscreteElasticRod::vertexDof(j), b = DiscreteElasticRod::vertexDof(j + 1);
    const double length = (s.q_start.segment<3>(b) - s.q_start.segment<3>(a)).norm();
    const Vec3 e = q.segment<3>(b) - q.segment<3>(a);
    if (e.norm() > 0.0) q.segment<3>(b) = q.segment<3>(a) + length * e.normalized();
  }
  // Gripped vertices where the grip carries them by the step's end (their angles stay free), and
  // the free vertices beside them drawn after them at their edges' lengths, as a chain follows
  // a hand (moved alone, a gripped vertex would stretch its edges by its step's move, which the
  // stiff stretching takes many Newton iterations to undo). A free strand's Newton starts from
  // x^n so moved (its inertial target may lie inside an obstacle, where the contact's energy is
  // not defined); a drawn vertex that would enter an obstacle stays, and the chain stops there.
  if (gripped) {
    Eigen::VectorXd start = s.q_start;
    Eigen::VectorXd& q0 = s.clamped ? q : start;
    const auto vertex = [&](int i) { return q0.segment<3>(DiscreteElasticRod::vertexDof(i)); };
    const auto admissible = [&](int i, const Vec3& x) {
      const Vec3 x_start = s.q_start.segment<3>(DiscreteElasticRod::vertexDof(i));
      for (const StrandObstacle& o : obstacles_)
        if (o.surface->project(x - dt * o.velocity.at(x_start)).gap < 0.0) return false;
      return true;
    };
    const auto draw = [&](int from, int step) {
      for (int b = from + step; b >= 0 && b < rod.numVertices() && !held(s, b); b += step) {
        const int a = b - step;
        const double length = (s.q_start.segment<3>(DiscreteElasticRod::vertexDof(b)) -
                               s.q_start.segment<3>(DiscreteElasticRod::vertexDof(a)))
                                  .norm();
        const Vec3 e = vertex(b) - vertex(a);
        if (e.norm() == 0.0) break;
        const Vec3 x = vertex(a) + length * e.normalized();
        if (!admissible(b, x)) break;
        vertex(b) = x;
      }
    };
    for (int i = 0; i < rod.numVertices(); ++i) {
      if (s.grip[i] < 0) continue;
      const int k = DiscreteElasticRod::vertexDof(i);
      std::fill(loads.held.begin() + k, loads.held.begin() + k + 3, 1);
      q0.segment<3>(k) = grips_.at(s.grip[i]).motion * s.grip_x[i];
      draw(i, 1);
      draw(i, -1);
    }
    if (!s.clamped) {
      q = q0;
      rod.setConfiguration(q);
    }
  }
  if (s.clamped) {
    rod.setConfiguration(q);
    // The first angle turns the (transported) reference director onto the clamp's director,
    // unwrapped to the nearest turn of the last angle.
    const Vec3 m1 = s.pose.linear() * s.root_m1;
    double theta = signedAngle(rod.referenceDirector1(0), m1, rod.tangent(0));
    theta += 2.0 * M_PI * std::round((s.q_start[3] - theta) / (2.0 * M_PI));
    q[3] = theta;
    rod.setConfiguration(q);
  }
  loads.inertial_target = target;
  // The obstacles' contact, its normal forces lagged from the step's start and then from each
  // pass's solution (IPC's lagged friction iterations).
  const RodMaterial& material = rod.material();
  std::vector<Vec3> x_start(rod.numVertices());
  std::vector<char> skip(rod.numVertices(), 0);
  // Candidates: within a segment and the step's largest move of the contact distance.
  double reach = rod.length() / rod.numEdges();
  for (int i = 0; i < rod.numVertices(); ++i) {
    x_start[i] = s.q_start.segment<3>(DiscreteElasticRod::vertexDof(i));
    reach = std::max(reach, dt * s.v[i].norm() + rod.length() / rod.numEdges());
    skip[i] = held(s, i);
  }
  ObstacleContactSettings contact_settings = settings_.obstacle_contact;
  contact_settings.stiffness *= material.stretchingStiffness() * rod.numEdges() / rod.length();
  ObstacleContact contact(obstacles_, contact_settings,
                          std::sqrt(material.radius_1 * material.semiAxis2()), dt, x_start);
  if (near_obstacles_)
    contact.setNearObstacles(
        [this](const Vec3& x) -> const std::vector<int>& { return near_obstacles_->near(x); },
        near_obstacles_->beyond());
  contact.updateLag(s.q_start, reach, skip);
  if (!contact.empty()) loads.obstacles = &contact;
  result = solveStrand(rod, loads, settings_.newton);
  for (int pass = 1; pass < settings_.obstacle_contact.lag_passes && loads.obstacles; ++pass) {
    if (contact.updateLag(rod.configuration(), reach, skip) <=
        settings_.obstacle_contact.lag_tolerance)
      break;
    const int before = result.iterations;
    result = solveStrand(rod, loads, settings_.newton);
    result.iterations += before;
  }
  const Eigen::VectorXd q_new = rod.configuration();
  s.obstacle_impulse.assign(obstacles_.size(), mpm::ColliderImpulse());
  if (loads.obstacles) {
    const std::vector<Vec3> f = contact.forces(q_new);
    for (std::size_t k = 0; k < f.size(); ++k) {
      const LaggedContact& c = contact.contacts()[k];
      s.obstacle_impulse[c.obstacle].add(q_new.segment<3>(DiscreteElasticRod::vertexDof(c.vertex)),
                                         dt * f[k]);
    }
  }
  s.clamp = HoldingWrench();
  for (Vec3& f : s.hold_force) f.setZero();
  // The reactions on gripped vertices' positions: the force each grip applies there.
  if (gripped && result.held_reaction.size() == rod.numDofs())
    for (int i = 0; i < rod.numVertices(); ++i)
      if (s.grip[i] >= 0)
        s.hold_force[i] = result.held_reaction.segment<3>(DiscreteElasticRod::vertexDof(i));
  // (None when the solve could not start: a configuration where the energy is not defined.)
  if (s.clamped && result.held_reaction.size() == rod.numDofs()) {
    // The reactions on the held unknowns: forces on x_0 and x_1, the moment about the first
    // edge on its angle.
    const Eigen::VectorXd& r = result.held_reaction;
    const Vec3 f1 = r.segment<3>(4);
    s.clamp.force = r.segment<3>(0) + f1;
    s.clamp.torque = (q_new.segment<3>(4) - q_new.segment<3>(0)).cross(f1) + r[3] * rod.tangent(0);
  }
  for (int i = 0; i < rod.numVertices(); ++i) {
    const int k = DiscreteElasticRod::vertexDof(i);
    particles_.x[s.offset + i] = s.q_start.segment<3>(k);
    particles_.v[s.offset + i] = (q_new.segment<3>(k) - s.q_start.segment<3>(k)) / dt;  // v*
  }
  for (int j = 0; j < rod.numEdges(); ++j) {
    const int k = DiscreteElasticRod::angleDof(j);
    s.omega[j] = (q_new[k] - s.q_start[k]) / dt;
  }
}

void HairDynamics::beginStep(double dt) {
  collider_impulse_.assign(colliders_.size(), mpm::ColliderImpulse());
  std::vector<StrandNewtonResult> results(strands_.size());
  // With many colliders (a mannequin's links) each vertex's obstacle contact asks only those
  // listed near it: within what a vertex's candidate reach (solveStrandStep), the contact
  // distance and an obstacle's motion over the step add up to at most.
  double segment = 0.0, fastest = 0.0, fastest_collider = 0.0;
  for (const Strand& s : strands_) {
    segment = std::max(segment, s.rod.length() / s.rod.numEdges());
    for (const Vec3& v : s.v) fastest = std::max(fastest, v.norm());
    for (const Vec3& x : s.rod.positions())
      for (const mpm::GridCollider& c : colliders_)
        fastest_collider = std::max(fastest_collider, c.velocity.at(x).norm());
  }
  const mpm::ColliderCandidates near(colliders_, 0.0,
                                     2.0 * (segment + dt * (fastest + fastest_collider)),
                                     4.0 * settings_.grid_spacing);
  near_obstacles_ = &near;
  tbb::parallel_for(0, numStrands(), [&](int s) { solveStrandStep(strands_[s], dt, results[s]); });
  near_obstacles_ = nullptr;
  for (const Strand& strand : strands_)
    for (std::size_t c = 0; c < collider_impulse_.size(); ++c) {
      collider_impulse_[c].linear += strand.obstacle_impulse[c].linear;
      collider_impulse_[c].angular += strand.obstacle_impulse[c].angular;
    }
  converged_ = true;
  last_iterations_ = 0;
  last_total_iterations_ = 0;
  for (const StrandNewtonResult& r : results) {
    converged_ = converged_ && r.converged;
    last_iterations_ = std::max(last_iterations_, r.iterations);
    last_total_iterations_ += r.iterations;
  }
}

// Han (4.8)-(4.9).
void HairDynamics::transferToGrid() {
  mpm::particleToGrid({&particles_}, grid_, settings_.kernel_degree, &supports_);
  // A vertex just inside a node's support gives it a mass of order w^2 m (1e-23 kg for hair a
  // hair's breadth inside): such a node carries nothing the strand could feel, but in the
  // contact with another body's field (world/field_contact.h) its velocity is the ratio of two
  // vanishing numbers. Nodes below 1e-9 of the heaviest vertex are dropped from the field (their
  // change of velocity, and so their effect on the vertices, is zero).
  double m_max = 0.0;
  for (double m : particles_.mass) m_max = std::max(m_max, m);
  for (int i = 0; i < grid_.size(); ++i)
    if (grid_.mass[i] < 1e-9 * m_max) {
      grid_.mass[i] = 0.0;
      grid_.momentum[i].setZero();
      grid_.velocity[i].setZero();
    }
  grid_v_star_ = grid_.velocity;
}

bool HairDynamics::updateGrid(double dt) {
  last_continuum_ = StrandContinuumStats();
  if (bulk_) {
    // Han (4.10)-(4.11): f_i = -sum_p V_p^0 tau(F_p^E) grad w_ip (the Kirchhoff form of P F^T;
    // gravity is in the Lagrangian update), v_i += h f_i / m_i, then F^E moved by the grid's
    // velocity gradient and returned to the cone, in substeps h <= cfl dx / c of the bulk's wave
    // on the step's grid (the nodes moved virtually, as Han's x_i + alpha dt v_i): the penalty
    // can then be stiff enough to stop strands moving at a fraction of c without shrinking the
    // world's step; a substep costs a transfer, no rod solve. The last substep's F^E update
    // waits for the grid's final velocity (after obstacles and other bodies), in
    // transferFromGrid.
    const double courant = settings_.cfl * settings_.grid_spacing;
    const int n = std::clamp(static_cast<int>(std::ceil(dt * bulk_wave_speed_ / courant)), 1,
                             kMaxBulkSubsteps);
    bulk_substep_ = dt / n;
    last_continuum_.substeps = n;
    // A strand's own vertices are no contact: the stress acts in the share of the grid mass
    // that other strands bring (a strand alone bends and swings as without the continuum).
    bulk_share_ = otherStrandsShare(grid_, particles_.x, particles_.mass, strand_offsets_,
                                    settings_.kernel_degree, supports_[0]);
    bulk_scratch_ = particles_;
    bulk_stress_.resize(particles_.size());
    for (int k = 0; k < n; ++k) {
      if (k > 0) {
        bulk_scratch_.x = particles_.x;  // the support's stencils are at the step start
        mpm::gridToParticle(grid_, bulk_scratch_, settings_.kernel_degree, 0.0, bulk_substep_,
                            &supports_[0]);
        returnToCone(bulk_scratch_.F, false);
      }
      tbb::parallel_for(0, particles_.size(), [&](int p) {
        const double V = bulk_share_[p] * particles_.volume0[p];
        bulk_stress_[p] = V > 0.0 ? Eigen::Matrix3d(V * bulk_->kirchhoffStress(bulk_scratch_.F[p]))
                                  : Eigen::Matrix3d::Zero();
      });
      std::fill(grid_.force.begin(), grid_.force.end(), Vec3::Zero());
      mpm::scatterStressForces(grid_, particles_.x, bulk_stress_, settings_.kernel_degree,
                               &supports_[0]);
      for (int i = 0; i < grid_.size(); ++i) {
        if (grid_.mass[i] <= 0.0) continue;  // a dropped node (transferToGrid): nothing to move
        grid_.momentum[i] += bulk_substep_ * grid_.force[i];
        grid_.velocity[i] = grid_.momentum[i] / grid_.mass[i];
      }
    }
  }
  mpm::applyGridColliders(grid_, colliders_, &collider_impulse_);
  return converged_;
}

void HairDynamics::reapplyColliders() {
  mpm::applyGridColliders(grid_, colliders_, &collider_impulse_);
}

void HairDynamics::transferFromGrid(double dt) {
  // Han (4.12): v = (1 - xi) (v* + sum_i w_ip (v_i** - v_i*)) + xi sum_i w_ip v_i**, with the
  // APIC affine velocity from v** for the next transfer.
  grid_dv_.resize(grid_.size());
  for (int i = 0; i < grid_.size(); ++i) grid_dv_[i] = grid_.velocity[i] - grid_v_star_[i];
  mpm::interpolateNodeField(grid_, grid_dv_, particles_.x, settings_.kernel_degree, supports_[0],
                            &dv_p_, nullptr);
  scratch_ = particles_;
  if (bulk_) scratch_.F = bulk_scratch_.F;  // F^E before the last substep (updateGrid)
  mpm::gridToParticle(grid_, scratch_, settings_.kernel_degree, 0.0, bulk_ ? bulk_substep_ : dt,
                      &supports_[0], bulk_.has_value());
  const double xi = settings_.pic_blend;
  x_start_ = particles_.x;
  if (bulk_) {
    returnToCone(scratch_.F, true);
    particles_.F = scratch_.F;
  }
  // Strands in parallel; each keeps its vertices' impulses on the colliders, summed after in
  // strand order (the same sum on any thread count).
  const std::size_t nc = surfaces_.size();
  strand_grid_impulse_.assign(strands_.size() * nc, mpm::ColliderImpulse());
  tbb::parallel_for(0, numStrands(), [&](int k) {
    Strand& s = strands_[k];
    DiscreteElasticRod& rod = s.rod;
    for (int i = 0; i < rod.numVertices(); ++i) {
      const int p = s.offset + i;
      const Vec3& x_start = x_start_[p];
      Vec3 v, x;
      if (held(s, i)) {  // the clamp's or the grip's motion
        v = particles_.v[p];
        x = x_start + dt * v;
        particles_.C[p].setZero();
      } else {
        const Vec3 v_flip = particles_.v[p] + dv_p_[p], to_grid = scratch_.v[p] - v_flip;
        v = v_flip + xi * to_grid;
        if (bulk_ && bulk_compressed_[p] && bulk_share_[p] > 0.0) {
          // Pressed into other strands: across the strand, the bulk's velocity (contact_blend).
          const int a = std::max(i - 1, 0), b = std::min(i + 1, rod.numVertices() - 1);
          const Vec3 t = (x_start_[s.offset + b] - x_start_[s.offset + a]).normalized();
          const Vec3 across = to_grid - t * t.dot(to_grid);
          v += (settings_.continuum.contact_blend - xi) * bulk_share_[p] * across;
        }
        particles_.C[p] = scratch_.C[p];
        x = x_start + dt * v;  // (4.13)
        // A vertex ending inside an obstacle: the nodes' Coulomb projection as an impulse on
        // it and the move redone, then the remaining depth removed from its position only
        // (the free nodes above a vertex resting on a surface do not resist its fall), by at
        // most the recovery speed's share of the step: a deep vertex moved out at once would
        // stretch its edges by its depth, and their recoil fling the strand.
        const double recovery = dt * settings_.obstacle_contact.recovery_speed;
        for (std::size_t c = 0; c < surfaces_.size(); ++c) {
          const SurfaceProjection pr = surfaces_[c]->project(x);
          if (pr.gap >= 0.0) continue;
          const mpm::GridCollider& gc = colliders_[c];
          const Vec3 vc = gc.velocity.at(x);
          const Vec3 v_rel = v - vc;
          if (v_rel.dot(pr.normal) < 0.0) {
            const Vec3 before = v;
            v = vc + mpm::collideRelativeVelocity(v_rel, pr.normal, gc.boundary, gc.friction);
            strand_grid_impulse_[k * nc + c].add(x, rod.vertexMass(i) * (v - before));
            particles_.C[p].setZero();
            x = x_start + dt * v;
          }
          const double gap = surfaces_[c]->project(x).gap;
          if (gap < 0.0) x -= std::max(gap, -recovery) * pr.normal;
        }
      }
      particles_.v[p] = v;
      particles_.x[p] = x;
    }
  });
  for (std::size_t k = 0; k < strands_.size(); ++k)
    for (std::size_t c = 0; c < nc; ++c) {
      collider_impulse_[c].linear += strand_grid_impulse_[k * nc + c].linear;
      collider_impulse_[c].angular += strand_grid_impulse_[k * nc + c].angular;
    }
  last_collisions_ = StrandCollisionStats();
  if (settings_.strand_collisions.enabled && !strands_.empty()) {
    // Han (4.13): the geometric impulses between strands on these velocities, clamped and
    // gripped vertices immovable; a vertex they change moves again from x^n, put back out of
    // any obstacle.
    inverse_mass_.resize(particles_.size());
    for (const Strand& s : strands_)
      for (int i = 0; i < s.rod.numVertices(); ++i)
        inverse_mass_[s.offset + i] = held(s, i) ? 0.0 : 1.0 / s.rod.vertexMass(i);
    v_free_ = particles_.v;
    last_collisions_ = collisions_.apply(x_start_, particles_.v, inverse_mass_, strand_offsets_,
                                         strandThickness(), dt);
    tbb::parallel_for(0, particles_.size(), [&](int p) {
      if (particles_.v[p] == v_free_[p]) return;
      Vec3 x = x_start_[p] + dt * particles_.v[p];
      for (const auto& surface : surfaces_) {
        const SurfaceProjection pr = surface->project(x);
        if (pr.gap < 0.0) x -= pr.gap * pr.normal;
      }
      particles_.x[p] = x;
    });
  }
  tbb::parallel_for(0, numStrands(), [&](int k) {
    Strand& s = strands_[k];
    DiscreteElasticRod& rod = s.rod;
    Eigen::VectorXd q = rod.configuration();  // the solved angles
    for (int i = 0; i < rod.numVertices(); ++i) {
      s.accel[i] = (particles_.v[s.offset + i] - s.v[i]) / dt;
      s.v[i] = particles_.v[s.offset + i];
      q.segment<3>(DiscreteElasticRod::vertexDof(i)) = particles_.x[s.offset + i];
    }
    rod.setConfiguration(q);
    rod.commit();
  });
}

// The trial F^E of every vertex returned to the Drucker-Prager cone in place; held vertices
// carry none. `last`: the step's final return, counted in the stats (resets in any substep).
void HairDynamics::returnToCone(std::vector<Eigen::Matrix3d>& F, bool last) {
  if (last) bulk_compressed_.assign(F.size(), 0);
  for (const Strand& s : strands_)
    for (int i = 0; i < s.rod.numVertices(); ++i) {
      const int p = s.offset + i;
      Eigen::Matrix3d& f = F[p];
      if (held(s, i) || particles_.volume0[p] <= 0.0) {
        f.setIdentity();
      } else if (!f.allFinite() || !(f.determinant() > 0.0)) {
        f.setIdentity();
        ++last_continuum_.reset;
      } else {
        mpm::DruckerPrager::Case c;
        f = bulk_return_->project(f, &c);
        if (!last) continue;
        bulk_compressed_[p] = c != mpm::DruckerPrager::Case::kSeparated;
        last_continuum_.compressed += c != mpm::DruckerPrager::Case::kSeparated;
        last_continuum_.slid += c == mpm::DruckerPrager::Case::kSlid;
      }
    }
}

const Eigen::Matrix3d& HairDynamics::bulkDeformation(int s, int i) const {
  checkStrand(s);
  if (i < 0 || i >= strands_[s].rod.numVertices())
    throw InputError("hair: no vertex " + std::to_string(i) + " on strand " + std::to_string(s));
  return particles_.F[strands_[s].offset + i];
}

double HairDynamics::strandThickness() const {
  if (settings_.strand_collisions.thickness > 0.0) return settings_.strand_collisions.thickness;
  double r = 0.0;
  for (const Strand& s : strands_) {
    const RodMaterial& m = s.rod.material();
    r = std::max({r, m.radius_1, m.semiAxis2()});
  }
  return 2.0 * r;
}

void HairDynamics::endStep(double dt) {
  time_ += dt;
}

std::vector<mpm::MassCarriers> HairDynamics::fieldCarriers() const {
  return {mpm::MassCarriers{&particles_.x, &particles_.mass, &supports_[0]}};
}

double HairDynamics::stableTimeStep() const {
  const double support = (settings_.kernel_degree + 1) * settings_.grid_spacing;
  const double cfl = settings_.cfl * settings_.grid_spacing;
  double dt = mpm::motionTimeStep({motion()}, colliders_, support, cfl, settings_.max_time_step);
  // The continuum's substeps stay within their cap (updateGrid).
  if (bulk_wave_speed_ > 0.0) dt = std::min(dt, kMaxBulkSubsteps * cfl / bulk_wave_speed_);
  return dt;
}

mpm::MotionGroup HairDynamics::motion() const {
  mpm::MotionGroup g;
  g.self = bulk_.has_value();
  for (const Strand& s : strands_) {
    g.x.insert(g.x.end(), s.rod.positions().begin(), s.rod.positions().end());
    g.v.insert(g.v.end(), s.v.begin(), s.v.end());
  }
  return g;
}

Vec3 HairDynamics::linearMomentum() const {
  Vec3 p = Vec3::Zero();
  for (const Strand& s : strands_)
    for (int i = 0; i < s.rod.numVertices(); ++i) p += s.rod.vertexMass(i) * s.v[i];
  return p;
}

double HairDynamics::kineticEnergy() const {
  double k = 0.0;
  for (const Strand& s : strands_) {
    for (int i = 0; i < s.rod.numVertices(); ++i)
      k += 0.5 * s.rod.vertexMass(i) * s.v[i].squaredNorm();
    for (int j = 0; j < s.rod.numEdges(); ++j)
      k += 0.5 * s.rod.angleInertia(j) * s.omega[j] * s.omega[j];
  }
  return k;
}

bool HairDynamics::finite() const {
  for (const Strand& s : strands_) {
    for (const Vec3& x : s.rod.positions())
      if (!x.allFinite()) return false;
    for (const Vec3& v : s.v)
      if (!v.allFinite()) return false;
  }
  return true;
}

void HairDynamics::setColliders(const RigidSurfaces& colliders,
                                const std::vector<SurfaceVelocity>& velocities,
                                const std::vector<double>& frictions) {
  std::vector<mpm::GridCollider> grid_colliders = mpm::makeGridColliders(
      colliders, velocities, frictions, settings_.boundary, settings_.friction, "hair");
  std::vector<StrandObstacle> obstacles;
  for (const mpm::GridCollider& g : grid_colliders)
    obstacles.push_back(StrandObstacle{g.surface, g.velocity, g.friction});
  surfaces_ = colliders;
  colliders_ = std::move(grid_colliders);
  obstacles_ = std::move(obstacles);
  collider_impulse_.assign(colliders_.size(), mpm::ColliderImpulse());
}

void HairDynamics::writeState(StateWriter& out) const {
  out.text("hair");
  out.u64(strands_.size());
  for (const Strand& s : strands_) {
    s.rod.writeState(out);
    out.vectors(s.v);
    out.vectors(s.accel);
    out.reals(s.omega);
    out.matrix(s.pose.matrix());
    out.ints(s.grip);
    out.vectors(s.grip_x);
    out.vectors(s.hold_force);
    out.vectors({s.clamp.force, s.clamp.torque});
  }
  out.u64(grips_.size());
  for (const auto& [id, g] : grips_) {
    out.u64(static_cast<std::uint64_t>(id));
    std::vector<int> v;
    for (const StrandVertex& sv : g.vertices) v.insert(v.end(), {sv.strand, sv.vertex});
    out.ints(v);
    out.matrix(g.motion.matrix());
  }
  out.u64(static_cast<std::uint64_t>(next_grip_));
  out.reals(particles_.mass);  // grips move mass off the grid
  out.matrices(particles_.C);
  out.matrices(particles_.F);
  out.real(time_);
}

void HairDynamics::readState(StateReader& in) {
  in.expectText("hair", "body kind");
  in.expectCount("hair strands", strands_.size());
  std::vector<Strand> strands = strands_;
  for (Strand& s : strands) {
    s.rod.readState(in);
    const std::size_t nv = s.rod.numVertices();
    s.v = in.vectors("strand velocities", nv);
    s.accel = in.vectors("strand accelerations", nv);
    s.omega = in.reals("strand angle rates", s.rod.numEdges());
    s.pose.matrix() = in.matrix("strand root frame");
    s.grip = in.ints("strand grips");
    if (s.grip.size() != nv) in.fail("strand grips of another vertex count");
    for (int id : s.grip)
      if (id < -1) in.fail("strand grip " + std::to_string(id) + " is no grip");
    s.grip_x = in.vectors("strand grip points", nv);
    s.hold_force = in.vectors("strand hold forces", nv);
    const std::vector<Vec3> clamp = in.vectors("strand clamp wrench", 2);
    s.clamp.force = clamp[0];
    s.clamp.torque = clamp[1];
  }
  std::map<int, Grip> grips;
  const std::uint64_t n_grips = in.u64("grip count");
  for (std::uint64_t k = 0; k < n_grips; ++k) {
    const int id = static_cast<int>(in.u64("grip id"));
    const std::vector<int> v = in.ints("grip vertices");
    if (v.size() % 2 != 0) in.fail("grip " + std::to_string(id) + ": an odd vertex list");
    Grip g;
    for (std::size_t i = 0; i + 1 < v.size(); i += 2) {
      if (v[i] < 0 || v[i] >= numStrands() || v[i + 1] < 0 ||
          v[i + 1] >= strands[v[i]].rod.numVertices())
        in.fail("grip " + std::to_string(id) + " holds a vertex the hair does not have");
      g.vertices.push_back(StrandVertex{v[i], v[i + 1]});
    }
    g.motion.matrix() = in.matrix("grip motion");
    grips[id] = g;
  }
  const int next_grip = static_cast<int>(in.u64("next grip id"));
  for (const Strand& s : strands)  // every held vertex's grip is in the record
    for (int id : s.grip)
      if (id >= 0 && !grips.count(id))
        in.fail("a vertex is held by grip " + std::to_string(id) + ", which is not saved");
  const std::size_t np = particles_.size();
  std::vector<double> mass = in.reals("vertex masses on the grid", np);
  std::vector<Eigen::Matrix3d> C = in.matrices("affine velocities", np);
  std::vector<Eigen::Matrix3d> F = in.matrices("bulk deformation", np);
  const double time = in.real("hair time");
  // All read: now the body takes it.
  strands_ = std::move(strands);
  grips_ = std::move(grips);
  next_grip_ = next_grip;
  particles_.mass = std::move(mass);
  particles_.C = std::move(C);
  particles_.F = std::move(F);
  for (const Strand& s : strands_)
    for (int i = 0; i < s.rod.numVertices(); ++i) {
      particles_.x[s.offset + i] = s.rod.positions()[i];
      particles_.v[s.offset + i] = s.v[i];
    }
  time_ = time;
}

std::unique_ptr<DynamicsSnapshot> HairDynamics::snapshot() const {
  auto s = std::make_unique<HairSnapshot>();
  for (const Strand& strand : strands_) {
    s->rods.push_back(strand.rod);
    s->v.push_back(strand.v);
    s->accel.push_back(strand.accel);
    s->omega.push_back(strand.omega);
    s->poses.push_back(strand.pose);
  }
  for (const auto& [id, g] : grips_) s->grip_motions[id] = g.motion;
  s->C = particles_.C;
  s->F = particles_.F;
  s->time = time_;
  return s;
}

void HairDynamics::restore(const DynamicsSnapshot& snapshot) {
  const auto* s = dynamic_cast<const HairSnapshot*>(&snapshot);
  if (!s) throw InputError("hair: snapshot of another body");
  if (s->rods.size() != strands_.size())
    throw InputError("hair: snapshot of " + std::to_string(s->rods.size()) + " strands for " +
                     std::to_string(strands_.size()));
  for (std::size_t k = 0; k < strands_.size(); ++k) {
    Strand& strand = strands_[k];
    strand.rod = s->rods[k];
    strand.v = s->v[k];
    strand.accel = s->accel[k];
    strand.omega = s->omega[k];
    strand.pose = s->poses[k];
    for (int i = 0; i < strand.rod.numVertices(); ++i) {
      particles_.x[strand.offset + i] = strand.rod.positions()[i];
      particles_.v[strand.offset + i] = strand.v[i];
    }
  }
  // Grips back at their motion then, as the clamps' root frames: a step redone in parts (a
  // caller's rollback) does not take the whole step's move of the grip in its first part.
  for (auto& [id, g] : grips_) {
    const auto it = s->grip_motions.find(id);
    if (it != s->grip_motions.end()) g.motion = it->second;
  }
  particles_.C = s->C;
  particles_.F = s->F;
  time_ = s->time;
}

}  // namespace chs::rod
