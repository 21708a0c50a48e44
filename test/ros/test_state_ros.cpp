// rostest of ~save_state and ~load_state (test/ros/state.test): a hanging, grasped garment is
// saved, changed (stepped on, removed) and loaded back: the garment list, sim time, grasp and
// vertices (from ~markers) return, and it steps on as it did after the save. Broken files are
// refused and the simulation runs on.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <mutex>

#include <unistd.h>

#include <gtest/gtest.h>
#include <ros/ros.h>
#include <std_srvs/SetBool.h>
#include <tf2_eigen/tf2_eigen.h>
#include <tf2_ros/static_transform_broadcaster.h>
#include <visualization_msgs/MarkerArray.h>
#include <Eigen/Geometry>

#include "cloth_hair_sim/GraspGarment.h"
#include "cloth_hair_sim/ListGarments.h"
#include "cloth_hair_sim/LoadGarment.h"
#include "cloth_hair_sim/LoadHair.h"
#include "cloth_hair_sim/ReleaseGrasp.h"
#include "cloth_hair_sim/RemoveGarment.h"
#include "cloth_hair_sim/SimStatus.h"
#include "cloth_hair_sim/StateFile.h"
#include "cloth_hair_sim/StepSim.h"

namespace {

using Vec3 = Eigen::Vector3d;

// Latest garment vertices (the ~markers triangles' corners) and ~status.
class Listener {
 public:
  explicit Listener(ros::NodeHandle& nh)
      : marker_sub_(nh.subscribe("/sim/markers", 2, &Listener::onMarkers, this)),
        status_sub_(nh.subscribe("/sim/status", 2, &Listener::onStatus, this)) {}
  // Garment marker points and status received a full period after this call.
  std::pair<std::vector<Vec3>, cloth_hair_sim::SimStatus> fresh() {
    const int markers = marker_count_, statuses = status_count_;
    const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(3.0);
    while (ros::WallTime::now() < end &&
           (marker_count_ < markers + 2 || status_count_ < statuses + 2))
      ros::WallDuration(0.01).sleep();
    std::lock_guard<std::mutex> lock(mutex_);
    return {points_, status_};
  }
  // The same for the hair markers' points.
  std::pair<std::vector<Vec3>, cloth_hair_sim::SimStatus> freshHair() {
    fresh();
    std::lock_guard<std::mutex> lock(mutex_);
    return {hair_points_, status_};
  }

 private:
  void onMarkers(const visualization_msgs::MarkerArray& a) {
    std::lock_guard<std::mutex> lock(mutex_);
    points_.clear();
    hair_points_.clear();
    for (const auto& m : a.markers) {
      if (m.action != visualization_msgs::Marker::ADD) continue;
      if (m.ns == "garments")
        for (const auto& p : m.points) points_.emplace_back(p.x, p.y, p.z);
      if (m.ns == "hair")
        for (const auto& p : m.points) hair_points_.emplace_back(p.x, p.y, p.z);
    }
    ++marker_count_;
  }
  void onStatus(const cloth_hair_sim::SimStatus& s) {
    std::lock_guard<std::mutex> lock(mutex_);
    status_ = s;
    ++status_count_;
  }
  std::mutex mutex_;
  std::vector<Vec3> points_, hair_points_;
  cloth_hair_sim::SimStatus status_;
  std::atomic<int> marker_count_{0}, status_count_{0};
  ros::Subscriber marker_sub_, status_sub_;
};

geometry_msgs::TransformStamped frameAt(const std::string& frame, const Vec3& p) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() = p;
  geometry_msgs::TransformStamped msg = tf2::eigenToTransform(t);
  msg.header.stamp = ros::Time::now();
  msg.header.frame_id = "world";
  msg.child_frame_id = frame;
  return msg;
}

double maxDistance(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  if (a.size() != b.size() || a.empty()) return INFINITY;
  double d = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) d = std::max(d, (a[i] - b[i]).norm());
  return d;
}

std::vector<std::string> garmentNames() {
  cloth_hair_sim::ListGarments list;
  EXPECT_TRUE(ros::service::call("/sim/list_garments", list));
  return list.response.names;
}

double stepped(int steps) {
  cloth_hair_sim::StepSim step;
  step.request.steps = steps;
  EXPECT_TRUE(ros::service::call("/sim/step", step) && step.response.success)
      << step.response.message;
  return step.response.sim_time;
}

cloth_hair_sim::StateFile::Response stateCall(const std::string& service, const std::string& path) {
  cloth_hair_sim::StateFile srv;
  srv.request.path = path;
  EXPECT_TRUE(ros::service::call(service, srv));
  std::printf("%s %s: %s\n", service.c_str(), path.c_str(), srv.response.message.c_str());
  return srv.response;
}

void writeBytes(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

TEST(StateFile, SaveChangeLoadBringsTheSimulationBack) {
  ros::NodeHandle nh;
  tf2_ros::StaticTransformBroadcaster frames;
  frames.sendTransform(std::vector<geometry_msgs::TransformStamped>{
      frameAt("hanger", Vec3(0, 0, 0.5)), frameAt("gripper", Vec3(-0.05, 0.0, 0.45))});
  Listener listener(nh);
  for (const char* s : {"/sim/load_garment", "/sim/save_state", "/sim/load_state", "/sim/grasp"})
    ASSERT_TRUE(ros::service::waitForService(s, ros::Duration(20.0))) << s;
  std_srvs::SetBool pause;
  pause.request.data = true;
  ASSERT_TRUE(ros::service::call("/sim/pause", pause));

  // A 10 x 10 cm square hung in the xz plane from the hanger by its top corners (20, 24); the
  // gripper holds its bottom-left corner (vertex 0).
  cloth_hair_sim::LoadGarment load;
  load.request.name = "cloth";
  load.request.rectangle_size = {0.1, 0.1};
  load.request.rectangle_cells = {4, 4};
  load.request.pose.position.z = 0.5;
  load.request.pose.orientation.x = load.request.pose.orientation.w = std::sqrt(0.5);
  load.request.material = "cotton_eischen";
  cloth_hair_sim::FramePins hanger;
  hanger.frame_id = "hanger";
  hanger.vertices = {20, 24};
  load.request.attached.push_back(hanger);
  ASSERT_TRUE(ros::service::call("/sim/load_garment", load) && load.response.success)
      << load.response.message;
  cloth_hair_sim::GraspGarment grasp;
  grasp.request.name = "grip";
  grasp.request.garment = "cloth";
  grasp.request.frame_id = "gripper";
  grasp.request.radius = 0.01;
  ASSERT_TRUE(ros::service::call("/sim/grasp", grasp) && grasp.response.success)
      << grasp.response.message;
  const double saved_time = stepped(100);

  const std::string path = "/tmp/chs_state_test_" + std::to_string(getpid()) + ".chs";
  const auto [saved_points, saved_status] = listener.fresh();
  ASSERT_FALSE(saved_points.empty());
  ASSERT_TRUE(stateCall("/sim/save_state", path).success);
  stepped(100);
  const std::vector<Vec3> continued = listener.fresh().first;
  const double moved = maxDistance(continued, saved_points);
  EXPECT_GT(moved, 1e-6) << "the garment did not move after the save";

  // Changed beyond recognition: the garment (and its grasp) removed.
  cloth_hair_sim::RemoveGarment remove;
  remove.request.name = "cloth";
  ASSERT_TRUE(ros::service::call("/sim/remove_garment", remove) && remove.response.success);
  EXPECT_TRUE(garmentNames().empty());

  ASSERT_TRUE(stateCall("/sim/load_state", path).success);
  EXPECT_EQ(garmentNames(), std::vector<std::string>{"cloth"});
  const auto [loaded_points, loaded_status] = listener.fresh();
  EXPECT_EQ(loaded_status.sim_time, saved_time);
  EXPECT_EQ(loaded_status.steps, saved_status.steps);
  EXPECT_EQ(loaded_status.state, "paused");
  EXPECT_EQ(loaded_status.grasps, std::vector<std::string>{"grip"});
  const double back = maxDistance(loaded_points, saved_points);
  EXPECT_LT(back, 1e-12);
  stepped(100);
  // The same 100 substeps again (TBB's sums may differ in the last bit).
  const double again = maxDistance(listener.fresh().first, continued);
  std::printf(
      "[figure] state file: vertices %.3e m from the saved ones after load, %.3e m from the "
      "original continuation after 100 more substeps (which moved them %.3e m)\n",
      back, again, moved);
  EXPECT_LT(again, 1e-9);

  // Broken files are refused by name; the simulation is untouched and keeps running.
  std::ifstream in(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::string flipped = bytes;
  flipped[bytes.size() / 2] ^= 0x01;
  writeBytes(path + ".flipped", flipped);
  writeBytes(path + ".cut", bytes.substr(0, bytes.size() / 2));
  const std::vector<Vec3> before = listener.fresh().first;
  const auto corrupt = stateCall("/sim/load_state", path + ".flipped");
  EXPECT_FALSE(corrupt.success);
  EXPECT_NE(corrupt.message.find("CRC-32"), std::string::npos);
  const auto cut = stateCall("/sim/load_state", path + ".cut");
  EXPECT_FALSE(cut.success);
  EXPECT_NE(cut.message.find("truncated"), std::string::npos);
  const auto missing = stateCall("/sim/load_state", path + ".none");
  EXPECT_FALSE(missing.success);
  EXPECT_NE(missing.message.find("cannot be read"), std::string::npos);
  EXPECT_EQ(garmentNames(), std::vector<std::string>{"cloth"});
  const auto [after, status] = listener.fresh();
  EXPECT_EQ(maxDistance(after, before), 0.0);
  pause.request.data = false;
  ASSERT_TRUE(ros::service::call("/sim/pause", pause));
  ros::WallDuration(1.0).sleep();
  EXPECT_GT(listener.fresh().second.sim_time, status.sim_time) << "the simulation stopped";
  // The grasp came back as a grasp.
  cloth_hair_sim::ReleaseGrasp release;
  release.request.name = "grip";
  EXPECT_TRUE(ros::service::call("/sim/release", release) && release.response.success)
      << release.response.message;
  for (const std::string& p : {path, path + ".flipped", path + ".cut"}) std::remove(p.c_str());
}

// Hair in a state file: a tuft on the hanger frame, a grasp of its free vertices, stepped,
// saved, stepped on, and loaded back: its strands (from ~markers), the grasp and the sim time
// return, and it steps on.
TEST(StateFile, HairComesBackWithItsGrasp) {
  ros::NodeHandle nh;
  for (const char* s : {"/sim/load_hair", "/sim/remove_hair"})
    ASSERT_TRUE(ros::service::waitForService(s, ros::Duration(20.0))) << s;
  Listener listener(nh);
  std_srvs::SetBool pause;
  pause.request.data = true;
  ASSERT_TRUE(ros::service::call("/sim/pause", pause));
  cloth_hair_sim::LoadHair hair;
  hair.request.name = "tuft";
  hair.request.frame_id = "hanger";
  hair.request.scalp_radii = {0.02};
  hair.request.strands = 6;
  hair.request.length = 0.05;
  hair.request.segments = 6;
  hair.request.material = "human_hair";
  hair.request.display_strands = -1;
  ASSERT_TRUE(ros::service::call("/sim/load_hair", hair) && hair.response.success)
      << hair.response.message;
  cloth_hair_sim::GraspGarment grasp;
  grasp.request.name = "pinch";
  grasp.request.garment = "tuft";
  grasp.request.frame_id = "hanger";
  grasp.request.radius = 0.06;
  ASSERT_TRUE(ros::service::call("/sim/grasp", grasp) && grasp.response.success)
      << grasp.response.message;
  stepped(20);
  const std::string path = "/tmp/chs_state_hair_" + std::to_string(getpid()) + ".state";
  const auto save = stateCall("/sim/save_state", path);
  ASSERT_TRUE(save.success) << save.message;
  EXPECT_NE(save.message.find("1 hair"), std::string::npos) << save.message;
  const auto [saved_hair, saved_status] = listener.freshHair();
  ASSERT_FALSE(saved_hair.empty());
  stepped(5);
  const std::vector<Vec3> continued = listener.freshHair().first;  // 5 steps on from the save
  stepped(25);
  EXPECT_GT(maxDistance(listener.freshHair().first, saved_hair), 1e-6) << "the hair did not move";
  const auto load = stateCall("/sim/load_state", path);
  ASSERT_TRUE(load.success) << load.message;
  EXPECT_NE(load.message.find("1 hair"), std::string::npos) << load.message;
  const auto [loaded_hair, loaded_status] = listener.freshHair();
  const double back = maxDistance(loaded_hair, saved_hair);
  EXPECT_EQ(back, 0.0);
  EXPECT_DOUBLE_EQ(loaded_status.sim_time, saved_status.sim_time);
  EXPECT_NE(std::find(loaded_status.grasps.begin(), loaded_status.grasps.end(), "pinch"),
            loaded_status.grasps.end());
  stepped(5);
  const std::vector<Vec3> replayed = listener.freshHair().first;
  const double replay = maxDistance(replayed, continued);
  std::printf(
      "[figure] hair back from the state file: strands within %.2e m of the saved ones "
      "(%zu marker points), sim time %.4f s (saved %.4f s); 5 steps on, %.2e m from the "
      "original continuation (which moved them %.2e m)\n",
      back, loaded_hair.size(), loaded_status.sim_time, saved_status.sim_time, replay,
      maxDistance(continued, saved_hair));
  EXPECT_LT(replay, 1e-9);  // the grid's parallel sums may differ in the last bits
  EXPECT_GT(maxDistance(replayed, saved_hair), 0.0) << "it does not step on";
  cloth_hair_sim::RemoveGarment remove;  // ~remove_hair takes the same request
  remove.request.name = "tuft";
  EXPECT_TRUE(ros::service::call("/sim/remove_hair", remove) && remove.response.success)
      << remove.response.message;
  std::remove(path.c_str());
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_state");
  ros::AsyncSpinner spinner(1);
  spinner.start();
  return RUN_ALL_TESTS();
}
