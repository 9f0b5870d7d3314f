// SPDX-License-Identifier: BSD-3-Clause
// Tracking in a running graph against the simulator's ground truth: the simulated head (true pose on TF as
// odom) feeds the detector, which tracks in odom. Checks over `scene_seconds` of scene time: one track id per
// object (an IDF1-style figure is printed), landmark errors at confirmation and after 20 observations, landmark
// velocities within 0.05 m/s of the truth, every object kept as a landmark while the camera looks away
// (`look_away`), ~get_landmark, ~enable, ~reset_tracks.
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <std_srvs/SetBool.h>
#include <std_srvs/Trigger.h>

#include <Eigen/Geometry>
#include <cmath>
#include <map>
#include <mutex>
#include <set>

#include "ros_test_helpers.h"
#include "underwater_stereo/DetectedObjectArray.h"
#include "underwater_stereo/GetLandmark.h"
#include "underwater_stereo/GroundTruth.h"

using namespace underwater_stereo;
using underwater_stereo::test::waitFor;

namespace {

struct Listener {
  explicit Listener(ros::NodeHandle& nh) {
    objects_sub = nh.subscribe("/stereo/detector/objects", 100, &Listener::onObjects, this);
    landmarks_sub = nh.subscribe("/stereo/detector/landmarks", 100, &Listener::onLandmarks, this);
    truth_sub = nh.subscribe("/stereo/ground_truth", 100, &Listener::onTruth, this);
  }
  void onObjects(const DetectedObjectArrayConstPtr& m) {
    std::lock_guard<std::mutex> lock(mutex);
    objects[m->header.stamp] = m;
  }
  void onLandmarks(const DetectedObjectArrayConstPtr& m) {
    std::lock_guard<std::mutex> lock(mutex);
    landmarks[m->header.stamp] = m;
  }
  void onTruth(const GroundTruthConstPtr& m) {
    std::lock_guard<std::mutex> lock(mutex);
    truths[m->header.stamp] = m;
    last_seq = m->header.seq;
  }
  std::mutex mutex;
  std::map<ros::Time, DetectedObjectArrayConstPtr> objects, landmarks;
  std::map<ros::Time, GroundTruthConstPtr> truths;
  std::uint32_t last_seq = 0;
  ros::Subscriber objects_sub, landmarks_sub, truth_sub;
};

Eigen::Vector3d vec(const geometry_msgs::Point& p) { return {p.x, p.y, p.z}; }

/// The ground-truth object nearest to `p` (positions in the stereo frame, or in the fixed frame), within
/// 0.15 m + 5 % of its range; -1 when none.
int nearestTruth(const GroundTruth& truth, const Eigen::Vector3d& p, bool fixed) {
  int best = -1;
  double best_d = 1e9;
  for (std::size_t i = 0; i < truth.objects.size(); ++i) {
    const auto& o = truth.objects[i];
    const double d = (vec(fixed ? o.position_fixed : o.position) - p).norm();
    if (d < best_d && d < 0.15 + 0.05 * o.range) {
      best_d = d;
      best = static_cast<int>(i);
    }
  }
  return best;
}

/// [deg] how far the camera looks away from its start (optical axis against odom x).
double lookAwayDeg(const GroundTruth& truth) {
  const auto& q = truth.camera_pose.orientation;
  const Eigen::Vector3d forward = Eigen::Quaterniond(q.w, q.x, q.y, q.z) * Eigen::Vector3d::UnitZ();
  return std::acos(std::clamp(forward.x() / forward.norm(), -1.0, 1.0)) * 180.0 / M_PI;
}

}  // namespace

TEST(TrackingGraph, IdsAndLandmarksAgainstGroundTruth) {
  ros::NodeHandle nh, pnh("~");
  const double rate = pnh.param("rate", 3.0), scene_seconds = pnh.param("scene_seconds", 60.0);
  const bool look_away = pnh.param("look_away", false);
  Listener listener(nh);
  ros::AsyncSpinner spinner(2);
  spinner.start();
  const auto scene_time = [&] {
    std::lock_guard<std::mutex> lock(listener.mutex);
    return listener.last_seq / rate;
  };
  ASSERT_TRUE(waitFor([&] { return scene_time() >= scene_seconds; }, 30.0 + 4.0 * scene_seconds * rate * 0.5))
      << "scene time reached: " << scene_time() << " s";
  ros::WallDuration(2.0).sleep();  // the last pairs' detections
  const double seconds = scene_time();

  std::lock_guard<std::mutex> lock(listener.mutex);
  // Track ids per true object, from ~objects.
  std::map<std::string, std::map<std::uint32_t, int>> ids, confirmed_ids;
  int matched = 0;
  for (const auto& [stamp, found] : listener.objects) {
    const auto truth = listener.truths.find(stamp);
    if (truth == listener.truths.end()) continue;
    for (const DetectedObject& o : found->objects) {
      const int t = nearestTruth(*truth->second, vec(o.position), false);
      if (t < 0 || o.track_id == 0) continue;
      ++matched;
      const std::string& name = truth->second->objects[static_cast<std::size_t>(t)].name;
      ++ids[name][o.track_id];
      if (o.observations >= 3) ++confirmed_ids[name][o.track_id];
    }
  }
  int best = 0, all = 0;
  for (const auto& [name, counts] : ids) {
    int top = 0;
    for (const auto& [id, n] : counts) {
      all += n;
      top = std::max(top, n);
    }
    best += top;
    std::printf("object %s: %zu track ids (%zu confirmed)\n", name.c_str(), counts.size(), confirmed_ids[name].size());
    EXPECT_EQ(confirmed_ids[name].size(), 1U) << name << ": a confirmed id switch";
  }
  const double idf1 = all > 0 ? static_cast<double>(best) / all : 0.0;
  std::printf("IDF1-style (detections carrying their object's main id): %.4f of %d tracked detections over %.0f s\n",
              idf1, all, seconds);
  const std::size_t objects_in_scene = listener.truths.begin()->second->objects.size();
  EXPECT_EQ(ids.size(), objects_in_scene);
  EXPECT_GE(idf1, 0.98);
  EXPECT_GT(matched, 50);

  // Each object's true velocity in odom per second of stamps (the time base the tracker sees).
  const GroundTruth& first_truth = *listener.truths.begin()->second;
  const GroundTruth& last_truth = *listener.truths.rbegin()->second;
  const double truth_span_s = (last_truth.header.stamp - first_truth.header.stamp).toSec();
  std::vector<Eigen::Vector3d> true_velocity;
  for (std::size_t i = 0; i < objects_in_scene; ++i) {
    true_velocity.push_back((vec(last_truth.objects[i].position_fixed) - vec(first_truth.objects[i].position_fixed)) /
                            truth_span_s);
  }
  double worst_velocity_error = 0;

  // Landmarks against the truth in odom.
  std::set<std::uint32_t> seen_ids;
  double worst_at_confirmation = 0, worst_after_20 = 0, worst_unseen = 0, worst_reacquired = 0;
  std::map<std::uint32_t, ros::Time> previous_seen, reacquired;
  int away_messages = 0, away_complete = 0, after_20 = 0, reported = 0;
  for (const auto& [stamp, landmarks] : listener.landmarks) {
    const auto truth = listener.truths.find(stamp);
    if (truth == listener.truths.end() || landmarks->header.frame_id != "odom") continue;
    std::set<int> present;
    for (const DetectedObject& l : landmarks->objects) {
      const int t = nearestTruth(*truth->second, vec(l.position), true);
      EXPECT_GE(t, 0) << "landmark " << l.track_id << " matches no object at " << vec(l.position).transpose();
      if (t < 0) continue;
      present.insert(t);
      const auto& o = truth->second->objects[static_cast<std::size_t>(t)];
      const double error = (vec(l.position) - vec(o.position_fixed)).norm() / o.range;
      if (seen_ids.insert(l.track_id).second) worst_at_confirmation = std::max(worst_at_confirmation, error);
      const bool seen_now = std::abs((stamp - l.last_seen).toSec()) < 1e-3;
      // Seen again after more than 2 s unseen: the first 2 s are the filter's transient after a coast.
      ros::Time& previous = previous_seen[l.track_id];
      if (seen_now && !previous.isZero() && (stamp - previous).toSec() > 2.0) reacquired[l.track_id] = stamp;
      if (seen_now) previous = stamp;
      const bool transient = reacquired.count(l.track_id) && (stamp - reacquired[l.track_id]).toSec() < 2.0;
      if (l.observations >= 20 && !seen_now) {  // unseen: occluded, merged or out of view
        worst_unseen = std::max(worst_unseen, error);
      } else if (l.observations >= 20 && transient) {
        worst_reacquired = std::max(worst_reacquired, error);
      } else if (l.observations >= 20) {
        const Eigen::Vector3d v(l.velocity.x, l.velocity.y, l.velocity.z);
        worst_velocity_error = std::max(worst_velocity_error, (v - true_velocity[static_cast<std::size_t>(t)]).norm());
        worst_after_20 = std::max(worst_after_20, error);
        ++after_20;
        if (error > 0.01 && ++reported <= 10) {
          std::printf("  %s #%u at scene t=%.1f s: error %.2f %% of %.2f m, %u observations, last seen %.1f s ago\n",
                      o.name.c_str(), l.track_id, truth->second->header.seq / rate, 100 * error, o.range,
                      l.observations, (stamp - l.last_seen).toSec());
        }
      }
    }
    if (lookAwayDeg(*truth->second) > 90.0) {
      ++away_messages;
      away_complete += present.size() == objects_in_scene;
    }
  }
  std::printf("landmark error / range: worst at confirmation %.2f %%, worst after >= 20 observations %.2f %% (%d, "
              "in the pair that saw it), worst while unseen %.2f %%, worst in the 2 s after 2 s or more unseen %.2f %%\n",
              100 * worst_at_confirmation, 100 * worst_after_20, after_20, 100 * worst_unseen, 100 * worst_reacquired);
  std::printf("velocity error after >= 20 observations: worst %.4f m/s (true speeds:", worst_velocity_error);
  for (const Eigen::Vector3d& v : true_velocity) std::printf(" %.3f", v.norm());
  std::printf(" m/s)\n");
  EXPECT_LE(worst_velocity_error, 0.05);
  EXPECT_LE(worst_at_confirmation, 0.02);
  EXPECT_LE(worst_after_20, 0.01);
  EXPECT_GT(after_20, 20);
  if (look_away) {
    std::printf("looking away (> 90 deg): %d pairs, all %zu objects among the landmarks in %d\n", away_messages,
                objects_in_scene, away_complete);
    EXPECT_GE(away_messages, static_cast<int>(5 * rate));
    EXPECT_EQ(away_complete, away_messages);
    EXPECT_LE(worst_unseen, 0.01) << "static buoys out of view";
  }
}

TEST(TrackingGraph, MissionServices) {
  ros::NodeHandle nh;
  ASSERT_TRUE(ros::service::waitForService("/stereo/detector/get_landmark", ros::Duration(30)));
  ros::AsyncSpinner spinner(2);
  spinner.start();
  GetLandmark get;
  get.request.target = "red_buoy";
  ASSERT_TRUE(waitFor([&] { return ros::service::call("/stereo/detector/get_landmark", get) && get.response.found; },
                      60.0))
      << get.response.message;
  EXPECT_EQ(get.response.label, "red_buoy");
  EXPECT_EQ(get.response.pose.header.frame_id, "odom");
  EXPECT_GE(get.response.observations, 3U);
  EXPECT_GT(get.response.position_covariance[0], 0.0);
  GetLandmark by_id;
  by_id.request.track_id = get.response.track_id;
  ASSERT_TRUE(ros::service::call("/stereo/detector/get_landmark", by_id));
  EXPECT_TRUE(by_id.response.found);
  GetLandmark unknown;
  unknown.request.target = "sea_serpent";
  ASSERT_TRUE(ros::service::call("/stereo/detector/get_landmark", unknown));
  EXPECT_FALSE(unknown.response.found);
  EXPECT_NE(unknown.response.message.find("no target named"), std::string::npos) << unknown.response.message;

  // Paused: no pair processed; resumed: pairs again.
  int objects = 0;
  std::mutex mutex;
  ros::Subscriber sub = nh.subscribe<DetectedObjectArray>("/stereo/detector/objects", 10,
                                                          [&](const DetectedObjectArrayConstPtr&) {
                                                            std::lock_guard<std::mutex> lock(mutex);
                                                            ++objects;
                                                          });
  std_srvs::SetBool enable;
  enable.request.data = false;
  ASSERT_TRUE(ros::service::call("/stereo/detector/enable", enable));
  EXPECT_TRUE(enable.response.success);
  ros::WallDuration(2.0).sleep();  // pairs in flight
  {
    std::lock_guard<std::mutex> lock(mutex);
    objects = 0;
  }
  ros::WallDuration(3.0).sleep();
  {
    std::lock_guard<std::mutex> lock(mutex);
    EXPECT_EQ(objects, 0) << "pairs processed while paused";
  }
  enable.request.data = true;
  ASSERT_TRUE(ros::service::call("/stereo/detector/enable", enable));
  EXPECT_TRUE(waitFor(
      [&] {
        std::lock_guard<std::mutex> lock(mutex);
        return objects >= 2;
      },
      30.0));

  std_srvs::Trigger reset;
  ASSERT_TRUE(ros::service::call("/stereo/detector/reset_tracks", reset));
  EXPECT_TRUE(reset.response.success);
  by_id.response = GetLandmark::Response();
  ASSERT_TRUE(ros::service::call("/stereo/detector/get_landmark", by_id));
  EXPECT_FALSE(by_id.response.found) << "ids are never reused: the old track is gone for good";
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "tracking_graph_test");
  return RUN_ALL_TESTS();
}
