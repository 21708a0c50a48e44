// rostest of the node's grasps, frame pins and tf-moved colliders (test/ros/grasp.test). The
// test broadcasts the frames gripper, hanger and pusher and moves them; garment vertices are
// read back from the ~markers points (every vertex is a corner of some marker triangle).
#include <atomic>
#include <cmath>
#include <cstdio>
#include <map>
#include <mutex>
#include <thread>

#include <geometry_msgs/WrenchStamped.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <std_srvs/SetBool.h>
#include <std_srvs/Trigger.h>
#include <tf2_eigen/tf2_eigen.h>
#include <tf2_ros/transform_broadcaster.h>
#include <visualization_msgs/MarkerArray.h>
#include <Eigen/Geometry>

#include "cloth_hair_sim/GraspGarment.h"
#include "cloth_hair_sim/LoadGarment.h"
#include "cloth_hair_sim/ReleaseGrasp.h"
#include "cloth_hair_sim/RemoveGarment.h"
#include "cloth_hair_sim/SimStatus.h"

namespace {

using Vec3 = Eigen::Vector3d;

// 10 x 10 cm cotton (0.2384 kg/m^2) of 4 x 4 quads.
const double kWeight = 0.2384 * 0.01 * 9.81;

// Broadcasts the test's frames at 100 Hz; move() glides one at constant velocity.
class Frames {
 public:
  Frames() : thread_([this] { run(); }) {}
  ~Frames() {
    stop_ = true;
    thread_.join();
  }
  void set(const std::string& frame, const Eigen::Isometry3d& pose) {
    std::lock_guard<std::mutex> lock(mutex_);
    poses_[frame] = pose;
  }
  Eigen::Isometry3d get(const std::string& frame) {
    std::lock_guard<std::mutex> lock(mutex_);
    return poses_.at(frame);
  }
  void move(const std::string& frame, const Vec3& by, double seconds) {
    const Eigen::Isometry3d start = get(frame);
    const ros::WallTime t0 = ros::WallTime::now();
    for (double s = 0.0; s < 1.0;) {
      s = std::min(1.0, (ros::WallTime::now() - t0).toSec() / seconds);
      Eigen::Isometry3d pose = start;
      pose.translation() += s * by;
      set(frame, pose);
      ros::WallDuration(0.005).sleep();
    }
  }

 private:
  void run() {
    while (!stop_) {
      {
        std::lock_guard<std::mutex> lock(mutex_);
        for (const auto& [frame, pose] : poses_) {
          geometry_msgs::TransformStamped t = tf2::eigenToTransform(pose);
          t.header.stamp = ros::Time::now();
          t.header.frame_id = "world";
          t.child_frame_id = frame;
          broadcaster_.sendTransform(t);
        }
      }
      ros::WallDuration(0.01).sleep();
    }
  }
  tf2_ros::TransformBroadcaster broadcaster_;
  std::mutex mutex_;
  std::map<std::string, Eigen::Isometry3d> poses_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

Eigen::Isometry3d at(double x, double y, double z) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() = Vec3(x, y, z);
  return t;
}

// Latest garment vertices (from ~markers) and grasp wrench.
class Listener {
 public:
  explicit Listener(ros::NodeHandle& nh)
      : marker_sub_(nh.subscribe("/sim/markers", 2, &Listener::onMarkers, this)),
        status_sub_(nh.subscribe("/sim/status", 2, &Listener::onStatus, this)) {}
  void watchWrench(ros::NodeHandle& nh, const std::string& grasp) {
    wrench_sub_ = nh.subscribe("/sim/grasp_wrench/" + grasp, 10, &Listener::onWrench, this);
  }
  // Points of the garment marker received after this call (empty on timeout).
  std::vector<Vec3> freshPoints(double timeout = 2.0) {
    const int seen = marker_count_;
    const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(timeout);
    while (ros::WallTime::now() < end) {
      if (marker_count_ > seen + 1) {  // one full period after the call
        std::lock_guard<std::mutex> lock(mutex_);
        return points_;
      }
      ros::WallDuration(0.01).sleep();
    }
    return {};
  }
  bool freshWrench(geometry_msgs::WrenchStamped& out, double timeout = 2.0) {
    const int seen = wrench_count_;
    const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(timeout);
    while (ros::WallTime::now() < end) {
      if (wrench_count_ > seen) {
        std::lock_guard<std::mutex> lock(mutex_);
        out = wrench_;
        return true;
      }
      ros::WallDuration(0.01).sleep();
    }
    return false;
  }
  // Wrench z values received since the last call.
  std::vector<double> takeWrenchHistory() {
    std::lock_guard<std::mutex> lock(mutex_);
    std::vector<double> out;
    out.swap(history_);
    return out;
  }
  cloth_hair_sim::SimStatus status() {
    std::lock_guard<std::mutex> lock(mutex_);
    return status_;
  }

 private:
  void onMarkers(const visualization_msgs::MarkerArray& a) {
    std::lock_guard<std::mutex> lock(mutex_);
    points_.clear();
    for (const auto& m : a.markers)
      if (m.ns == "garments" && m.action == visualization_msgs::Marker::ADD)
        for (const auto& p : m.points) points_.emplace_back(p.x, p.y, p.z);
    ++marker_count_;
  }
  void onWrench(const geometry_msgs::WrenchStamped& w) {
    std::lock_guard<std::mutex> lock(mutex_);
    wrench_ = w;
    history_.push_back(w.wrench.force.z);
    ++wrench_count_;
  }
  void onStatus(const cloth_hair_sim::SimStatus& s) {
    std::lock_guard<std::mutex> lock(mutex_);
    status_ = s;
  }
  std::mutex mutex_;
  std::vector<Vec3> points_;
  geometry_msgs::WrenchStamped wrench_;
  std::vector<double> history_;
  cloth_hair_sim::SimStatus status_;
  std::atomic<int> marker_count_{0}, wrench_count_{0};
  ros::Subscriber marker_sub_, status_sub_, wrench_sub_;
};

// Distance from p to the nearest garment vertex.
double nearest(const std::vector<Vec3>& points, const Vec3& p) {
  double d = 1e9;
  for (const auto& q : points) d = std::min(d, (q - p).norm());
  return d;
}
double highest(const std::vector<Vec3>& points) {
  double z = -1e9;
  for (const auto& q : points) z = std::max(z, q.z());
  return z;
}

// The 10 x 10 cm square hung in the world xz plane, centred at (x, 0, z): its top edge (vertices
// 20..24, x from -5 to +5 cm) is at z + 0.05.
cloth_hair_sim::LoadGarment::Request hanging(const std::string& name, double x, double z) {
  cloth_hair_sim::LoadGarment::Request r;
  r.name = name;
  r.rectangle_size = {0.1, 0.1};
  r.rectangle_cells = {4, 4};
  r.pose.position.x = x;
  r.pose.position.z = z;
  r.pose.orientation.x = std::sqrt(0.5);  // +90 deg about x: the sheet's y becomes z
  r.pose.orientation.w = std::sqrt(0.5);
  r.material = "cotton_eischen";
  return r;
}

bool call(const std::string& service, cloth_hair_sim::LoadGarment& srv) {
  return ros::service::call(service, srv) && srv.response.success;
}

class GraspTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    frames_ = new Frames;
    frames_->set("gripper", at(0.0, 0.0, 1.06));
    frames_->set("hanger", at(1.0, 0.0, 1.05));
    frames_->set("pusher", at(2.0, -0.1, 1.0));
    ASSERT_TRUE(ros::service::waitForService("/sim/grasp", ros::Duration(30.0)));
  }
  static void TearDownTestSuite() { delete frames_; }
  static Frames* frames_;
  ros::NodeHandle nh_;
  Listener listener_{nh_};
};
Frames* GraspTest::frames_ = nullptr;

TEST_F(GraspTest, GraspLiftsWeighsAndReleases) {
  // Paused, so that the towel does not fall before the gripper closes.
  std_srvs::SetBool pause;
  pause.request.data = true;
  ASSERT_TRUE(ros::service::call("/sim/pause", pause));
  cloth_hair_sim::LoadGarment load;
  load.request = hanging("towel", 0.0, 1.0);
  ASSERT_TRUE(call("/sim/load_garment", load)) << load.response.message;
  // The gripper 1 cm above the middle of the top edge closes on the three vertices within 3 cm.
  cloth_hair_sim::GraspGarment grasp;
  grasp.request.name = "lift";
  grasp.request.garment = "towel";
  grasp.request.frame_id = "gripper";
  grasp.request.radius = 0.03;
  listener_.watchWrench(nh_, "lift");
  ASSERT_TRUE(ros::service::call("/sim/grasp", grasp));
  ASSERT_TRUE(grasp.response.success) << grasp.response.message;
  EXPECT_EQ(grasp.response.vertices, (std::vector<int>{21, 22, 23}));
  pause.request.data = false;
  ASSERT_TRUE(ros::service::call("/sim/pause", pause));

  // The cloth hangs from the grasp; once the swing of its free corners has died out the grasp
  // carries its weight.
  ros::WallDuration(3.0).sleep();
  geometry_msgs::WrenchStamped w;
  ASSERT_TRUE(listener_.freshWrench(w));
  std::printf(
      "hanging from the grasp: wrench force (%.3e, %.3e, %.6e) N, torque (%.2e, %.2e, "
      "%.2e) N m; weight %.6e N\n",
      w.wrench.force.x, w.wrench.force.y, w.wrench.force.z, w.wrench.torque.x, w.wrench.torque.y,
      w.wrench.torque.z, kWeight);
  EXPECT_EQ(w.header.frame_id, "gripper");
  EXPECT_NEAR(w.wrench.force.z, -kWeight, 0.05 * kWeight);  // the cloth pulls the gripper down
  EXPECT_NEAR(std::hypot(w.wrench.force.x, w.wrench.force.y), 0.0, 0.05 * kWeight);
  // Hung symmetrically below the gripper: no moment beyond the 1 cm offset times the sideways
  // pull of the edge (tiny).
  EXPECT_LT(std::abs(w.wrench.torque.y), 0.05 * kWeight * 0.05);
  EXPECT_EQ(listener_.status().grasps, std::vector<std::string>{"lift"});

  // Lift by 10 cm: the grasped vertices rise with the gripper, keeping their offsets.
  auto before = listener_.freshPoints();
  ASSERT_FALSE(before.empty());
  const double top0 = highest(before);
  listener_.takeWrenchHistory();
  frames_->move("gripper", Vec3(0.0, 0.0, 0.1), 1.0);
  // While it rises at 0.1 m/s the grasp also carries the cloth's damping, 5/s x M x v.
  const std::vector<double> lifting = listener_.takeWrenchHistory();
  ASSERT_GT(lifting.size(), 20u);
  double mean = 0.0, rms = 0.0;
  for (size_t k = 10; k < lifting.size(); ++k) mean += lifting[k] / (lifting.size() - 10);
  for (size_t k = 10; k < lifting.size(); ++k)
    rms += std::pow(lifting[k] - mean, 2) / (lifting.size() - 10);
  rms = std::sqrt(rms);
  const double expected_lifting = kWeight + 5.0 * 0.2384 * 0.01 * 0.1;
  std::printf(
      "lifting at 0.1 m/s (%zu wrenches after the first 10): mean z %.6e N, rms about it "
      "%.2e N; weight + damping %.6e N\n",
      lifting.size() - 10, mean, rms, expected_lifting);
  EXPECT_NEAR(-mean, expected_lifting, 0.1 * kWeight);
  ros::WallDuration(1.0).sleep();
  auto after = listener_.freshPoints();
  ASSERT_FALSE(after.empty());
  EXPECT_NEAR(highest(after), top0 + 0.1, 2e-3);
  for (double x : {-0.025, 0.0, 0.025})
    EXPECT_LT(nearest(after, Vec3(x, 0.0, 1.15)), 1e-3) << "grasped vertex at x = " << x;
  // The stop rang the cloth's stretch: average over another second as a controller would.
  listener_.takeWrenchHistory();
  ros::WallDuration(1.0).sleep();
  const std::vector<double> held = listener_.takeWrenchHistory();
  ASSERT_GT(held.size(), 20u);
  double held_mean = 0.0, lo = 1e9, hi = -1e9;
  for (double z : held) {
    held_mean += z / held.size();
    lo = std::min(lo, z);
    hi = std::max(hi, z);
  }
  std::printf(
      "lifted, 1 to 2 s after the stop: mean wrench z %.6e N (%.2f %% off the weight), "
      "range [%.4e, %.4e] N\n",
      held_mean, 100.0 * (-held_mean / kWeight - 1.0), lo, hi);
  EXPECT_NEAR(held_mean, -kWeight, 0.05 * kWeight);

  // Release: the cloth falls.
  cloth_hair_sim::ReleaseGrasp release;
  release.request.name = "lift";
  ASSERT_TRUE(ros::service::call("/sim/release", release));
  EXPECT_TRUE(release.response.success) << release.response.message;
  ros::WallDuration(0.5).sleep();
  const auto fallen = listener_.freshPoints();
  ASSERT_FALSE(fallen.empty());
  std::printf("0.5 s after the release: top of the cloth at z %.3f m (was %.3f)\n", highest(fallen),
              highest(after));
  EXPECT_LT(highest(fallen), highest(after) - 0.3);
  EXPECT_FALSE(ros::service::call("/sim/release", release) && release.response.success);

  cloth_hair_sim::RemoveGarment remove;
  remove.request.name = "towel";
  ASSERT_TRUE(ros::service::call("/sim/remove_garment", remove));
}

TEST_F(GraspTest, RefusesBadGrasps) {
  cloth_hair_sim::LoadGarment load;
  load.request = hanging("rag", 3.0, 1.0);
  load.request.pinned = {20, 24};
  ASSERT_TRUE(call("/sim/load_garment", load)) << load.response.message;
  struct Case {
    std::string name, garment, frame;
    double radius;
    std::string expect;
  };
  const std::vector<Case> cases = {
      {"a", "nobody", "world", 0.1, "no garment 'nobody'"},
      {"b", "rag", "no_such_frame", 0.1, "no_such_frame"},
      {"c", "rag", "world", 0.0, "radius"},
      {"d", "rag", "world", 0.1, "nearest vertex"},  // the rag is 3 m away from the origin
      {"bad/name", "rag", "world", 0.1, "'/' at position 4"},
      {"my grasp", "rag", "world", 0.1, "a space at position 3"},
  };
  for (const auto& c : cases) {
    cloth_hair_sim::GraspGarment g;
    g.request.name = c.name;
    g.request.garment = c.garment;
    g.request.frame_id = c.frame;
    g.request.radius = c.radius;
    ASSERT_TRUE(ros::service::call("/sim/grasp", g));
    EXPECT_FALSE(g.response.success) << c.name;
    EXPECT_NE(g.response.message.find(c.expect), std::string::npos)
        << c.name << ": " << g.response.message;
  }
  // Pinned vertices are not grasped: a gripper on the pinned corner 20 takes only its free
  // neighbours within 3 cm.
  frames_->set("gripper2", at(2.95, 0.0, 1.05));
  cloth_hair_sim::GraspGarment g;
  g.request.name = "corner";
  g.request.garment = "rag";
  g.request.frame_id = "gripper2";
  g.request.radius = 0.03;
  ASSERT_TRUE(ros::service::call("/sim/grasp", g));
  ASSERT_TRUE(g.response.success) << g.response.message;
  EXPECT_EQ(g.response.vertices, (std::vector<int>{15, 21}));
  ASSERT_TRUE(ros::service::call("/sim/grasp", g));
  EXPECT_FALSE(g.response.success);  // the name is taken
  // Removing the garment drops its grasps.
  cloth_hair_sim::RemoveGarment remove;
  remove.request.name = "rag";
  ASSERT_TRUE(ros::service::call("/sim/remove_garment", remove));
  EXPECT_NE(remove.response.message.find("corner"), std::string::npos) << remove.response.message;
  cloth_hair_sim::ReleaseGrasp release;
  release.request.name = "corner";
  ASSERT_TRUE(ros::service::call("/sim/release", release));
  EXPECT_FALSE(release.response.success);
}

TEST_F(GraspTest, PinsAttachedToAFrameFollowIt) {
  cloth_hair_sim::LoadGarment load;
  load.request = hanging("flag", 1.0, 1.0);
  cloth_hair_sim::FramePins pins;
  pins.frame_id = "hanger";  // at the middle of the top edge
  pins.vertices = {20, 24};  // the top corners
  load.request.attached = {pins};
  ASSERT_TRUE(call("/sim/load_garment", load)) << load.response.message;
  // The hanger moves 20 cm along x and 10 cm up, then turns 90 degrees about z.
  frames_->move("hanger", Vec3(0.2, 0.0, 0.1), 1.0);
  Eigen::Isometry3d turned = frames_->get("hanger");
  turned.rotate(Eigen::AngleAxisd(M_PI / 2, Vec3::UnitZ()));
  frames_->set("hanger", turned);
  ros::WallDuration(0.5).sleep();
  const auto points = listener_.freshPoints();
  ASSERT_FALSE(points.empty());
  for (double x : {-0.05, 0.05}) {
    const Vec3 expected = turned * Vec3(x, 0.0, 0.0);
    std::printf("corner at offset x = %+.2f: expected (%.3f, %.3f, %.3f), nearest vertex %.2e m\n",
                x, expected.x(), expected.y(), expected.z(), nearest(points, expected));
    EXPECT_LT(nearest(points, expected), 1e-6);
  }
  // A reset restarts the flag at its reference shape carried by the hanger, not at its load
  // pose with the corners torn away (nor frozen by rollbacks).
  std_srvs::Trigger reset;
  ASSERT_TRUE(ros::service::call("/sim/reset", reset));
  ASSERT_TRUE(reset.response.success) << reset.response.message;
  ros::WallDuration(0.3).sleep();
  const auto restarted = listener_.freshPoints();
  ASSERT_FALSE(restarted.empty());
  double farthest = 0.0;
  for (const auto& p : restarted) farthest = std::max(farthest, (p - turned.translation()).norm());
  std::printf("after ~reset: farthest vertex %.3f m from the hanger, rollbacks %d\n", farthest,
              listener_.status().rollbacks);
  EXPECT_LT(farthest, 0.125);  // the 10 x 10 cm flag hangs below it (corner: 0.112 m)
  for (double x : {-0.05, 0.05}) EXPECT_LT(nearest(restarted, turned * Vec3(x, 0.0, 0.0)), 1e-6);
  EXPECT_EQ(listener_.status().rollbacks, 0);

  // Unknown frames and bad indices are refused.
  load.request.name = "flag2";
  load.request.attached[0].frame_id = "no_such_frame";
  ASSERT_TRUE(ros::service::call("/sim/load_garment", load));
  EXPECT_FALSE(load.response.success);
  EXPECT_NE(load.response.message.find("no_such_frame"), std::string::npos);
  load.request.attached[0].frame_id = "hanger";
  load.request.attached[0].vertices = {25};
  ASSERT_TRUE(ros::service::call("/sim/load_garment", load));
  EXPECT_FALSE(load.response.success);
  EXPECT_NE(load.response.message.find("25"), std::string::npos) << load.response.message;

  cloth_hair_sim::RemoveGarment remove;
  remove.request.name = "flag";
  ASSERT_TRUE(ros::service::call("/sim/remove_garment", remove));
}

TEST_F(GraspTest, ColliderMovedThroughTfPushesTheCloth) {
  cloth_hair_sim::LoadGarment load;
  load.request = hanging("curtain", 2.0, 1.0);
  load.request.pinned = {20, 21, 22, 23, 24};  // the top edge, fixed in the world
  ASSERT_TRUE(call("/sim/load_garment", load)) << load.response.message;
  ros::WallDuration(0.3).sleep();
  const auto still = listener_.freshPoints();
  ASSERT_FALSE(still.empty());
  double y0 = -1e9;
  for (const auto& p : still) y0 = std::max(y0, p.y());
  // The 3 cm sphere behind the curtain's middle moves 15 cm through it along +y.
  frames_->move("pusher", Vec3(0.0, 0.15, 0.0), 1.0);
  ros::WallDuration(0.2).sleep();
  const auto pushed = listener_.freshPoints();
  ASSERT_FALSE(pushed.empty());
  double y1 = -1e9;
  for (const auto& p : pushed) y1 = std::max(y1, p.y());
  const Vec3 centre = frames_->get("pusher").translation();
  double inside = 0.0;
  for (const auto& p : pushed) inside = std::max(inside, 0.03 - (p - centre).norm());
  std::printf(
      "sphere moved to y = %.3f: cloth reaches y = %.4f (was %.4f), deepest vertex inside "
      "the sphere %.2e m\n",
      centre.y(), y1, y0, inside);
  EXPECT_NEAR(y0, 0.0, 1e-6);
  EXPECT_GT(y1, centre.y());  // carried in front of the sphere, not left behind it
  EXPECT_LT(inside, 1e-3);
  cloth_hair_sim::RemoveGarment remove;
  remove.request.name = "curtain";
  ASSERT_TRUE(ros::service::call("/sim/remove_garment", remove));
}

}  // namespace

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_grasp");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  const int result = RUN_ALL_TESTS();
  ros::shutdown();
  return result;
}
