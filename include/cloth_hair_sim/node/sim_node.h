#pragma once
#include <atomic>
#include <chrono>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>

#include <dynamic_reconfigure/server.h>
#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <std_srvs/SetBool.h>
#include <std_srvs/Trigger.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>
#include <boost/thread/recursive_mutex.hpp>

#include "cloth_hair_sim/DrapeSolve.h"
#include "cloth_hair_sim/GraspGarment.h"
#include "cloth_hair_sim/ListGarments.h"
#include "cloth_hair_sim/LoadGarment.h"
#include "cloth_hair_sim/LoadHair.h"
#include "cloth_hair_sim/ReleaseGrasp.h"
#include "cloth_hair_sim/RemoveGarment.h"
#include "cloth_hair_sim/SimConfig.h"
#include "cloth_hair_sim/StateFile.h"
#include "cloth_hair_sim/StepSim.h"
#include "cloth_hair_sim/node/collider_tracker.h"
#include "cloth_hair_sim/node/drape_action.h"
#include "cloth_hair_sim/node/garment.h"
#include "cloth_hair_sim/node/grasp.h"
#include "cloth_hair_sim/node/hair.h"
#include "cloth_hair_sim/node/sim_diagnostics.h"
#include "cloth_hair_sim/node/sim_params.h"

namespace chs_node {

// cloth_hair_sim_node: steps the core's dynamics on a timer, follows colliders through tf2,
// publishes ~status and ~markers and offers the garment and drape services. Callbacks run on
// an AsyncSpinner, so a long ~drape_solve leaves the timers and other services running; one
// mutex guards the simulation state, and the drape solve itself runs without holding it.
class SimNode {
 public:
  // Throws chs::InputError for bad parameters (the caller reports it and exits).
  SimNode(ros::NodeHandle nh, ros::NodeHandle private_nh);

 private:
  struct UpdateStats {
    double dt = 0.0;
    int substeps = 0;
    double wall_per_step = 0.0;
    double real_time_factor = 0.0;
  };

  void onStepTimer(const ros::TimerEvent& event);
  void onClockTimer(const ros::WallTimerEvent& event);  // ~publish_clock: steps, then /clock
  void advanceClock(double seconds);                    // ~publish_clock: /clock moves on
  // One update over `elapsed` seconds of the clock the node follows (wall or /clock); with
  // ~publish_clock the inputs share the node's clock and never lag it. Returns the seconds it
  // simulated (0: paused or nothing to step).
  double update(double elapsed);
  void onStatusTimer(const ros::TimerEvent& event);
  void onMarkerTimer(const ros::TimerEvent& event);

  bool loadGarment(cloth_hair_sim::LoadGarment::Request& req,
                   cloth_hair_sim::LoadGarment::Response& res);
  bool removeGarment(cloth_hair_sim::RemoveGarment::Request& req,
                     cloth_hair_sim::RemoveGarment::Response& res);
  // ~load_hair, ~remove_hair (sim_node_hair.cpp): hair as a body of world_; a refused load
  // leaves the world as it was.
  bool loadHair(cloth_hair_sim::LoadHair::Request& req, cloth_hair_sim::LoadHair::Response& res);
  bool removeHair(cloth_hair_sim::RemoveGarment::Request& req,
                  cloth_hair_sim::RemoveGarment::Response& res);
  // Under mutex_: the settings hair is built with, on the world's grid once it has one.
  chs::rod::HairSettings hairSettings() const;
  // Under mutex_: true if the hair's state is not finite or a vertex is faster than max_speed.
  bool diverged(const Hair& h) const;
  bool listGarments(cloth_hair_sim::ListGarments::Request& req,
                    cloth_hair_sim::ListGarments::Response& res);
  bool reset(std_srvs::Trigger::Request& req, std_srvs::Trigger::Response& res);
  bool pause(std_srvs::SetBool::Request& req, std_srvs::SetBool::Response& res);
  bool step(cloth_hair_sim::StepSim::Request& req, cloth_hair_sim::StepSim::Response& res);
  bool drapeSolve(cloth_hair_sim::DrapeSolve::Request& req,
                  cloth_hair_sim::DrapeSolve::Response& res);
  // The drape of ~drape_solve and ~drape, off the simulation mutex; returns true when the
  // solve stopped because cancel was set (the garment is then unchanged).
  bool drape(const cloth_hair_sim::DrapeSolve::Request& req,
             cloth_hair_sim::DrapeSolve::Response& res, const chs::ProgressCallback& progress,
             const chs::CancelFlag* cancel);
  // For /diagnostics (takes mutex_).
  HealthSample healthSample();
  bool grasp(cloth_hair_sim::GraspGarment::Request& req,
             cloth_hair_sim::GraspGarment::Response& res);
  bool release(cloth_hair_sim::ReleaseGrasp::Request& req,
               cloth_hair_sim::ReleaseGrasp::Response& res);
  // Under mutex_ (sim_node_hair.cpp): ~grasp of loaded hair, the gripper frame at world pose
  // `pose`; fills res (refused: a message naming the problem).
  void graspHair(const cloth_hair_sim::GraspGarment::Request& req, const Eigen::Isometry3d& pose,
                 Hair& hair, cloth_hair_sim::GraspGarment::Response& res);
  // Under mutex_: drops the grasps of a hair (removed or reset); returns their names.
  std::vector<std::string> dropHairGrasps(const std::string& hair);
  // Under mutex_: publishes each hair grasp's mean wrench of the update.
  void publishHairGraspWrenches();
  // ~save_state, ~load_state (state_io.h): the whole simulation to or from a file; a refused load
  // leaves the running simulation as it was.
  bool saveState(cloth_hair_sim::StateFile::Request& req, cloth_hair_sim::StateFile::Response& res);
  bool loadState(cloth_hair_sim::StateFile::Request& req, cloth_hair_sim::StateFile::Response& res);

  // World pose of a frame that carries vertices (the world frame itself is the identity), at
  // tf_delay_ behind now or else the latest; false and a reason if it cannot be looked up
  // within timeout.
  bool lookupFrame(const std::string& frame, double timeout, Eigen::Isometry3d& pose,
                   std::string* error);
  // Under mutex_: the frames of frame pins and grasps from tf (a missing one holds its pose).
  void refreshAttachments();
  // Under mutex_: the wrench each grasp feels, over an update of `duration` simulated seconds
  // (0: nothing was simulated, the held vertices count as still).
  void publishGraspWrenches(double duration);
  // Under mutex_: drops the grasps of a garment (removed or reset); returns their names.
  std::vector<std::string> dropGrasps(const std::string& garment);

  // Under mutex_: colliders from tf into every garment.
  void refreshColliders();
  // Under mutex_: obstacles for the world's garments and the others.
  void setColliders(const chs::RigidSurfaces& surfaces,
                    const std::vector<chs::SurfaceVelocity>& velocities,
                    const std::vector<double>& frictions);
  // Under mutex_: the parameters a garment is built with: on the world's grid once it has one.
  SimParams garmentParams() const;
  // A world holding the mpm garments and the hair, the node's own unless given (throws
  // chs::InputError for a body that does not fit).
  chs::World worldOf(const std::map<std::string, Garment>& garments,
                     const std::map<std::string, Hair>* hairs = nullptr) const;
  // Under mutex_: one substep of the world's garments together; a diverged step or an implicit
  // solve short of its tolerance is rolled back and retried as two halves, a few levels deep.
  void stepWorld(double h, int depth);
  // Under mutex_: the colliders' loads of the last world step, into this update's sums.
  void addColliderLoads(double h);
  // Under mutex_: ~collider_wrench/<name>: each collider's mean load over the update.
  void publishColliderWrenches();
  // Under mutex_: colliders and attachment frames that jumped in this update of `duration`
  // simulated seconds (teleport.h) are teleported rather than swept (sim_node_teleport.cpp).
  void teleportJumps(double duration);
  // Under mutex_: advances every garment by `count` substeps of h, the kinematic inputs over
  // the share `reach` of their way from their pose at the update's start to their current one
  // (1: all of it; less when the simulation falls behind, see ~max_input_lag).
  void advance(int count, double h, double reach = 1.0);
  // Under mutex_: one substep of one garment; a diverged step is rolled back and retried as two
  // halves, a few levels deep, before the garment is stopped where it was.
  void stepGarment(Garment& g, double h, int depth);
  bool diverged(const Garment& g) const;
  // Under mutex_: the largest substep every garment tolerates.
  double substepLimit() const;

  // dynamic_reconfigure (cfg/Sim.cfg, sim_node_reconfigure.cpp): the server shows the node's
  // parameters; a change is applied under mutex_, a refused value is put back and logged.
  void startReconfigure();
  void onReconfigure(cloth_hair_sim::SimConfig& config);
  // Under mutex_: the material group, for the garment the config's `garment` names.
  void reconfigureMaterial(cloth_hair_sim::SimConfig& config);

  ros::NodeHandle nh_, pnh_;
  SimParams params_;
  tf2_ros::Buffer tf_buffer_;
  tf2_ros::TransformListener tf_listener_;

  std::mutex mutex_;
  // mutex_, taken with the edits that ~load_garment and ~remove_garment queued meanwhile applied
  // first: every section under mutex_ sees garments_ and world_ as the services answered.
  class WorldLock {
   public:
    explicit WorldLock(SimNode& node) : lock_(node.mutex_) { node.applyPendingEdits(); }

   private:
    std::lock_guard<std::mutex> lock_;
  };
  // Loads (a built garment) and removals (none) asked for while an update of the world held
  // mutex_: the services answer at once instead of waiting for the update (one substep of a
  // 20-garment world takes ~0.1 s), and the edits apply in order at the next WorldLock. The
  // catalogue shows them at once. Under pending_mutex_.
  struct PendingEdit {
    std::string name;
    std::optional<Garment> garment;
  };
  std::mutex pending_mutex_;
  std::vector<PendingEdit> pending_edits_;
  // Under mutex_.
  void applyPendingEdits();
  // Under mutex_: puts a built garment into garments_ and world_. Throws chs::InputError when
  // the world refuses it (grid spacing or kernel other than the world's). The caller refreshes
  // the catalogue.
  void insertGarment(const std::string& name, Garment g);
  // Under mutex_: takes a garment out of garments_ and world_ and drops its grasps (their names).
  // The caller refreshes the catalogue.
  std::vector<std::string> eraseGarment(const std::string& name);
  // What ~list_garments answers, under its own mutex: the list is rebuilt from garments_,
  // hairs_ (under mutex_) and the pending garments wherever they change, so that listing them
  // never waits for a step of the world (a step of 20 garments takes up to ~0.1 s). The same
  // call refreshes load_params_ (under pending_mutex_): garmentParams() for the loads built
  // while the world steps.
  std::mutex catalogue_mutex_;
  cloth_hair_sim::ListGarments::Response catalogue_;
  // The garment grasps' names and garments, under catalogue_mutex_, refreshed with the list: a
  // removal answered while the world steps names the grasps that leave with the garment.
  std::vector<std::pair<std::string, std::string>> grasped_garments_;
  SimParams load_params_;
  // The world's particles as of the last refresh (under pending_mutex_): a load queued while
  // the world steps is checked against ~mpm/max_particles with it and the queue's.
  long world_particles_ = 0;
  void refreshCatalogue();
  // Whether the catalogue lists a garment or hair of that name (without mutex_).
  bool nameTaken(const std::string& name);
  ColliderTracker colliders_;
  std::map<std::string, Garment> garments_;
  std::map<std::string, Hair> hairs_;  // bodies of world_ too
  // ~hair/: display strands per hair when a load asks for the default, the markers' colour
  // [r, g, b, a] and line width [m], and dx when hair is the world's first body.
  int hair_display_strands_ = 100;
  std::vector<float> hair_colour_{0.45f, 0.3f, 0.15f, 1.0f};
  double hair_line_width_ = 0.0005;
  double hair_grid_spacing_ = 0.01;
  // ~hair/continuum/: the strands' frictional contact as a continuum on the grid (opt-in).
  chs::rod::StrandContinuumSettings hair_continuum_;
  // The mpm garments as bodies of one world: one grid, contact and friction between them.
  chs::World world_;
  std::vector<std::string> active_colliders_;  // the world's collider order (those with a pose)
  struct ColliderLoadSum {
    Eigen::Vector3d force = Eigen::Vector3d::Zero(), moment = Eigen::Vector3d::Zero();
    double duration = 0.0;
  };
  std::map<std::string, ColliderLoadSum> collider_loads_;  // this update's, per collider
  std::map<std::string, ros::Publisher> collider_wrench_pubs_;
  std::map<std::string, Grasp> grasps_;
  std::map<std::string, HairGrasp> hair_grasps_;  // names unique with grasps_
  // Collider poses at the start of the current update: colliders move from there towards their
  // current pose over the update's substeps (all the way unless the inputs lag), with the
  // velocity of that motion.
  std::map<std::string, Eigen::Isometry3d> collider_from_;
  // Colliders that jumped in the previous update: the tail of an interpolated jump is placed too.
  std::set<std::string> colliders_jumped_;
  // [s] frame pins and grasps follow their frames this far in the past (~tf_delay), where tf
  // interpolates: sampled at the latest stamp, a frame would advance by one or two of its
  // publisher's periods per update and shake the stiff cloth.
  double tf_delay_ = 0.05;
  std::uint64_t next_generation_ = 1;
  int next_colour_ = 0;
  // Written by ~pause without mutex_ (it takes effect when the update in progress ends).
  std::atomic<bool> paused_{false};
  bool transforms_ok_ = true;
  double sim_time_ = 0.0;
  std::uint64_t steps_ = 0;
  int rollbacks_ = 0;
  int unconverged_solves_ = 0;
  UpdateStats last_;
  double substep_cost_ = 0.0;  // [s] wall time per substep of the last update (0: not known)
  double input_lag_ = 0.0;     // [s] of the kinematic inputs' motion not simulated yet
  std::atomic<bool> drape_running_{false};
  std::string drape_garment_;  // under mutex_: the garment of the running drape, and its start
  std::chrono::steady_clock::time_point drape_started_;

  ros::Publisher status_pub_, marker_pub_;
  ros::ServiceServer load_srv_, remove_srv_, list_srv_, reset_srv_, pause_srv_, step_srv_,
      drape_srv_, grasp_srv_, release_srv_, save_state_srv_, load_state_srv_, load_hair_srv_,
      remove_hair_srv_;
  // The timers (step, status, markers, diagnostics) all take mutex_: on the global queue they
  // could hold every spinner thread while an update runs, and a service as light as
  // ~list_garments waited for the update (0.165 s with 20 garments). They have a queue and a
  // thread of their own; the global queue's threads serve the services.
  ros::CallbackQueue timer_queue_;
  ros::NodeHandle timer_nh_;
  ros::Timer step_timer_, status_timer_, marker_timer_;
  ros::WallTimer clock_timer_;
  ros::Publisher clock_pub_;
  ros::Time clock_;  // ~publish_clock: the time last published on /clock
  std::unique_ptr<SimDiagnostics> diagnostics_;
  std::unique_ptr<ros::AsyncSpinner> timer_spinner_;
  // Last: destroyed first, it cancels and waits for a running drape that uses the members above.
  std::unique_ptr<DrapeAction> drape_action_;
  // Taken by the server around each callback; never while holding mutex_ (the callback takes
  // mutex_ inside it).
  boost::recursive_mutex reconfigure_mutex_;
  std::unique_ptr<dynamic_reconfigure::Server<cloth_hair_sim::SimConfig>> reconfigure_;
  cloth_hair_sim::SimConfig live_;  // the last accepted configuration
};

}  // namespace chs_node
