#include "cloth_hair_sim/node/sim_node.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <tuple>

#include <geometry_msgs/WrenchStamped.h>
#include <rosgraph_msgs/Clock.h>
#include <tf2_eigen/tf2_eigen.h>
#include <visualization_msgs/MarkerArray.h>

#include "cloth_hair_sim/SimStatus.h"
#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/common/names.h"
#include "cloth_hair_sim/core/io/scene.h"
#include "cloth_hair_sim/core/io/state_file.h"
#include "cloth_hair_sim/node/garment_mesh.h"
#include "cloth_hair_sim/node/markers.h"
#include "cloth_hair_sim/node/state_io.h"
#include "cloth_hair_sim/node/urdf_colliders.h"

namespace chs_node {
namespace {

using Clock = std::chrono::steady_clock;

// Back faces of garment markers sit this far behind the front ones [m]: far enough for rviz's
// depth buffer at room scale, too little to see.
constexpr double kBackFaceOffset = 5e-4;

double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

std::vector<TrackedCollider> collidersParam(const ros::NodeHandle& pnh) {
  XmlRpc::XmlRpcValue list;
  if (!pnh.getParam("colliders", list)) return {};
  return parseColliders(list);
}

}  // namespace

SimNode::SimNode(ros::NodeHandle nh, ros::NodeHandle private_nh)
    : nh_(nh),
      pnh_(private_nh),
      params_(loadSimParams(private_nh)),
      tf_listener_(tf_buffer_),
      colliders_(tf_buffer_, params_.world_frame, params_.tf_timeout, params_.tf_max_age) {
  pnh_.param("tf_delay", tf_delay_, tf_delay_);
  if (!(tf_delay_ >= 0.0) || !std::isfinite(tf_delay_))
    throw chs::InputError("parameter tf_delay must be >= 0 (s)");
  colliders_.setColliders(withUrdfColliders(pnh_, collidersParam(pnh_)));

  world_ = chs::World(params_.world);
  const ros::NodeHandle hair(pnh_, "hair");
  hair.param("display_strands", hair_display_strands_, hair_display_strands_);
  hair.param("colour", hair_colour_, hair_colour_);
  hair.param("line_width", hair_line_width_, hair_line_width_);
  hair.param("grid_spacing", hair_grid_spacing_, hair_grid_spacing_);
  if (hair_display_strands_ < 0 || hair_display_strands_ > chs::rod::kMaxDisplayStrands)
    throw chs::InputError("parameter ~hair/display_strands must be 0.." +
                          std::to_string(chs::rod::kMaxDisplayStrands));
  if (hair_colour_.size() != 4)
    throw chs::InputError("parameter ~hair/colour must be [r, g, b, a] in 0..1");
  for (float c : hair_colour_)
    if (!(c >= 0.0f && c <= 1.0f))
      throw chs::InputError("parameter ~hair/colour must be [r, g, b, a] in 0..1");
  if (!(hair_line_width_ > 0.0) || !std::isfinite(hair_line_width_))
    throw chs::InputError("parameter ~hair/line_width must be positive (m)");
  if (!(hair_grid_spacing_ > 0.0) || !std::isfinite(hair_grid_spacing_))
    throw chs::InputError("parameter ~hair/grid_spacing must be positive (m)");
  const ros::NodeHandle continuum(hair, "continuum");
  chs::rod::StrandContinuumSettings& c = hair_continuum_;
  continuum.param("enabled", c.enabled, c.enabled);
  continuum.param("youngs_modulus", c.youngs_modulus, c.youngs_modulus);
  continuum.param("poisson_ratio", c.poisson_ratio, c.poisson_ratio);
  continuum.param("friction", c.friction, c.friction);
  continuum.param("contact_blend", c.contact_blend, c.contact_blend);
  try {  // the core checks them
    chs::rod::HairSettings check;
    check.continuum = c;
    chs::rod::HairDynamics{check};
  } catch (const chs::InputError& e) {
    throw chs::InputError(std::string("parameter ~hair/continuum: ") + e.what());
  }
  for (const auto& c : colliders_.colliders()) {
    try {
      chs::checkName(c.name);
    } catch (const chs::InputError& e) {  // a URDF link's name need not be a topic name
      ROS_WARN("collider '%s': no ~collider_wrench topic: %s", c.name.c_str(), e.what());
      continue;
    }
    collider_wrench_pubs_[c.name] =
        pnh_.advertise<geometry_msgs::WrenchStamped>("collider_wrench/" + c.name, 10);
  }
  status_pub_ = pnh_.advertise<cloth_hair_sim::SimStatus>("status", 10);
  marker_pub_ = pnh_.advertise<visualization_msgs::MarkerArray>("markers", 1);
  refreshCatalogue();  // and load_params_, before load_garment can read them
  load_srv_ = pnh_.advertiseService("load_garment", &SimNode::loadGarment, this);
  remove_srv_ = pnh_.advertiseService("remove_garment", &SimNode::removeGarment, this);
  list_srv_ = pnh_.advertiseService("list_garments", &SimNode::listGarments, this);
  load_hair_srv_ = pnh_.advertiseService("load_hair", &SimNode::loadHair, this);
  remove_hair_srv_ = pnh_.advertiseService("remove_hair", &SimNode::removeHair, this);
  reset_srv_ = pnh_.advertiseService("reset", &SimNode::reset, this);
  pause_srv_ = pnh_.advertiseService("pause", &SimNode::pause, this);
  step_srv_ = pnh_.advertiseService("step", &SimNode::step, this);
  drape_srv_ = pnh_.advertiseService("drape_solve", &SimNode::drapeSolve, this);
  grasp_srv_ = pnh_.advertiseService("grasp", &SimNode::grasp, this);
  release_srv_ = pnh_.advertiseService("release", &SimNode::release, this);
  save_state_srv_ = pnh_.advertiseService("save_state", &SimNode::saveState, this);
  load_state_srv_ = pnh_.advertiseService("load_state", &SimNode::loadState, this);
  timer_nh_ = nh_;
  timer_nh_.setCallbackQueue(&timer_queue_);
  if (params_.publish_clock) {
    // Under /use_sim_time a ros::Timer waits for /clock, which this node publishes: it steps on
    // wall time instead. The clock starts at the wall time, so stamps look like a live run's.
    if (!ros::Time::isSimTime())
      ROS_WARN("~publish_clock is set but /use_sim_time is not: other nodes ignore /clock");
    clock_pub_ = nh_.advertise<rosgraph_msgs::Clock>("/clock", 10);
    clock_ = ros::Time(ros::WallTime::now().toSec());
    advanceClock(0.0);
    clock_timer_ = timer_nh_.createWallTimer(ros::WallDuration(1.0 / params_.step_rate),
                                             &SimNode::onClockTimer, this);
  } else {
    step_timer_ =
        timer_nh_.createTimer(ros::Duration(1.0 / params_.step_rate), &SimNode::onStepTimer, this);
  }
  status_timer_ = timer_nh_.createTimer(ros::Duration(1.0 / params_.status_rate),
                                        &SimNode::onStatusTimer, this);
  marker_timer_ = timer_nh_.createTimer(ros::Duration(1.0 / params_.marker_rate),
                                        &SimNode::onMarkerTimer, this);
  diagnostics_ = std::make_unique<SimDiagnostics>(timer_nh_, pnh_, params_.real_time_factor,
                                                  [this] { return healthSample(); });
  drape_action_ = std::make_unique<DrapeAction>(
      pnh_, [this](const auto& req, auto& res, const auto& progress, const auto* cancel) {
        return drape(req, res, progress, cancel);
      });
  ROS_INFO(
      "cloth_hair_sim_node: world frame '%s', %zu colliders, backend %s, dt %g s, %g Hz, "
      "real-time factor %g",
      params_.world_frame.c_str(), colliders_.colliders().size(), params_.dynamics_backend.c_str(),
      params_.dt, params_.step_rate, params_.real_time_factor);
  startReconfigure();
  timer_spinner_ = std::make_unique<ros::AsyncSpinner>(1, &timer_queue_);
  timer_spinner_->start();
}

void SimNode::refreshColliders() {
  transforms_ok_ = colliders_.update();
  if (!transforms_ok_)
    ROS_WARN_THROTTLE(5.0, "colliders without a transform to '%s' hold their last pose: %s",
                      params_.world_frame.c_str(), joined(colliders_.staleNames()).c_str());
  chs::RigidSurfaces surfaces;
  try {
    surfaces = colliders_.surfaces();
  } catch (const std::exception& e) {  // a degenerate transform: keep the previous surfaces
    ROS_ERROR_THROTTLE(5.0, "colliders not updated: %s", e.what());
    return;
  }
  const std::vector<double> frictions = colliders_.frictions();
  setColliders(surfaces, {}, frictions);
  active_colliders_.clear();
  for (const auto& c : colliders_.colliders())
    if (c.has_pose) active_colliders_.push_back(c.name);
}

void SimNode::setColliders(const chs::RigidSurfaces& surfaces,
                           const std::vector<chs::SurfaceVelocity>& velocities,
                           const std::vector<double>& frictions) {
  for (auto& [name, g] : garments_)
    if (!g.body) g.dynamics->setColliders(surfaces, velocities, frictions);
  world_.setColliders(surfaces, velocities, frictions);
}

SimParams SimNode::garmentParams() const {
  SimParams p = params_;
  if (world_.gridSpacing() > 0.0) p.mpm.grid_spacing = world_.gridSpacing();
  return p;
}

chs::World SimNode::worldOf(const std::map<std::string, Garment>& garments,
                            const std::map<std::string, Hair>* hairs) const {
  chs::World world(params_.world);
  world.setColliders(colliders_.surfaces(), {}, colliders_.frictions());
  for (const auto& [name, g] : garments)
    if (g.body) world.add(name, g.body);
  for (const auto& [name, h] : hairs ? *hairs : hairs_) world.add(name, h.body);
  return world;
}

double SimNode::substepLimit() const {
  // The world's bound holds its bodies' own (with their margins and CFL conditions) and how fast
  // the bodies approach each other; a garment outside the world (the particle model) has its own.
  double h = std::min(params_.dt, world_.stableTimeStep());
  for (const auto& [name, g] : garments_)
    if (!g.body) h = std::min(h, g.dynamics->stableTimeStep());
  return h;
}

bool SimNode::diverged(const Garment& g) const {
  const auto& x = g.dynamics->positions();
  const auto& v = g.dynamics->velocities();
  for (size_t i = 0; i < x.size(); ++i)
    if (!x[i].allFinite() || !v[i].allFinite() || v[i].norm() > params_.max_speed) return true;
  return false;
}

void SimNode::stepGarment(Garment& g, double h, int depth) {
  const std::unique_ptr<chs::DynamicsSnapshot> before = g.dynamics->snapshot();
  g.dynamics->step(h);
  if (const auto* shell = dynamic_cast<const chs::HybridShellDynamics*>(g.dynamics.get());
      shell && shell->settings().integration == chs::TimeIntegration::kBackwardEuler &&
      !shell->lastImplicitSolve().converged()) {
    ++unconverged_solves_;
    ROS_WARN_THROTTLE(5.0, "garment '%s': implicit solve %s; redone with explicit substeps",
                      g.name.c_str(), shell->lastImplicitSolve().describe().c_str());
  }
  if (!diverged(g)) return;
  g.dynamics->restore(*before);
  ++rollbacks_;
  if (depth < 4) {
    stepGarment(g, 0.5 * h, depth + 1);
    stepGarment(g, 0.5 * h, depth + 1);
    return;
  }
  // Still diverging at a sixteenth of the step: stop the garment where it was rather than
  // publish garbage; the node carries on.
  ++g.diverged_stops;
  g.dynamics->setVelocities(
      std::vector<Eigen::Vector3d>(g.dynamics->numVertices(), Eigen::Vector3d::Zero()));
  ROS_ERROR_THROTTLE(5.0, "garment '%s' diverges even at dt %g s: stopped in place", g.name.c_str(),
                     h);
}

void SimNode::stepWorld(double h, int depth) {
  if (world_.numBodies() == 0) return;
  const chs::World::Snapshot before = world_.snapshot();
  const chs::WorldStepReport report = world_.step(h);
  std::vector<Garment*> diverging;
  for (auto& [name, g] : garments_)
    if (g.body && diverged(g)) diverging.push_back(&g);
  std::vector<Hair*> diverging_hair;
  for (auto& [name, hair] : hairs_)
    if (diverged(hair)) diverging_hair.push_back(&hair);
  if (diverging.empty() && diverging_hair.empty() && report.converged) {
    addColliderLoads(h);
    return;
  }
  // A diverged step, or an implicit solve short of its tolerance (whose iterate can let layers
  // pass through each other): the whole world goes back and takes the step as two halves.
  world_.restore(before);
  if (!report.converged) {
    ++unconverged_solves_;
    ROS_WARN_THROTTLE(5.0,
                      "garments %s: implicit solve short of its tolerance at dt %g s; redone "
                      "as two half steps",
                      joined(report.unconverged).c_str(), h);
  }
  if (!diverging.empty() || !diverging_hair.empty()) ++rollbacks_;
  if (depth < 4) {
    stepWorld(0.5 * h, depth + 1);
    stepWorld(0.5 * h, depth + 1);
    return;
  }
  if (diverging.empty() &&
      diverging_hair.empty()) {  // the solve still falls short at a sixteenth: its iterate is kept
    world_.step(h);
    addColliderLoads(h);
    return;
  }
  // Still diverging at a sixteenth of the step: those garments stop where they were and the
  // world waits for them this substep rather than publish garbage; the node carries on.
  for (Garment* g : diverging) {
    ++g->diverged_stops;
    g->dynamics->setVelocities(
        std::vector<Eigen::Vector3d>(g->dynamics->numVertices(), Eigen::Vector3d::Zero()));
    ROS_ERROR_THROTTLE(5.0, "garment '%s' diverges even at dt %g s: stopped in place",
                       g->name.c_str(), h);
  }
  for (Hair* hair : diverging_hair) {
    ++hair->diverged_stops;
    for (int s = 0; s < hair->body->numStrands(); ++s)
      hair->body->setVelocities(s, std::vector<Eigen::Vector3d>(hair->body->strand(s).numVertices(),
                                                                Eigen::Vector3d::Zero()));
    ROS_ERROR_THROTTLE(5.0, "hair '%s' diverges even at dt %g s: stopped in place",
                       hair->name.c_str(), h);
  }
}

void SimNode::addColliderLoads(double h) {
  const std::vector<chs::ColliderLoad> loads = world_.colliderLoads();
  for (std::size_t c = 0; c < loads.size() && c < active_colliders_.size(); ++c) {
    ColliderLoadSum& sum = collider_loads_[active_colliders_[c]];
    sum.force += h * loads[c].force;
    sum.moment += h * loads[c].moment;
    sum.duration += h;
  }
}

void SimNode::publishColliderWrenches() {
  const ros::Time now = ros::Time::now();
  for (const auto& c : colliders_.colliders()) {
    const auto pub = collider_wrench_pubs_.find(c.name);
    const auto sum = collider_loads_.find(c.name);
    if (!c.has_pose || pub == collider_wrench_pubs_.end() || sum == collider_loads_.end() ||
        sum->second.duration <= 0.0)
      continue;
    // What the collider takes from the garments over the update, in its own frame about its
    // origin, as a force-torque sensor in the link would report it.
    chs::ColliderLoad mean;
    mean.force = sum->second.force / sum->second.duration;
    mean.moment = sum->second.moment / sum->second.duration;
    // The frame where the update left the collider (behind its tf pose while inputs lag).
    const auto from = collider_from_.find(c.name);
    const Eigen::Isometry3d& pose =
        from == collider_from_.end() ? c.world_from_frame : from->second;
    const Eigen::Matrix3d r = pose.linear();
    const Eigen::Vector3d f = r.transpose() * mean.force;
    const Eigen::Vector3d t = r.transpose() * mean.momentAbout(pose.translation());
    geometry_msgs::WrenchStamped msg;
    msg.header.stamp = now;
    msg.header.frame_id = c.frame_id;
    msg.wrench.force.x = f.x();
    msg.wrench.force.y = f.y();
    msg.wrench.force.z = f.z();
    msg.wrench.torque.x = t.x();
    msg.wrench.torque.y = t.y();
    msg.wrench.torque.z = t.z();
    pub->second.publish(msg);
  }
  collider_loads_.clear();
}

void SimNode::advance(int count, double h, double reach) {
  const double duration = count * h;
  // The inputs' motion from their start pose to their current one took this long.
  const double span = duration / reach;
  teleportJumps(span);
  // Kinematic inputs (tf-posed colliders, frame pins, grasps) move from their pose at the start
  // of the update towards the current one across its substeps, colliders with the matching
  // velocity: a frame that moved between updates neither jerks the cloth nor tunnels through it.
  const auto reached = [reach](const Eigen::Isometry3d& from, const Eigen::Isometry3d& to) {
    return reach >= 1.0 ? to : interpolate(from, to, reach);
  };
  struct Moving {
    const TrackedCollider* collider;
    Eigen::Isometry3d from;
  };
  std::vector<Moving> colliders;
  bool any_moving = false;
  for (const auto& c : colliders_.colliders()) {
    if (!c.has_pose) continue;
    const auto it = collider_from_.find(c.name);
    const Eigen::Isometry3d from = it == collider_from_.end() ? c.world_from_frame : it->second;
    any_moving = any_moving || from.matrix() != c.world_from_frame.matrix();
    colliders.push_back({&c, from});
  }
  std::vector<std::pair<Garment*, FrameAttachment*>> attached;
  for (auto& [name, g] : garments_)
    for (auto& a : g.frame_pins) attached.push_back({&g, &a});
  for (auto& [name, grasp] : grasps_) {
    const auto it = garments_.find(grasp.garment);
    if (it != garments_.end()) attached.push_back({&it->second, &grasp.attachment});
  }
  for (int i = 0; i < count; ++i) {
    const double alpha = reach * (i + 1) / count;
    for (auto& [g, a] : attached) a->pinAt(*g->dynamics, alpha);
    for (auto& [name, hair] : hairs_) hair.clampAt(alpha);
    for (auto& [name, grasp] : hair_grasps_) grasp.gripAt(*hairs_.at(grasp.hair).body, alpha);
    if (any_moving) {
      try {
        chs::RigidSurfaces surfaces;
        std::vector<chs::SurfaceVelocity> velocities;
        std::vector<double> frictions;
        for (const auto& m : colliders) {
          frictions.push_back(m.collider->friction);
          const Eigen::Isometry3d to = m.collider->world_from_frame;
          const Eigen::Isometry3d pose = interpolate(m.from, to, alpha);
          surfaces.push_back(m.collider->shape.makeSurface(pose));
          velocities.push_back(rigidVelocity(m.from, to, span));
          velocities.back().origin = pose.translation();
        }
        setColliders(surfaces, velocities, frictions);
      } catch (const std::exception&) {  // refreshColliders has logged it: no interpolation
        any_moving = false;
      }
    }
    for (auto& [name, g] : garments_)
      if (!g.body) stepGarment(g, h, 0);
    stepWorld(h, 0);
    for (auto& [name, grasp] : grasps_) {
      const auto it = garments_.find(grasp.garment);
      if (it == garments_.end()) continue;
      const FrameAttachment& a = grasp.attachment;
      const chs::HoldingWrench w = chs::holdingWrench(
          *it->second.dynamics, a.vertices, interpolate(a.from, a.to, alpha).translation());
      grasp.sum.force += w.force;
      grasp.sum.torque += w.torque;
      ++grasp.samples;
    }
    for (auto& [name, grasp] : hair_grasps_) {
      const chs::HoldingWrench w =
          hairs_.at(grasp.hair)
              .body->gripWrench(grasp.grip, interpolate(grasp.from, grasp.to, alpha).translation());
      grasp.sum.force += w.force;
      grasp.sum.torque += w.torque;
      ++grasp.samples;
    }
    sim_time_ += h;
    ++steps_;
  }
  // The next update starts where this one ended.
  for (const auto& m : colliders)
    collider_from_[m.collider->name] = reached(m.from, m.collider->world_from_frame);
  for (auto& [g, a] : attached) a->from = reached(a->from, a->to);
  for (auto& [name, hair] : hairs_) hair.from = reached(hair.from, hair.to);
  for (auto& [name, grasp] : hair_grasps_) grasp.from = reached(grasp.from, grasp.to);
}

bool SimNode::lookupFrame(const std::string& frame, double timeout, Eigen::Isometry3d& pose,
                          std::string* error) {
  if (frame == params_.world_frame) {
    pose = Eigen::Isometry3d::Identity();
    return true;
  }
  // At a steady delay behind now (see tf_delay_); failing that (a frame published rarely or not
  // any more, the start), the latest pose.
  const ros::Time now = ros::Time::now();
  ros::Time time(0);
  if (tf_delay_ > 0.0 && now.toSec() > tf_delay_ &&
      tf_buffer_.canTransform(params_.world_frame, frame, now - ros::Duration(tf_delay_)))
    time = now - ros::Duration(tf_delay_);
  else if (!tf_buffer_.canTransform(params_.world_frame, frame, time, ros::Duration(timeout),
                                    error))
    return false;
  try {
    const geometry_msgs::TransformStamped t =
        tf_buffer_.lookupTransform(params_.world_frame, frame, time);
    if (tooOld(t.header.stamp, now, params_.tf_max_age)) {
      if (error) *error = "its latest transform is older than ~tf_max_age";
      return false;
    }
    pose = tf2::transformToEigen(t);
  } catch (const tf2::TransformException& e) {
    if (error) *error = e.what();
    return false;
  }
  if (pose.matrix().allFinite()) return true;
  if (error) *error = "the transform is not finite";
  return false;
}

void SimNode::refreshAttachments() {
  struct Lookup {
    bool ok = false;
    Eigen::Isometry3d pose;
  };
  std::map<std::string, Lookup> frames;  // one lookup per frame and update
  auto lookup = [&](const std::string& frame_id, const char* what) -> const Lookup& {
    auto it = frames.find(frame_id);
    if (it == frames.end()) {
      Lookup l;
      std::string error;
      l.ok = lookupFrame(frame_id, params_.tf_timeout, l.pose, &error);
      if (!l.ok)
        ROS_WARN_THROTTLE(5.0,
                          "frame '%s' of %s has no transform to '%s' (%s): they hold their "
                          "last pose",
                          frame_id.c_str(), what, params_.world_frame.c_str(), error.c_str());
      it = frames.emplace(frame_id, l).first;
    }
    transforms_ok_ = transforms_ok_ && it->second.ok;
    return it->second;
  };
  auto update = [&](FrameAttachment& a) {
    const Lookup& l = lookup(a.frame_id, "attached vertices");
    a.stale = !l.ok;
    if (l.ok) a.to = l.pose;
  };
  for (auto& [name, g] : garments_)
    for (auto& a : g.frame_pins) update(a);
  for (auto& [name, grasp] : grasps_) update(grasp.attachment);
  for (auto& [name, grasp] : hair_grasps_) {
    const Lookup& l = lookup(grasp.frame_id, "a grasped lock of hair");
    grasp.stale = !l.ok;
    if (l.ok) grasp.to = l.pose;
  }
  for (auto& [name, hair] : hairs_) {
    const Lookup& l = lookup(hair.frame_id, "hair roots");
    hair.stale = !l.ok;
    if (l.ok) hair.to = l.pose;
  }
}

void SimNode::publishGraspWrenches(double duration) {
  const ros::Time now = ros::Time::now();
  for (auto& [name, grasp] : grasps_) {
    const auto it = garments_.find(grasp.garment);
    if (it == garments_.end()) continue;
    const chs::ClothDynamics& dyn = *it->second.dynamics;
    const std::vector<int>& held = grasp.attachment.vertices;
    const Eigen::Isometry3d& frame = grasp.attachment.from;  // where the update left it
    chs::HoldingWrench hold;
    if (grasp.samples > 0) {
      hold.force = grasp.sum.force / grasp.samples;
      hold.torque = grasp.sum.torque / grasp.samples;
    } else {  // nothing simulated (paused): the wrench of the state as it is
      hold = chs::holdingWrench(dyn, held, frame.translation());
    }
    grasp.sum = chs::HoldingWrench();
    grasp.samples = 0;
    // The held vertices' mean acceleration over the update: the inertia the grasp also carries.
    std::vector<Eigen::Vector3d> velocity;
    for (int v : held) velocity.push_back(dyn.velocities()[v]);
    if (duration > 0.0) {
      if (grasp.last_velocity.size() == held.size())
        for (size_t k = 0; k < held.size(); ++k) {
          const Eigen::Vector3d f =
              dyn.masses()[held[k]] * (velocity[k] - grasp.last_velocity[k]) / duration;
          hold.force += f;
          hold.torque += (dyn.positions()[held[k]] - frame.translation()).cross(f);
        }
      grasp.last_velocity = velocity;
    }
    // The cloth pulls on the gripper with the opposite of the wrench that holds it; expressed
    // in the gripper frame, as a wrist force-torque sensor would report it.
    const Eigen::Vector3d f = frame.linear().transpose() * -hold.force;
    const Eigen::Vector3d t = frame.linear().transpose() * -hold.torque;
    geometry_msgs::WrenchStamped msg;
    msg.header.stamp = now;
    msg.header.frame_id = grasp.attachment.frame_id;
    msg.wrench.force.x = f.x();
    msg.wrench.force.y = f.y();
    msg.wrench.force.z = f.z();
    msg.wrench.torque.x = t.x();
    msg.wrench.torque.y = t.y();
    msg.wrench.torque.z = t.z();
    grasp.wrench_pub.publish(msg);
  }
  publishHairGraspWrenches();
}

std::vector<std::string> SimNode::dropGrasps(const std::string& garment) {
  return dropGraspsOf(grasps_, garment, [](const Grasp& g) { return g.garment; });
}

void SimNode::onStepTimer(const ros::TimerEvent& event) {
  const double period = 1.0 / params_.step_rate;
  double elapsed =
      event.last_real.isZero() ? period : (event.current_real - event.last_real).toSec();
  if (!(elapsed > 0.0)) elapsed = period;
  update(elapsed);
}

void SimNode::onClockTimer(const ros::WallTimerEvent& event) {
  const double period = 1.0 / params_.step_rate;
  double wall = event.last_real.isZero() ? period : (event.current_real - event.last_real).toSec();
  if (!(wall > 0.0)) wall = period;
  // The clock advances by what the update simulated; with nothing to step, at the requested
  // pace; paused, not at all (the world and everything moving with it wait; ~step advances it).
  const double idle = (params_.real_time_factor > 0.0 ? params_.real_time_factor : 1.0) * wall;
  const double simulated = update(wall);
  if (paused_) return;
  advanceClock(simulated > 0.0 ? simulated : idle);
}

void SimNode::advanceClock(double seconds) {
  clock_ += ros::Duration(seconds);
  rosgraph_msgs::Clock c;
  c.clock = clock_;
  clock_pub_.publish(c);
}

double SimNode::update(double elapsed) {
  const WorldLock lock(*this);
  refreshColliders();
  refreshAttachments();
  const double period = 1.0 / params_.step_rate;
  if (paused_ || (garments_.empty() &&
                  hairs_.empty())) {  // keeps the substep of the last ~step for the status
    input_lag_ = 0.0;
    last_.substeps = 0;
    last_.wall_per_step = last_.real_time_factor = 0.0;
    publishGraspWrenches(0.0);
    return 0.0;
  }
  // After a stall (a slow callback, a paused /clock) do not try to catch up all at once.
  const double budget = std::min(elapsed, 5.0 * period);
  const double h_max = substepLimit();
  int n = params_.max_substeps;
  double h = h_max;
  if (params_.real_time_factor > 0.0) {
    // With the inputs' motion still pending from earlier updates (input_lag_): caught up.
    const double target = params_.real_time_factor * budget + input_lag_;
    const double needed = std::ceil(target / h_max - 1e-9);
    if (needed <= params_.max_substeps) {
      n = std::max(1, static_cast<int>(needed));
      h = target / n;
    }
  }
  // No more substeps than fit in max_update_wall at the last update's cost: the update holds
  // mutex_, and a service call waiting for it (load_garment, list_garments, grasp) would
  // otherwise wait for max_substeps of a slow world, seconds. The simulation falls behind, and
  // the kinematic inputs with it (below): it does not jerk.
  // A cost not known yet (the first update, a garment just loaded) is probed with one substep.
  n = substep_cost_ > 0.0
          ? std::max(1, std::min(n, static_cast<int>(params_.max_update_wall / substep_cost_)))
          : 1;
  // Behind real time, the inputs keep their real speed in simulated time: squeezed into fewer
  // simulated seconds, a slow update (a rolled-back step) makes the next strike the cloth or
  // hair faster than the robot moved, which slows it further. Their motion pending from earlier
  // updates and this update's wall time is `span`; what the update does not simulate waits,
  // up to ~max_input_lag, for later updates to catch up (they simulate it on top of their own
  // time while their substeps allow).
  double reach = 1.0;
  if (params_.real_time_factor > 0.0 && !params_.publish_clock) {
    const double span = input_lag_ + params_.real_time_factor * elapsed;
    reach = n * h >= (1.0 - 1e-9) * span ? 1.0 : n * h / span;
    if (span * (1.0 - reach) > params_.max_input_lag) reach = 1.0 - params_.max_input_lag / span;
    input_lag_ = span * (1.0 - reach);
  }
  const Clock::time_point start = Clock::now();
  advance(n, h, reach);
  const double wall = secondsSince(start);
  last_.dt = h;
  last_.substeps = n;
  last_.wall_per_step = substep_cost_ = wall / n;
  last_.real_time_factor = n * h / std::max(elapsed, wall);
  publishGraspWrenches(n * h);
  publishColliderWrenches();
  return n * h;
}

void SimNode::onStatusTimer(const ros::TimerEvent&) {
  cloth_hair_sim::SimStatus s;
  {
    const WorldLock lock(*this);
    s.header.stamp = ros::Time::now();
    s.header.frame_id = params_.world_frame;
    s.state = garments_.empty() && hairs_.empty() ? "idle" : paused_ ? "paused" : "running";
    s.sim_time = sim_time_;
    s.steps = steps_;
    s.dt = last_.dt;
    s.substeps = last_.substeps;
    s.wall_time_per_step = last_.wall_per_step;
    s.real_time_factor = last_.real_time_factor;
    s.input_lag = input_lag_;
    s.garments = static_cast<int>(garments_.size());
    s.colliders = colliders_.activeCount();
    s.dynamics_backend = params_.dynamics_backend;
    for (const auto& [name, g] : garments_) {
      s.vertices += g.dynamics->numVertices();
      s.kinetic_energy += g.dynamics->kineticEnergy();
      if (const auto* h = dynamic_cast<const chs::HybridShellDynamics*>(g.dynamics.get())) {
        s.particles += h->numVertices() + h->numContactParticles();
        s.quadrature_points += h->numQuadraturePoints();
        s.grid_nodes += h->numGridNodes();
      } else {
        s.particles += g.dynamics->numVertices();
      }
      // Positions are finite here: a diverged substep is rolled back before it is kept.
      s.deepest_penetration = std::max(s.deepest_penetration, g.dynamics->deepestPenetration());
    }
    for (const auto& [name, h] : hairs_) {
      s.vertices += h.numVertices();
      s.particles += h.numVertices();
      s.kinetic_energy += h.body->kineticEnergy();
    }
    s.rollbacks = rollbacks_;
    s.unconverged_solves = unconverged_solves_;
    s.transforms_ok = transforms_ok_;
    s.stale_colliders = colliders_.staleNames();
    for (const auto& [name, grasp] : grasps_) s.grasps.push_back(name);
    for (const auto& [name, grasp] : hair_grasps_) s.grasps.push_back(name);
  }
  s.drape_running = drape_running_;
  status_pub_.publish(s);
}

void SimNode::onMarkerTimer(const ros::TimerEvent&) {
  visualization_msgs::MarkerArray array;
  visualization_msgs::Marker clear;  // removed garments and colliders disappear
  clear.action = visualization_msgs::Marker::DELETEALL;
  array.markers.push_back(clear);
  {
    const WorldLock lock(*this);
    const ros::Time now = ros::Time::now();
    for (const auto& [name, g] : garments_) {
      const chs::DisplaySurface surface = g.dynamics->displaySurface();
      for (auto& m : garmentMarkers(surface, g.colour, g.colour, kBackFaceOffset))
        array.markers.push_back(std::move(m));
      if (g.mesh_pub.getNumSubscribers() == 0) continue;
      cloth_hair_sim::GarmentMesh mesh = garmentMeshMessage(name, *g.dynamics, surface);
      mesh.header.stamp = now;
      mesh.header.frame_id = params_.world_frame;
      g.mesh_pub.publish(mesh);
    }
    int hair_id = 0;
    for (const auto& [name, h] : hairs_)
      array.markers.push_back(hairMarker(h, hair_id++, hair_colour_, hair_line_width_));
    if (params_.show_colliders) {
      int id = 0;
      for (const auto& c : colliders_.colliders()) {
        if (c.has_pose) array.markers.push_back(colliderMarker(c, id));
        ++id;
      }
    }
  }
  const ros::Time now = ros::Time::now();
  for (auto& m : array.markers) {
    m.header.stamp = now;
    m.header.frame_id = params_.world_frame;
  }
  marker_pub_.publish(array);
}

bool SimNode::loadGarment(cloth_hair_sim::LoadGarment::Request& req,
                          cloth_hair_sim::LoadGarment::Response& res) {
  res.success = false;
  const std::string who = "garment '" + req.name + "': ";
  try {
    chs::checkName(req.name);
  } catch (const chs::InputError& e) {
    res.message = who + e.what();
    ROS_WARN("%s", res.message.c_str());
    return true;
  }
  if (nameTaken(req.name)) {
    res.message = who + "a garment or hair of that name is loaded; remove it first";
    return true;
  }
  std::map<std::string, Eigen::Isometry3d> attach_frames;
  for (const auto& group : req.attached) {
    if (group.frame_id.empty() || attach_frames.count(group.frame_id)) continue;
    std::string error;
    if (!lookupFrame(group.frame_id, 0.5, attach_frames[group.frame_id], &error)) {
      res.message = who + "attached pins: frame '" + group.frame_id + "' has no transform to '" +
                    params_.world_frame + "' (" + error + ")";
      return true;
    }
  }
  Eigen::Isometry3d world_from_frame = Eigen::Isometry3d::Identity();
  if (!req.frame_id.empty() && req.frame_id != params_.world_frame) {
    std::string error;
    if (!tf_buffer_.canTransform(params_.world_frame, req.frame_id, ros::Time(0),
                                 ros::Duration(0.5), &error)) {
      res.message = who + "frame '" + req.frame_id + "' has no transform to '" +
                    params_.world_frame + "' (" + error + ")";
      return true;
    }
    try {
      world_from_frame = tf2::transformToEigen(
          tf_buffer_.lookupTransform(params_.world_frame, req.frame_id, ros::Time(0)));
    } catch (const tf2::TransformException& e) {
      res.message = who + "frame '" + req.frame_id + "': " + e.what();
      return true;
    }
  }
  try {
    SimParams params;
    {
      std::lock_guard<std::mutex> pending(pending_mutex_);
      params = load_params_;
    }
    Garment g = buildGarment(req, world_from_frame, attach_frames, params);
    g.mesh_pub = pnh_.advertise<cloth_hair_sim::GarmentMesh>("garments/" + req.name + "/mesh", 1);
    res.vertices = g.reference.mesh.numVertices();
    res.faces = g.reference.mesh.numQuads();
    const std::string loaded = who + "loaded, " + std::to_string(res.vertices) + " vertices, " +
                               std::to_string(res.faces) + " quads, material " + g.material_name;
    std::unique_lock<std::mutex> world(mutex_, std::try_to_lock);
    if (world.owns_lock()) {
      applyPendingEdits();
      if (garments_.count(req.name) || hairs_.count(req.name)) {
        res.message = who + "a garment or hair of that name was loaded meanwhile";
        return true;
      }
      insertGarment(req.name, std::move(g));
      refreshCatalogue();
      res.message = loaded;
    } else {
      // The world is stepping: the garment joins it at the next WorldLock. Its name is checked
      // against the catalogue (garments_ and hairs_ as of the last change) and the queue.
      std::lock_guard<std::mutex> pending(pending_mutex_);
      std::lock_guard<std::mutex> listed(catalogue_mutex_);
      if (std::count(catalogue_.names.begin(), catalogue_.names.end(), req.name)) {
        res.message = who + "a garment or hair of that name was loaded meanwhile";
        return true;
      }
      // The world's particle budget, as World::add checks it, with the queue's loads counted.
      if (g.body) {
        long queued = world_particles_;
        for (const PendingEdit& edit : pending_edits_)
          if (edit.garment && edit.garment->body)
            queued += static_cast<long>(edit.garment->body->motion().x.size());
        const long particles = static_cast<long>(g.body->motion().x.size());
        if (particles > load_params_.world.max_particles - queued) {
          res.message = who + "its " + std::to_string(particles) +
                        " particles would bring the world to " +
                        std::to_string(queued + particles) + ", over ~mpm/max_particles " +
                        std::to_string(load_params_.world.max_particles);
          ROS_WARN("%s", res.message.c_str());
          return true;
        }
      }
      catalogue_.names.push_back(req.name);
      catalogue_.vertices.push_back(g.dynamics->numVertices());
      catalogue_.materials.push_back(g.material_name);
      catalogue_.kinds.push_back("garment");
      // The first body of an empty world sets its grid: later loads are built on it.
      if (load_params_.mpm.grid_spacing <= 0.0 && g.body)
        load_params_.mpm.grid_spacing = g.body->field().spacing();
      pending_edits_.push_back({req.name, std::move(g)});
      res.message = loaded + " (joins the stepping world at its next substep)";
    }
    res.success = true;
  } catch (const std::exception& e) {
    res.message = who + e.what();
  }
  if (res.success)
    ROS_INFO("%s", res.message.c_str());
  else
    ROS_WARN("%s", res.message.c_str());
  return true;
}

void SimNode::insertGarment(const std::string& name, Garment g) {
  if (g.body) world_.add(name, g.body);  // refuses a garment that does not fit the grid
  g.generation = next_generation_++;
  g.colour = next_colour_++;
  g.dynamics->setColliders(colliders_.surfaces(), {}, colliders_.frictions());
  garments_.emplace(name, std::move(g));
  substep_cost_ = 0.0;  // the world grew: the next update probes its cost
}

void SimNode::applyPendingEdits() {
  std::vector<PendingEdit> edits;
  {
    std::lock_guard<std::mutex> lock(pending_mutex_);
    edits.swap(pending_edits_);
  }
  if (edits.empty()) return;
  // The catalogue is refreshed once, after the whole batch: refreshed after each edit, it would
  // list the batch's later removals again (in garments_ still, out of pending_edits_ already).
  for (PendingEdit& edit : edits) {
    if (!edit.garment) {
      const std::vector<std::string> dropped = eraseGarment(edit.name);
      const std::string grasps = dropped.empty() ? "" : "; grasps released: " + joined(dropped);
      ROS_INFO("garment '%s': left the world%s", edit.name.c_str(), grasps.c_str());
      continue;
    }
    try {
      if (garments_.count(edit.name) || hairs_.count(edit.name))
        throw chs::InputError("a garment or hair of that name was loaded meanwhile");
      insertGarment(edit.name, std::move(*edit.garment));
    } catch (const std::exception& e) {
      // The load had answered success: say loudly that it was dropped after all.
      ROS_ERROR("garment '%s': dropped before it joined the world: %s", edit.name.c_str(),
                e.what());
    }
  }
  refreshCatalogue();
}

std::vector<std::string> SimNode::eraseGarment(const std::string& name) {
  garments_.erase(name);
  world_.remove(name);
  return dropGrasps(name);
}

bool SimNode::removeGarment(cloth_hair_sim::RemoveGarment::Request& req,
                            cloth_hair_sim::RemoveGarment::Response& res) {
  const std::string who = "garment '" + req.name + "': ";
  std::unique_lock<std::mutex> world(mutex_, std::try_to_lock);
  if (!world.owns_lock()) {
    // The world is stepping: the garment leaves it at the next WorldLock.
    std::lock_guard<std::mutex> pending(pending_mutex_);
    std::lock_guard<std::mutex> listed(catalogue_mutex_);
    auto& c = catalogue_;
    std::size_t i = 0;
    while (i < c.names.size() && !(c.names[i] == req.name && c.kinds[i] == "garment")) ++i;
    res.success = i < c.names.size();
    if (res.success) {
      c.names.erase(c.names.begin() + i);
      c.vertices.erase(c.vertices.begin() + i);
      c.materials.erase(c.materials.begin() + i);
      c.kinds.erase(c.kinds.begin() + i);
      pending_edits_.push_back({req.name, std::nullopt});
    }
    std::vector<std::string> grasps;
    for (const auto& [grasp, garment] : grasped_garments_)
      if (garment == req.name) grasps.push_back(grasp);
    res.message = who + (res.success ? "removed (leaves the stepping world at its next substep, "
                                       "its grasps with it)"
                                     : "not loaded");
    if (res.success && !grasps.empty()) res.message += "; grasps released: " + joined(grasps);
    return true;
  }
  applyPendingEdits();
  res.success = garments_.count(req.name) > 0;
  const std::vector<std::string> dropped = eraseGarment(req.name);
  refreshCatalogue();
  res.message = who + (res.success ? "removed" : "not loaded");
  if (!dropped.empty()) res.message += "; grasps released: " + joined(dropped);
  return true;
}

void SimNode::refreshCatalogue() {
  cloth_hair_sim::ListGarments::Response list;
  for (const auto& [name, g] : garments_) {
    list.names.push_back(name);
    list.vertices.push_back(g.dynamics->numVertices());
    list.materials.push_back(g.material_name);
    list.kinds.push_back("garment");
  }
  for (const auto& [name, h] : hairs_) {
    list.names.push_back(name);
    list.vertices.push_back(h.numVertices());
    list.materials.push_back(h.material_name);
    list.kinds.push_back("hair");
  }
  std::lock_guard<std::mutex> pending(pending_mutex_);
  load_params_ = garmentParams();
  world_particles_ = world_.numParticles();
  for (const PendingEdit& edit : pending_edits_) {
    if (!edit.garment) {
      for (std::size_t i = 0; i < list.names.size(); ++i)
        if (list.names[i] == edit.name && list.kinds[i] == "garment") {
          list.names.erase(list.names.begin() + i);
          list.vertices.erase(list.vertices.begin() + i);
          list.materials.erase(list.materials.begin() + i);
          list.kinds.erase(list.kinds.begin() + i);
          break;
        }
      continue;
    }
    const Garment& g = *edit.garment;
    if (load_params_.mpm.grid_spacing <= 0.0 && g.body)
      load_params_.mpm.grid_spacing = g.body->field().spacing();
    list.names.push_back(edit.name);
    list.vertices.push_back(g.dynamics->numVertices());
    list.materials.push_back(g.material_name);
    list.kinds.push_back("garment");
  }
  std::vector<std::pair<std::string, std::string>> grasped;
  for (const auto& [name, grasp] : grasps_) grasped.emplace_back(name, grasp.garment);
  std::lock_guard<std::mutex> lock(catalogue_mutex_);
  catalogue_ = std::move(list);
  grasped_garments_ = std::move(grasped);
}

bool SimNode::nameTaken(const std::string& name) {
  std::lock_guard<std::mutex> lock(catalogue_mutex_);
  return std::count(catalogue_.names.begin(), catalogue_.names.end(), name) > 0;
}

bool SimNode::listGarments(cloth_hair_sim::ListGarments::Request&,
                           cloth_hair_sim::ListGarments::Response& res) {
  std::lock_guard<std::mutex> lock(catalogue_mutex_);
  res = catalogue_;
  return true;
}

bool SimNode::reset(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
  // The garments' fresh states are built before the world is held: a shell builds its elastic
  // solve with it (0.8 s for a 90 x 90 sheet), and the world's steps and the other services
  // would wait for that. A garment loaded, reset or changed in the meantime (a new generation)
  // is built again under the lock.
  struct Fresh {
    std::uint64_t generation = 0;
    FreshDynamics state;
  };
  std::map<std::string, Fresh> fresh;
  try {
    std::vector<std::tuple<std::string, std::uint64_t, chs::DrapeProblem, std::optional<double>>>
        garments;
    SimParams params;
    {
      const WorldLock lock(*this);
      params = garmentParams();
      for (const auto& [name, g] : garments_)
        garments.emplace_back(name, g.generation, g.reference, g.self_friction);
    }
    for (const auto& [name, generation, reference, self_friction] : garments)
      fresh[name] = {generation, freshDynamics(reference, self_friction, params)};
  } catch (const std::exception& e) {
    res.success = false;
    res.message = e.what();  // nothing changed
    return true;
  }
  const WorldLock lock(*this);
  std::vector<std::string> released;
  try {
    const SimParams params = garmentParams();
    for (auto& [name, g] : garments_) {
      const auto built = fresh.find(name);
      if (built != fresh.end() && built->second.generation == g.generation) {
        g.dynamics = built->second.state.dynamics;
        g.body = built->second.state.body;
      } else {
        resetDynamics(g, params);
      }
      g.generation = next_generation_++;
      g.diverged_stops = 0;
      g.dynamics->setColliders(colliders_.surfaces(), {}, colliders_.frictions());
      // A garment hanging from frames restarts where its first frame has carried it since load
      // (pinned across one substep instead, its vertices would move faster than max_speed and
      // every retry would be rolled back); world pins stay where they are.
      if (!g.frame_pins.empty()) {
        const FrameAttachment& first = g.frame_pins.front();
        const Eigen::Isometry3d moved = first.to * first.attached_at.inverse();
        std::vector<Eigen::Vector3d> x = g.dynamics->positions();
        for (int v = 0; v < g.dynamics->numVertices(); ++v)
          if (!g.dynamics->isPinned(v)) x[v] = moved * x[v];
        for (auto& a : g.frame_pins)
          for (std::size_t k = 0; k < a.vertices.size(); ++k)
            x[a.vertices[k]] = a.to * a.offsets[k];
        g.dynamics->setPositions(x);
        for (auto& a : g.frame_pins) {
          a.from = a.to;
          a.pinAt(*g.dynamics, 1.0);
        }
      }
      // Grasps held the old state: released.
      for (const auto& n : dropGrasps(name)) released.push_back(n);
    }
    // Hair restarts at rest where its root frame is now.
    const chs::rod::HairSettings hair_settings = hairSettings();
    for (auto& [name, h] : hairs_) {
      for (const auto& n : dropHairGrasps(name)) released.push_back(n);  // grips of the old body
      rebuildHairBody(h, h.to, hair_settings);
    }
    world_ = worldOf(garments_);
  } catch (const std::exception& e) {
    world_ = worldOf(garments_);  // the garments reset before the failure, with the others
    refreshCatalogue();           // the grasps released before it
    res.success = false;
    res.message = e.what();
    return true;
  }
  sim_time_ = 0.0;
  steps_ = 0;
  rollbacks_ = 0;
  unconverged_solves_ = 0;
  last_ = UpdateStats();
  refreshCatalogue();  // the grasps it released
  res.success = true;
  res.message = "reset " + std::to_string(garments_.size()) + " garments to their reference and " +
                std::to_string(hairs_.size()) + " hair to rest";
  if (!released.empty()) res.message += "; grasps released: " + joined(released);
  return true;
}

bool SimNode::pause(std_srvs::SetBool::Request& req, std_srvs::SetBool::Response& res) {
  // Without mutex_: a pause asked during an update answers at once and holds the world from the
  // end of that update (~max_update_wall at most).
  paused_ = req.data;
  res.success = true;
  res.message = req.data ? "paused" : "running";
  return true;
}

bool SimNode::step(cloth_hair_sim::StepSim::Request& req, cloth_hair_sim::StepSim::Response& res) {
  const WorldLock lock(*this);
  res.success = false;
  if (!paused_) {
    res.message = "the simulation is running: pause it first (~pause true)";
  } else if (req.steps < 1 || req.steps > 1000000) {
    res.message = "steps must be between 1 and 1000000";
  } else {
    refreshColliders();
    refreshAttachments();
    const double h = substepLimit();
    advance(req.steps, h);
    if (params_.publish_clock) advanceClock(req.steps * h);
    publishGraspWrenches(req.steps * h);
    last_ = UpdateStats();
    last_.dt = h;
    last_.substeps = req.steps;
    res.success = true;
    res.message =
        "advanced " + std::to_string(req.steps) + " substeps of " + std::to_string(h) + " s";
  }
  res.sim_time = sim_time_;
  return true;
}

bool SimNode::drapeSolve(cloth_hair_sim::DrapeSolve::Request& req,
                         cloth_hair_sim::DrapeSolve::Response& res) {
  drape(req, res, {}, nullptr);
  return true;
}

bool SimNode::drape(const cloth_hair_sim::DrapeSolve::Request& req,
                    cloth_hair_sim::DrapeSolve::Response& res,
                    const chs::ProgressCallback& progress, const chs::CancelFlag* cancel) {
  res.success = res.converged = false;
  const std::string who = "drape of '" + req.garment + "': ";
  if (drape_running_.exchange(true)) {
    res.message = who + "another drape solve is running; try again when it is done";
    return false;
  }
  struct Release {
    std::atomic<bool>& flag;
    ~Release() { flag = false; }
  } release{drape_running_};

  chs::DrapeProblem problem;
  std::uint64_t generation = 0;
  {
    const WorldLock lock(*this);
    const auto it = garments_.find(req.garment);
    if (it == garments_.end()) {
      res.message = who + "no garment of that name is loaded";
      return false;
    }
    problem = it->second.reference;
    problem.colliders = colliders_.surfaces();
    generation = it->second.generation;
    drape_garment_ = req.garment;
    drape_started_ = Clock::now();
  }
  const Clock::time_point start = Clock::now();
  bool cancelled = false;
  try {
    const chs::DrapeMethod method = chs::parseMethod(req.method.empty() ? "fem_shell" : req.method);
    if (!(req.tolerance >= 0.0) || !std::isfinite(req.tolerance))
      throw chs::InputError("tolerance must be >= 0 (0: the solver's default)");
    if (req.max_iterations < 0) throw chs::InputError("max_iterations must be >= 0 (0: default)");
    if (!(req.stabilization >= 0.0) || !std::isfinite(req.stabilization))
      throw chs::InputError("stabilization must be >= 0");
    problem.checkStaticSupport();
    if (method != chs::DrapeMethod::kSolidShell &&
        (!req.scheme.empty() || req.adaptive_levels != 0))
      throw chs::InputError("scheme and adaptive_levels apply to method solid_shell only");
    if (req.coarse_levels < 0) throw chs::InputError("coarse_levels must be >= 0 (0: off)");
    if (method != chs::DrapeMethod::kFemShell && req.coarse_levels != 0)
      throw chs::InputError("coarse_levels applies to method fem_shell only");
    chs::DrapeResult r;
    if (method == chs::DrapeMethod::kFemShell) {
      chs::FemShellSettings s;
      if (req.tolerance > 0.0) s.tolerance = req.tolerance;
      if (req.max_iterations > 0) s.max_load_steps = s.max_iterations = req.max_iterations;
      s.stabilization = req.stabilization;
      s.coarse_levels = req.coarse_levels;
      s.cancel = cancel;
      r = chs::solveFemShell(problem, s, progress);
    } else if (method == chs::DrapeMethod::kSolidShell) {
      chs::SolidShellSettings s;
      // The energy scheme by default: the seed's multiplier scheme does not settle a cloth over a
      // table's edge (docs/VALIDATION.md).
      s.scheme = chs::parseSolidShellScheme(req.scheme.empty() ? "energy" : req.scheme);
      s.adaptive_levels = req.adaptive_levels;
      if (req.tolerance > 0.0) s.tolerance = req.tolerance;
      if (req.max_iterations > 0) s.max_iterations = req.max_iterations;
      s.cancel = cancel;
      r = chs::solveSolidShell(problem, s, progress);
    } else {
      chs::ParticleSettings s;
      if (req.tolerance > 0.0) s.displacement_tolerance = req.tolerance;
      if (req.max_iterations > 0) s.max_iterations = req.max_iterations;
      s.cancel = cancel;
      r = chs::solveParticleStatic(problem, s, progress);
    }
    cancelled = r.cancelled;
    res.converged = r.converged;
    res.iterations = r.iterations;
    res.residual = r.residual;
    res.message = who + r.status;
    // An adaptive solid shell answers on its finest background mesh, whose first vertices are
    // the garment's own (adaptive_mesh.h): the garment takes those.
    const chs::QuadMesh& solved = r.refined_mesh ? *r.refined_mesh : problem.mesh;
    const bool complete = static_cast<int>(r.positions.size()) == solved.numVertices() &&
                          std::all_of(r.positions.begin(), r.positions.end(),
                                      [](const Eigen::Vector3d& x) { return x.allFinite(); });
    if (complete) res.mesh = meshMessage(solved, r.positions);
    r.positions.resize(std::min<std::size_t>(r.positions.size(), problem.mesh.numVertices()));
    if (r.converged && complete) {
      const WorldLock lock(*this);
      const auto it = garments_.find(req.garment);
      if (it == garments_.end() || it->second.generation != generation) {
        res.message += "; not applied: the garment was removed, reloaded or reset meanwhile";
      } else {
        it->second.dynamics->setPositions(r.positions);
        it->second.dynamics->setVelocities(
            std::vector<Eigen::Vector3d>(r.positions.size(), Eigen::Vector3d::Zero()));
        res.success = true;
      }
    }
  } catch (const std::exception& e) {
    res.message = who + e.what();
  }
  res.wall_time = secondsSince(start);
  ROS_INFO("%s (%.2f s)", res.message.c_str(), res.wall_time);
  return cancelled;
}

bool SimNode::grasp(cloth_hair_sim::GraspGarment::Request& req,
                    cloth_hair_sim::GraspGarment::Response& res) {
  res.success = false;
  const std::string who = "grasp '" + req.name + "': ";
  try {
    chs::checkName(req.name);
  } catch (const chs::InputError& e) {
    res.message = who + e.what();
    return true;
  }
  std::string error;
  if (!(req.radius > 0.0) || !std::isfinite(req.radius)) {
    res.message = who + "radius must be positive and finite (m)";
    return true;
  }
  if (req.frame_id.empty()) {
    res.message = who + "needs the gripper's frame_id";
    return true;
  }
  Eigen::Isometry3d pose;
  if (!lookupFrame(req.frame_id, 0.5, pose, &error)) {
    res.message = who + "frame '" + req.frame_id + "' has no transform to '" + params_.world_frame +
                  "' (" + error + ")";
    return true;
  }
  const WorldLock lock(*this);
  const auto it = garments_.find(req.garment);
  const auto hair = hairs_.find(req.garment);
  if (grasps_.count(req.name) || hair_grasps_.count(req.name)) {
    res.message = who + "a grasp of that name is active; release it first";
  } else if (hair != hairs_.end()) {
    graspHair(req, pose, hair->second, res);
  } else if (it == garments_.end()) {
    res.message = who + "no garment '" + req.garment + "' is loaded (nor hair of that name)";
  } else {
    chs::ClothDynamics& dyn = *it->second.dynamics;
    const std::vector<int> held = freeVerticesNear(dyn, pose.translation(), req.radius);
    if (held.empty()) {
      double nearest = std::numeric_limits<double>::infinity();
      for (const auto& x : dyn.positions())
        nearest = std::min(nearest, (x - pose.translation()).norm());
      res.message = who + "no free vertex of '" + req.garment + "' within " +
                    std::to_string(req.radius) + " m of frame '" + req.frame_id +
                    "' (the nearest vertex is " + std::to_string(nearest) + " m away)";
    } else {
      Grasp g{req.name,
              req.garment,
              FrameAttachment(req.frame_id, held, dyn.positions(), pose),
              pnh_.advertise<geometry_msgs::WrenchStamped>("grasp_wrench/" + req.name, 10),
              {},
              {},
              0};
      g.attachment.pinAt(dyn, 1.0);  // held where they are, from now on
      res.vertices.assign(held.begin(), held.end());
      res.success = true;
      res.message = who + std::to_string(held.size()) + " vertices of '" + req.garment +
                    "' held by frame '" + req.frame_id + "'; wrench on " + g.wrench_pub.getTopic();
      grasps_.emplace(req.name, std::move(g));
      refreshCatalogue();
    }
  }
  if (res.success)
    ROS_INFO("%s", res.message.c_str());
  else
    ROS_WARN("%s", res.message.c_str());
  return true;
}

bool SimNode::release(cloth_hair_sim::ReleaseGrasp::Request& req,
                      cloth_hair_sim::ReleaseGrasp::Response& res) {
  const WorldLock lock(*this);
  if (const auto hg = hair_grasps_.find(req.name); hg != hair_grasps_.end()) {
    const auto h = hairs_.find(hg->second.hair);
    std::size_t n = 0;
    if (h != hairs_.end()) {
      n = h->second.body->gripVertices(hg->second.grip).size();
      h->second.body->removeGrip(hg->second.grip);
    }
    hg->second.wrench_pub.shutdown();
    res.success = true;
    res.message = "grasp '" + req.name + "': released " + std::to_string(n) +
                  " vertices of hair '" + hg->second.hair + "'";
    hair_grasps_.erase(hg);
    ROS_INFO("%s", res.message.c_str());
    return true;
  }
  const auto it = grasps_.find(req.name);
  res.success = it != grasps_.end();
  if (!res.success) {
    res.message = "grasp '" + req.name + "': no active grasp of that name";
    return true;
  }
  const auto g = garments_.find(it->second.garment);
  if (g != garments_.end()) it->second.attachment.unpin(*g->second.dynamics);
  it->second.wrench_pub.shutdown();
  res.message = "grasp '" + req.name + "': released " +
                std::to_string(it->second.attachment.vertices.size()) + " vertices of '" +
                it->second.garment + "'";
  grasps_.erase(it);
  refreshCatalogue();
  ROS_INFO("%s", res.message.c_str());
  return true;
}

bool SimNode::saveState(cloth_hair_sim::StateFile::Request& req,
                        cloth_hair_sim::StateFile::Response& res) {
  res.success = false;
  if (req.path.empty()) {
    res.message = "save_state: give the file's path";
    return true;
  }
  std::string payload, summary;
  {
    const WorldLock lock(*this);
    payload = encodeSimulation(params_.dynamics_backend,
                               {sim_time_, steps_, paused_, rollbacks_, unconverged_solves_},
                               garments_, grasps_, hairs_, hair_grasps_);
    // The saved run goes on from the same start as a reload of it will.
    for (auto& [name, g] : garments_) g.dynamics->dropSolverCaches();
    summary = std::to_string(garments_.size()) + " garments, " + std::to_string(hairs_.size()) +
              " hair, " + std::to_string(grasps_.size() + hair_grasps_.size()) +
              " grasps at sim time " + std::to_string(sim_time_) + " s";
  }
  try {  // the file is written without holding up the simulation
    chs::writeStateFile(req.path, payload);
    res.success = true;
    res.message = "saved " + summary + " to " + req.path;
    ROS_INFO("%s", res.message.c_str());
  } catch (const std::exception& e) {
    res.message = std::string("save_state: ") + e.what();
    ROS_WARN("%s", res.message.c_str());
  }
  return true;
}

bool SimNode::loadState(cloth_hair_sim::StateFile::Request& req,
                        cloth_hair_sim::StateFile::Response& res) {
  res.success = false;
  if (req.path.empty()) {
    res.message = "load_state: give the file's path";
    return true;
  }
  try {
    // Read, rebuilt and checked before the running simulation is touched.
    chs::rod::HairSettings hair_settings;
    {
      const WorldLock lock(*this);
      hair_settings = hairSettings();
    }
    SavedSimulation saved = readSimulation(req.path, params_, hair_settings, hair_display_strands_);
    const WorldLock lock(*this);
    const chs::RigidSurfaces surfaces = colliders_.surfaces();
    const std::vector<double> frictions = colliders_.frictions();
    for (auto& [name, g] : saved.garments) {
      g.dynamics->setColliders(surfaces, {}, frictions);
      g.mesh_pub = pnh_.advertise<cloth_hair_sim::GarmentMesh>("garments/" + name + "/mesh", 1);
      g.generation = next_generation_++;  // a drape solve of the old garment is not applied
      next_colour_ = std::max(next_colour_, g.colour + 1);
    }
    for (auto& [name, grasp] : grasps_) grasp.wrench_pub.shutdown();
    for (auto& [name, grasp] : saved.grasps)
      grasp.wrench_pub = pnh_.advertise<geometry_msgs::WrenchStamped>("grasp_wrench/" + name, 10);
    for (auto& [name, h] : saved.hairs) h.body->setColliders(surfaces, {}, frictions);
    // Refuses garments and hair that do not fit one grid (hair saved on another spacing).
    chs::World world = worldOf(saved.garments, &saved.hairs);
    for (auto& [name, grasp] : hair_grasps_) grasp.wrench_pub.shutdown();
    for (auto& [name, grasp] : saved.hair_grasps)
      grasp.wrench_pub = pnh_.advertise<geometry_msgs::WrenchStamped>("grasp_wrench/" + name, 10);
    garments_ = std::move(saved.garments);
    world_ = std::move(world);
    grasps_ = std::move(saved.grasps);
    hairs_ = std::move(saved.hairs);
    hair_grasps_ = std::move(saved.hair_grasps);
    refreshCatalogue();
    sim_time_ = saved.clock.sim_time;
    steps_ = saved.clock.steps;
    paused_ = saved.clock.paused;
    rollbacks_ = saved.clock.rollbacks;
    unconverged_solves_ = saved.clock.unconverged_solves;
    last_ = UpdateStats();
    res.success = true;
    res.message = "loaded " + std::to_string(garments_.size()) + " garments, " +
                  std::to_string(hairs_.size()) + " hair, " +
                  std::to_string(grasps_.size() + hair_grasps_.size()) + " grasps at sim time " +
                  std::to_string(sim_time_) + " s from " + req.path + (paused_ ? " (paused)" : "");
    ROS_INFO("%s", res.message.c_str());
  } catch (const std::exception& e) {
    res.message = std::string("load_state refused, the simulation is unchanged: ") + e.what();
    ROS_WARN("%s", res.message.c_str());
  }
  return true;
}

}  // namespace chs_node
