#pragma once
#include <functional>
#include <map>
#include <string>
#include <vector>

#include <diagnostic_updater/diagnostic_updater.h>
#include <ros/ros.h>

namespace chs_node {

// The simulator's health as /diagnostics reports it, sampled under the simulation mutex.
struct HealthSample {
  ros::Time stamp;
  bool running = false;  // garments loaded and not paused
  double sim_time = 0.0;
  double last_update_rtf = 0.0;  // real-time factor achieved in the last update
  int rollbacks = 0;
  int unconverged_solves = 0;
  std::map<std::string, int> diverged_stops;  // per garment: stopped in place since load or reset
  std::vector<std::string> stale_frames;      // frames not looked up in the last update, in words
  bool drape_running = false;
  std::string drape_garment;
  double drape_seconds = 0.0;  // wall time of the running drape so far
};

// Publishes the node's health on /diagnostics (diagnostic_updater, every ~diagnostic_period s,
// default 1) as four statuses: "Real-time factor" (WARN below ~rtf_warn_fraction of the
// requested real_time_factor), "Solver" (WARN when substeps were rolled back or implicit solves
// fell short since the last report, ERROR when a garment diverged and was stopped in place),
// "Transforms" (WARN naming the frames that hold their last pose) and "Drape" (OK, says whether
// a drape solve is running).
class SimDiagnostics {
 public:
  // Throws chs::InputError for a bad ~rtf_warn_fraction or ~diagnostic_period.
  SimDiagnostics(ros::NodeHandle nh, ros::NodeHandle private_nh, double requested_rtf,
                 std::function<HealthSample()> sample);

 private:
  void onTimer(const ros::TimerEvent& event);
  void realTime(diagnostic_updater::DiagnosticStatusWrapper& status);
  void solver(diagnostic_updater::DiagnosticStatusWrapper& status);
  void transforms(diagnostic_updater::DiagnosticStatusWrapper& status);
  void drape(diagnostic_updater::DiagnosticStatusWrapper& status);

  double requested_rtf_;
  double warn_fraction_ = 0.5;
  std::function<HealthSample()> sample_;
  HealthSample now_, before_;
  bool has_before_ = false;
  diagnostic_updater::Updater updater_;
  ros::Timer timer_;
};

}  // namespace chs_node
