#include "cloth_hair_sim/node/sim_diagnostics.h"

#include <cmath>
#include <sstream>

#include "cloth_hair_sim/core/common/input_error.h"

namespace chs_node {
namespace {

using diagnostic_msgs::DiagnosticStatus;

// Growth of a counter since the last report; a counter that fell was reset meanwhile.
int increase(int now, int before) {
  return now >= before ? now - before : now;
}

std::string listed(const std::vector<std::string>& items) {
  std::string out;
  for (const auto& s : items) out += (out.empty() ? "" : ", ") + s;
  return out;
}

}  // namespace

SimDiagnostics::SimDiagnostics(ros::NodeHandle nh, ros::NodeHandle private_nh, double requested_rtf,
                               std::function<HealthSample()> sample)
    : requested_rtf_(requested_rtf), sample_(std::move(sample)), updater_(nh, private_nh) {
  private_nh.param("rtf_warn_fraction", warn_fraction_, warn_fraction_);
  if (!(warn_fraction_ >= 0.0 && warn_fraction_ <= 1.0))
    throw chs::InputError("parameter rtf_warn_fraction must lie in [0, 1]");
  const double period = updater_.getPeriod();
  if (!(period > 0.0) || !std::isfinite(period))
    throw chs::InputError("parameter diagnostic_period must be positive (s)");
  updater_.setHardwareID("none");  // a simulator: no device behind it
  updater_.add("Real-time factor", this, &SimDiagnostics::realTime);
  updater_.add("Solver", this, &SimDiagnostics::solver);
  updater_.add("Transforms", this, &SimDiagnostics::transforms);
  updater_.add("Drape", this, &SimDiagnostics::drape);
  timer_ = nh.createTimer(ros::Duration(period), &SimDiagnostics::onTimer, this);
}

void SimDiagnostics::onTimer(const ros::TimerEvent&) {
  now_ = sample_();
  updater_.force_update();
  before_ = now_;
  has_before_ = true;
}

void SimDiagnostics::realTime(diagnostic_updater::DiagnosticStatusWrapper& status) {
  status.add("requested", requested_rtf_);
  status.add("warn below", warn_fraction_ * requested_rtf_);
  if (!now_.running) {
    status.summary(DiagnosticStatus::OK, "not stepping (paused or no garment)");
    return;
  }
  // Over the whole report period where it can be told (running throughout, no reset), else the
  // last update's.
  double achieved = now_.last_update_rtf;
  const double wall = (now_.stamp - before_.stamp).toSec();
  if (has_before_ && before_.running && wall > 0.0 && now_.sim_time >= before_.sim_time)
    achieved = (now_.sim_time - before_.sim_time) / wall;
  status.add("achieved", achieved);
  std::ostringstream msg;
  msg << "achieved " << achieved;
  if (requested_rtf_ <= 0.0) {
    msg << " (as fast as possible)";
    status.summary(DiagnosticStatus::OK, msg.str());
  } else if (achieved < warn_fraction_ * requested_rtf_) {
    msg << ", below " << warn_fraction_ * 100.0 << " % of the requested " << requested_rtf_;
    status.summary(DiagnosticStatus::WARN, msg.str());
  } else {
    msg << " of the requested " << requested_rtf_;
    status.summary(DiagnosticStatus::OK, msg.str());
  }
}

void SimDiagnostics::solver(diagnostic_updater::DiagnosticStatusWrapper& status) {
  const int rollbacks = increase(now_.rollbacks, has_before_ ? before_.rollbacks : 0);
  const int unconverged =
      increase(now_.unconverged_solves, has_before_ ? before_.unconverged_solves : 0);
  status.add("rollbacks", now_.rollbacks);
  status.add("unconverged solves", now_.unconverged_solves);
  std::vector<std::string> stopped;
  for (const auto& [name, count] : now_.diverged_stops) {
    status.add("diverged stops of " + name, count);
    const auto it = before_.diverged_stops.find(name);
    const int before = has_before_ && it != before_.diverged_stops.end() ? it->second : 0;
    if (increase(count, before) > 0) stopped.push_back("'" + name + "'");
  }
  std::ostringstream since;
  since << rollbacks << " substeps rolled back and " << unconverged
        << " implicit solves unconverged since the last report";
  if (!stopped.empty())
    status.summary(DiagnosticStatus::ERROR,
                   "diverged and stopped in place: " + listed(stopped) + "; " + since.str());
  else if (rollbacks > 0 || unconverged > 0)
    status.summary(DiagnosticStatus::WARN, since.str());
  else
    status.summary(DiagnosticStatus::OK,
                   "no rollbacks or unconverged solves since the last report");
}

void SimDiagnostics::transforms(diagnostic_updater::DiagnosticStatusWrapper& status) {
  status.add("stale frames", static_cast<int>(now_.stale_frames.size()));
  if (now_.stale_frames.empty())
    status.summary(DiagnosticStatus::OK, "all tf frames current");
  else
    status.summary(DiagnosticStatus::WARN, "stale tf frames: " + listed(now_.stale_frames));
}

void SimDiagnostics::drape(diagnostic_updater::DiagnosticStatusWrapper& status) {
  status.add("running", now_.drape_running);
  if (!now_.drape_running) {
    status.summary(DiagnosticStatus::OK, "no drape solve running");
    return;
  }
  std::ostringstream msg;
  msg << "drape of '" << now_.drape_garment << "' running for " << now_.drape_seconds << " s";
  status.summary(DiagnosticStatus::OK, msg.str());
}

}  // namespace chs_node
