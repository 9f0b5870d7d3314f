// SPDX-License-Identifier: BSD-3-Clause
// The detector nodelet in a running graph: fed by the simulated head (Live), by `rosbag play --clock` of a
// rendered bag (Playback), or by this test's own messages (HandFedDetector). One executable; each .test file
// picks its case with --gtest_filter.
#include <cv_bridge/cv_bridge.h>
#include <diagnostic_msgs/DiagnosticArray.h>
#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <tf2_ros/buffer.h>
#include <tf2_msgs/TFMessage.h>
#include <tf2_ros/transform_listener.h>
#include <visualization_msgs/MarkerArray.h>

#include <algorithm>
#include <utility>
#include <cctype>
#include <cstdio>
#include <map>
#include <mutex>
#include <tuple>

#include "ros_test_helpers.h"
#include "underwater_stereo/DetectedObjectArray.h"
#include "underwater_stereo/GroundTruth.h"
#include "underwater_stereo/detection/detector.h"
#include "underwater_stereo/ros_glue/calibration_conversions.h"
#include "underwater_stereo/sim/renderer.h"

using namespace underwater_stereo;
using underwater_stereo::test::waitFor;

namespace {

constexpr char kSmallPool[] = UWS_SOURCE_DIR "/test/scenes/small_pool.yaml";

/// Everything the detector publishes, by stamp.
struct Listener {
  explicit Listener(ros::NodeHandle& nh) {
    objects_sub = nh.subscribe("/stereo/detector/objects", 50, &Listener::onObjects, this);
    truth_sub = nh.subscribe("/stereo/ground_truth", 50, &Listener::onTruth, this);
    markers_sub = nh.subscribe("/stereo/detector/markers", 50, &Listener::onMarkers, this);
    diagnostics_sub = nh.subscribe("/diagnostics", 50, &Listener::onDiagnostics, this);
  }
  void onObjects(const DetectedObjectArrayConstPtr& m) {
    std::lock_guard<std::mutex> lock(mutex);
    objects[m->header.stamp] = m;
    arrival.push_back(m->header.stamp);
  }
  void onTruth(const GroundTruthConstPtr& m) {
    std::lock_guard<std::mutex> lock(mutex);
    truths[m->header.stamp] = m;
  }
  void onMarkers(const visualization_msgs::MarkerArrayConstPtr& m) {
    std::lock_guard<std::mutex> lock(mutex);
    if (!m->markers.empty()) markers[m->markers.front().header.stamp] = m;
  }
  void onDiagnostics(const diagnostic_msgs::DiagnosticArrayConstPtr& m) {
    std::lock_guard<std::mutex> lock(mutex);
    for (const auto& s : m->status) {
      if (s.name.find("detector") != std::string::npos && s.name.find("tracking") == std::string::npos) {
        diagnostics.push_back(s);
      }
    }
  }
  std::mutex mutex;
  std::map<ros::Time, DetectedObjectArrayConstPtr> objects;
  std::vector<ros::Time> arrival;  ///< objects stamps in the order they came
  std::map<ros::Time, GroundTruthConstPtr> truths;
  std::map<ros::Time, visualization_msgs::MarkerArrayConstPtr> markers;
  std::vector<diagnostic_msgs::DiagnosticStatus> diagnostics;
  ros::Subscriber objects_sub, truth_sub, markers_sub, diagnostics_sub;
};

/// Checks one objects message against its ground truth; returns the number of objects checked.
int expectMatchesTruth(const DetectedObjectArray& found, const GroundTruth& truth) {
  int checked = 0;
  for (const auto& gt : truth.objects) {
    if (gt.visible_pixels < 400) continue;
    const auto d = std::find_if(found.objects.begin(), found.objects.end(),
                                [&](const DetectedObject& o) { return o.colour == gt.colour; });
    if (d == found.objects.end()) {
      ADD_FAILURE() << gt.name << " not found at " << found.header.stamp;
      continue;
    }
    EXPECT_EQ(d->shape, gt.shape) << gt.name;
    EXPECT_NEAR(d->range, gt.range, 0.03 * gt.range) << gt.name;
    const double dx = d->position.x - gt.position.x, dy = d->position.y - gt.position.y,
                 dz = d->position.z - gt.position.z;
    EXPECT_LT(std::sqrt(dx * dx + dy * dy + dz * dz), 0.03 * gt.range) << gt.name;
    ++checked;
  }
  return checked;
}

}  // namespace

TEST(DetectorGraph, Live) {
  ros::NodeHandle nh;
  Listener listener(nh);
  tf2_ros::Buffer tf_buffer;
  tf2_ros::TransformListener tf_listener(tf_buffer);
  ros::AsyncSpinner spinner(2);
  spinner.start();
  auto matched = [&] {
    std::lock_guard<std::mutex> lock(listener.mutex);
    int n = 0;
    for (const auto& [stamp, objects] : listener.objects) n += listener.truths.count(stamp) && listener.markers.count(stamp);
    return n;
  };
  ASSERT_TRUE(waitFor([&] { return matched() >= 5; }, 80.0)) << "objects with ground truth and markers: " << matched();
  // The first kCheckedMessages matched messages, copied out: the checks below wait for TF frames, and must neither
  // hold the listener's lock (its callbacks would queue behind them) nor grow with the messages still arriving.
  constexpr int kCheckedMessages = 10;
  using Matched =
      std::tuple<ros::Time, DetectedObjectArrayConstPtr, GroundTruthConstPtr, visualization_msgs::MarkerArrayConstPtr>;
  std::vector<Matched> checked;
  {
    std::lock_guard<std::mutex> lock(listener.mutex);
    for (const auto& [stamp, found] : listener.objects) {
      const auto truth = listener.truths.find(stamp);
      const auto markers = listener.markers.find(stamp);
      if (truth == listener.truths.end() || markers == listener.markers.end()) continue;
      checked.emplace_back(stamp, found, truth->second, markers->second);
      if (static_cast<int>(checked.size()) == kCheckedMessages) break;
    }
  }
  int messages = 0, objects = 0;
  for (const auto& [stamp, found, truth, markers] : checked) {
    ++messages;
    objects += expectMatchesTruth(*found, *truth);
    EXPECT_EQ(found->header.frame_id, "stereo_left_optical_frame");
    EXPECT_EQ(found->quality.status, ImageQuality::OK);
    // DELETEALL, then a shape and a label per object.
    EXPECT_EQ(markers->markers.size(), 1 + 2 * found->objects.size());
    // A TF frame per confirmed track (3 observations), named by its target or colour, at its filtered position.
    for (const DetectedObject& o : found->objects) {
      if (o.observations < 3) continue;
      const std::string frame = (o.label.empty() ? o.colour : o.label) + "_" + std::to_string(o.track_id);
      EXPECT_TRUE(tf_buffer.canTransform("stereo_left_optical_frame", frame, stamp, ros::Duration(1.0))) << frame;
      if (tf_buffer.canTransform("stereo_left_optical_frame", frame, stamp)) {
        const auto t = tf_buffer.lookupTransform("stereo_left_optical_frame", frame, stamp);
        EXPECT_NEAR(t.transform.translation.z, o.position.z, 0.05) << frame;
      }
    }
  }
  EXPECT_GE(messages, 5);
  EXPECT_GE(objects, 2 * messages);
  spinner.stop();
}

TEST(DetectorGraph, PlaybackGivesTheDetectionsOfTheSameFramesLive) {
  // The bag holds frames k = 0.. of small_pool at `rate` Hz from `start_time`. "Live" detections of the same
  // frames: the same renderer and the same detector, run here without ROS.
  ros::NodeHandle nh, pnh("~");
  const double rate = pnh.param("rate", 5.0), start_time = pnh.param("start_time", 1.6e9);
  const int frames = pnh.param("frames", 6);
  Listener listener(nh);
  ros::AsyncSpinner spinner(2);
  spinner.start();
  auto received = [&] {
    std::lock_guard<std::mutex> lock(listener.mutex);
    return static_cast<int>(listener.objects.size());
  };
  ASSERT_TRUE(waitFor([&] { return received() >= frames - 1; }, 100.0)) << received() << " of " << frames;
  spinner.stop();
  sim::Scene scene = sim::loadSceneFile(kSmallPool);
  const sim::Renderer renderer(scene);
  Detector live(loadDetectorConfigFile(UWS_SOURCE_DIR "/config/detector.yaml"), renderer.calibration());
  std::lock_guard<std::mutex> lock(listener.mutex);
  int compared = 0;
  for (const auto& [stamp, found] : listener.objects) {
    const int k = static_cast<int>(std::lround((stamp.toSec() - start_time) * rate));
    const sim::RenderedPair pair = renderer.render(k / rate, k);
    // As the nodelet gets them: the camera's Bayer frames, unconverted.
    const DetectionResult expected =
        live.detect(RawFrame(pair.left, pixelLayoutOf(pair.encoding)), RawFrame(pair.right, pixelLayoutOf(pair.encoding)));
    ASSERT_EQ(found->objects.size(), expected.objects.size()) << "frame " << k;
    for (std::size_t i = 0; i < expected.objects.size(); ++i) {
      EXPECT_EQ(found->objects[i].colour, expected.objects[i].colour);
      EXPECT_EQ(found->objects[i].shape, shapeName(expected.objects[i].shape));
      EXPECT_NEAR(found->objects[i].range, expected.objects[i].range_m, 1e-4) << "frame " << k;
      EXPECT_NEAR(found->objects[i].position.x, expected.objects[i].position_m.x(), 1e-4);
    }
    ++compared;
  }
  EXPECT_GE(compared, frames - 1);
}

namespace {

/// Publishes hand-made pairs on /stereo/left|right/image_raw + camera_info.
struct Publisher {
  explicit Publisher(ros::NodeHandle& nh)
      : left(nh.advertise<sensor_msgs::Image>("/stereo/left/image_raw", 50)),
        right(nh.advertise<sensor_msgs::Image>("/stereo/right/image_raw", 50)),
        left_info(nh.advertise<sensor_msgs::CameraInfo>("/stereo/left/camera_info", 50)),
        right_info(nh.advertise<sensor_msgs::CameraInfo>("/stereo/right/camera_info", 50)) {}

  void send(sensor_msgs::Image l, sensor_msgs::CameraInfo li, sensor_msgs::Image r, sensor_msgs::CameraInfo ri,
            ros::Time stamp, double right_offset_s = 0.0) {
    l.header.stamp = li.header.stamp = stamp;
    r.header.stamp = ri.header.stamp = stamp + ros::Duration(right_offset_s);
    l.header.frame_id = li.header.frame_id = r.header.frame_id = ri.header.frame_id = "stereo_left_optical_frame";
    left_info.publish(li);
    right_info.publish(ri);
    left.publish(l);
    right.publish(r);
  }
  ros::Publisher left, right, left_info, right_info;
};

/// The detector fed with this test's own messages: one rendered pair of the small pool (two buoys) as bgr8
/// images with their camera_info, published once the detector listens.
class HandFedDetector : public ::testing::Test {
 protected:
  void SetUp() override {
    spinner.start();
    // Every link up before the first message: the detector's four inputs and this test's objects and diagnostics.
    ASSERT_TRUE(waitFor(
        [&] {
          return pub.left.getNumSubscribers() > 0 && pub.right.getNumSubscribers() > 0 &&
                 pub.left_info.getNumSubscribers() > 0 && pub.right_info.getNumSubscribers() > 0 &&
                 listener.objects_sub.getNumPublishers() > 0 && listener.diagnostics_sub.getNumPublishers() > 0;
        },
        30));
    ros::WallDuration(1.0).sleep();
    sim::Scene scene = sim::loadSceneFile(kSmallPool);
    scene.sensor.encoding = "bgr8";
    const sim::Renderer renderer(scene);
    pair = renderer.render(0, 0);
    left = *cv_bridge::CvImage(std_msgs::Header(), "bgr8", pair.left).toImageMsg();
    right = *cv_bridge::CvImage(std_msgs::Header(), "bgr8", pair.right).toImageMsg();
    left_info = ros_glue::toCameraInfo(renderer.calibration().left);
    right_info = ros_glue::toCameraInfo(renderer.calibration().right);
  }
  void TearDown() override { spinner.stop(); }

  /// The first diagnostic of `level` whose message holds `text`, waited for up to `timeout_s`; "" when none came.
  std::string diagnosed(unsigned char level, const std::string& text, double timeout_s) {
    std::string message;
    waitFor(
        [&] {
          std::lock_guard<std::mutex> lock(listener.mutex);
          for (const auto& d : listener.diagnostics) {
            if (d.level == level && d.message.find(text) != std::string::npos) {
              message = d.message;
              return true;
            }
          }
          return false;
        },
        timeout_s);
    return message;
  }

  /// Whether the objects of the pair stamped `stamp` are published within 20 s.
  bool published(const ros::Time& stamp) {
    return waitFor(
        [&] {
          std::lock_guard<std::mutex> lock(listener.mutex);
          return listener.objects.count(stamp) > 0;
        },
        20.0);
  }

  ros::NodeHandle nh;
  Listener listener{nh};
  Publisher pub{nh};
  ros::AsyncSpinner spinner{2};
  sim::RenderedPair pair;
  sensor_msgs::Image left, right;
  sensor_msgs::CameraInfo left_info, right_info;
};

/// Value of `key` in a diagnostic status; "" if absent.
std::string diagnosticValue(const diagnostic_msgs::DiagnosticStatus& s, const std::string& key) {
  for (const auto& kv : s.values) {
    if (kv.key == key) return kv.value;
  }
  return "";
}

}  // namespace

// Pairs sent faster than they are processed, slow ones (two objects) between fast ones (black frames: spoiled,
// no search), to several workers: every result belongs to its own pair, results come in the order the pairs
// were sent, and every synchronised pair is either published, dropped or bad input.
TEST_F(HandFedDetector, BurstOfPairsIsPublishedInArrivalOrderByParallelWorkers) {
  const cv::Mat black_frame = cv::Mat::zeros(pair.left.size(), CV_8UC3);
  const sensor_msgs::Image black = *cv_bridge::CvImage(std_msgs::Header(), "bgr8", black_frame).toImageMsg();

  constexpr int kPairs = 24;
  const ros::Time first(2000.0);
  for (int i = 0; i < kPairs; ++i) {
    const bool slow = i % 2 == 0;
    pub.send(slow ? left : black, left_info, slow ? right : black, right_info, first + ros::Duration(0.1 * i));
    ros::WallDuration(0.002).sleep();
  }
  // Settled: the diagnostics' counters account for every pair (published once a second).
  std::string received, processed, dropped, bad;
  const bool settled = waitFor(
      [&] {
        std::lock_guard<std::mutex> lock(listener.mutex);
        if (listener.diagnostics.empty()) return false;
        const auto& d = listener.diagnostics.back();
        received = diagnosticValue(d, "pairs received");
        processed = diagnosticValue(d, "pairs processed");
        dropped = diagnosticValue(d, "pairs dropped (detector busy)");
        bad = diagnosticValue(d, "bad input pairs");
        return !received.empty() && std::stol(received) > 0 &&
               std::stol(processed) + std::stol(dropped) + std::stol(bad) == std::stol(received) &&
               std::stol(processed) == static_cast<long>(listener.arrival.size());
      },
      30.0);
  std::lock_guard<std::mutex> lock(listener.mutex);
  EXPECT_TRUE(settled) << "received " << received << ", processed " << processed << ", dropped " << dropped
                       << ", bad " << bad << ", published " << listener.arrival.size();
  std::cout << "received " << received << ", processed " << processed << ", dropped " << dropped << std::endl;
  EXPECT_EQ(bad, "0");
  for (int k = 0; k < kRejectionStageCount; ++k) {  // what the detector looked at and did not report, by stage
    const std::string key = "regions rejected: " + rejectionStageName(static_cast<RejectionStage>(k));
    const std::string count = diagnosticValue(listener.diagnostics.back(), key);
    EXPECT_TRUE(!count.empty() && std::all_of(count.begin(), count.end(), ::isdigit)) << key << ": '" << count << "'";
  }
  ASSERT_GE(listener.arrival.size(), 4U) << "too few pairs were processed to see their order";
  for (std::size_t k = 1; k < listener.arrival.size(); ++k) {
    EXPECT_LT(listener.arrival[k - 1], listener.arrival[k]) << "results published out of order at " << k;
  }
  for (const auto& [stamp, found] : listener.objects) {
    const int i = static_cast<int>(std::lround((stamp - first).toSec() / 0.1));
    if (i % 2 == 0) {
      EXPECT_EQ(found->objects.size(), 2U) << "pair " << i << " (two objects)";
    } else {
      EXPECT_TRUE(found->objects.empty()) << "pair " << i << " (black)";
    }
  }
}

TEST_F(HandFedDetector, BadInputIsReportedAndSkippedThenAValidPairIsProcessed) {

  struct Case {
    std::string name, expected_in_message;
    std::function<void(sensor_msgs::Image&, sensor_msgs::CameraInfo&, sensor_msgs::Image&, sensor_msgs::CameraInfo&)> spoil;
    double right_offset_s = 0.0;
    int pairs = 1;  ///< sent this many times (stamps 0.1 s apart); the last must be refused
  };
  // Every expected text is one no other case's message holds: an error stays in the summary for 5 s.
  const std::vector<Case> cases{
      {"wrong encoding", "encoding '16UC1'",
       [](auto& l, auto&, auto&, auto&) {
         l.encoding = "16UC1";
         l.step = l.width * 2;
         l.data.resize(l.step * l.height);
       }},
      {"left/right size mismatch", "is 640x400 but",
       [&](auto&, auto&, auto& r, auto&) {
         cv::Mat small;
         cv::resize(pair.right, small, cv::Size(320, 200));
         r = *cv_bridge::CvImage(std_msgs::Header(), "bgr8", small).toImageMsg();
       }},
      {"uncalibrated camera_info", "(camera not calibrated)",
       [](auto&, auto& li, auto&, auto&) { li.K.fill(0.0); li.P.fill(0.0); }},
      {"NaN camera_info", "K, R or P contains NaN/Inf",
       [](auto&, auto&, auto&, auto& ri) { ri.P[0] = std::numeric_limits<double>::quiet_NaN(); }},
      {"empty image", "image size 0x0 is outside",
       [](auto& l, auto&, auto&, auto&) {
         l.data.clear();
         l.width = l.height = 0;
       }},
      {"unsynchronised stamps", "apart", [](auto&, auto&, auto&, auto&) {}, 0.05},
      {"1 px image", "image size 1x1 is outside",
       [](auto& l, auto&, auto&, auto&) {
         l.width = l.height = 1;
         l.step = 3;
         l.data.assign(3, 0);
       }},
      {"width overflowing 32 bits", "image size 2147483648x400",
       [](auto&, auto&, auto& r, auto&) {
         r.width = 0x80000000U;
         r.step = 16;
       }},
      {"step shorter than a row", "step 100 is below",
       [](auto& l, auto&, auto&, auto&) { l.step = 100; }},
      {"implausible baseline", "baseline -P_right[3] / P_right[0] = 1e+12 m is outside",
       [](auto&, auto&, auto&, auto& ri) { ri.P[3] = -ri.P[0] * 1e12; }},
      {"unknown distortion model", "distortion_model 'equidistant' is not supported",
       [](auto&, auto& li, auto&, auto&) { li.distortion_model = "equidistant"; }},
      {"absurd distortion coefficient", "distortion coefficient 500",
       [](auto&, auto& li, auto&, auto&) { li.D = {500, -500, 0, 0, 0}; }},
      {"focal length 1e-6 px", "K[0] (fx) = 1e-06 px",
       [](auto&, auto& li, auto&, auto&) { li.K[0] = 1e-6; }},
      {"left and right images swapped", "left and right images look swapped",
       [](auto& l, auto&, auto& r, auto&) { std::swap(l.data, r.data); }, 0.0, 3},
  };
  ros::Time stamp(1000.0);
  for (const Case& c : cases) {
    sensor_msgs::Image l = left, r = right;
    sensor_msgs::CameraInfo li = left_info, ri = right_info;
    c.spoil(l, li, r, ri);
    {
      std::lock_guard<std::mutex> lock(listener.mutex);
      listener.diagnostics.clear();
    }
    stamp += ros::Duration(1.0);
    for (int k = 1; k < c.pairs; ++k) {  // each processed before the next: none dropped while the workers are busy
      pub.send(l, li, r, ri, stamp, c.right_offset_s);
      EXPECT_TRUE(published(stamp)) << c.name << ": pair " << k << " of " << c.pairs << " was not processed";
      stamp += ros::Duration(0.1);
    }
    pub.send(l, li, r, ri, stamp, c.right_offset_s);
    // Approximate sync emits a set once later messages show it is the best one: follow with a second.
    if (c.right_offset_s != 0) pub.send(l, li, r, ri, stamp + ros::Duration(0.5), c.right_offset_s);
    const bool reported = !diagnosed(diagnostic_msgs::DiagnosticStatus::ERROR, c.expected_in_message, 10.0).empty();
    EXPECT_TRUE(reported) << c.name << ": no ERROR diagnostic mentioning '" << c.expected_in_message << "'";
    std::lock_guard<std::mutex> lock(listener.mutex);
    EXPECT_EQ(listener.objects.count(stamp), 0U) << c.name << ": an objects message was published";
  }
  stamp += ros::Duration(1.0);
  pub.send(left, left_info, right, right_info, stamp);
  ASSERT_TRUE(published(stamp)) << "the valid pair after the bad ones was not processed";
  std::lock_guard<std::mutex> lock(listener.mutex);
  EXPECT_EQ(listener.objects[stamp]->objects.size(), 2U);
}

// Grey (mono8) pairs are valid input, but no designated colour can be named in them: processed, nothing found, and
// the diagnostic WARNs saying why (not a silent "detecting"); colour pairs after them bring "detecting" back.
TEST_F(HandFedDetector, BadInputOfMonoPairsWarnsThatNoColourCanBeFound) {
  cv::Mat grey_left, grey_right;
  cv::cvtColor(pair.left, grey_left, cv::COLOR_BGR2GRAY);
  cv::cvtColor(pair.right, grey_right, cv::COLOR_BGR2GRAY);
  const sensor_msgs::Image l = *cv_bridge::CvImage(std_msgs::Header(), "mono8", grey_left).toImageMsg();
  const sensor_msgs::Image r = *cv_bridge::CvImage(std_msgs::Header(), "mono8", grey_right).toImageMsg();
  {
    std::lock_guard<std::mutex> lock(listener.mutex);
    listener.diagnostics.clear();
  }
  ros::Time stamp(3000.0);
  pub.send(l, left_info, r, right_info, stamp);
  ASSERT_TRUE(published(stamp)) << "the mono8 pair was not processed";
  {
    std::lock_guard<std::mutex> lock(listener.mutex);
    EXPECT_TRUE(listener.objects[stamp]->objects.empty());
  }
  EXPECT_FALSE(diagnosed(diagnostic_msgs::DiagnosticStatus::WARN, "mono8 images carry no colour", 15.0).empty())
      << "no WARN diagnostic saying that grey images carry no colour";
  {
    std::lock_guard<std::mutex> lock(listener.mutex);
    listener.diagnostics.clear();
  }
  stamp += ros::Duration(1.0);
  pub.send(left, left_info, right, right_info, stamp);
  EXPECT_FALSE(diagnosed(diagnostic_msgs::DiagnosticStatus::OK, "detecting", 15.0).empty())
      << "the diagnostic did not return to detecting after a colour pair";
}

// A usable frame darker than quality.enhance_below is searched at dark_search_width_px across (a quarter of
// 1920x1200): the diagnostic says so in its summary, with the scale and a count of such pairs.
TEST_F(HandFedDetector, DarkPairsAreSaidToBeSearchedCoarser) {
  sim::Scene scene = sim::loadSceneFile(UWS_SOURCE_DIR "/config/scenes/pool_dark.yaml");  // mean luma ~27
  scene.sensor.encoding = "bgr8";
  const sim::Renderer renderer(scene);
  const sim::RenderedPair dark = renderer.render(0, 0);
  {
    std::lock_guard<std::mutex> lock(listener.mutex);
    listener.diagnostics.clear();
  }
  const ros::Time stamp(4000.0);
  pub.send(*cv_bridge::CvImage(std_msgs::Header(), "bgr8", dark.left).toImageMsg(),
           ros_glue::toCameraInfo(renderer.calibration().left),
           *cv_bridge::CvImage(std_msgs::Header(), "bgr8", dark.right).toImageMsg(),
           ros_glue::toCameraInfo(renderer.calibration().right), stamp);
  ASSERT_TRUE(published(stamp)) << "the dark pair was not processed";
  EXPECT_FALSE(diagnosed(diagnostic_msgs::DiagnosticStatus::OK, "searched coarser, at 0.25 of full size", 15.0).empty())
      << "no diagnostic saying that the dark pair was searched at a quarter";
  std::lock_guard<std::mutex> lock(listener.mutex);
  const auto said = std::find_if(listener.diagnostics.rbegin(), listener.diagnostics.rend(), [](const auto& d) {
    return d.message.find("searched coarser") != std::string::npos;
  });
  ASSERT_NE(said, listener.diagnostics.rend());
  EXPECT_EQ(diagnosticValue(*said, "search scale"), "0.25");
  EXPECT_EQ(diagnosticValue(*said, "pairs searched coarser (dark)"), "1");
}

// Exact sync (detector_exact_sync.test): a valid calibration that changes its distortion vector's length
// (5 -> 0 -> 4 -> 8 -> 5) rebuilds the rectification maps and every pair is processed.
TEST_F(HandFedDetector, ExactSyncPairsWhoseDistortionVectorChangesLengthAreAllProcessed) {
  // Each pair sent once the one before is out: every change rebuilds the maps, and pairs sent faster than a loaded
  // machine rebuilds them would be dropped as the detector's queue fills (max_waiting_pairs), which is not what this
  // tests.
  ros::Time stamp(3000.0);
  int i = 0;
  for (const std::size_t n : {5, 0, 4, 8, 5}) {
    sensor_msgs::CameraInfo li = left_info, ri = right_info;
    li.D.assign(n, 0.0);
    ri.D.assign(n, 0.0);
    if (n == 8) li.distortion_model = ri.distortion_model = "rational_polynomial";
    stamp += ros::Duration(1.0);
    pub.send(left, li, right, ri, stamp);
    EXPECT_TRUE(published(stamp)) << "pair " << i << " (distortion vector of " << n << ") was not processed";
    std::lock_guard<std::mutex> lock(listener.mutex);
    if (listener.objects.count(stamp)) {
      EXPECT_EQ(listener.objects[stamp]->objects.size(), 2U) << "pair " << i;
    }
    ++i;
  }
}

// Exact sync: a left image without a right one and a pair whose stamps differ by 1 ms never pair; once the
// synchroniser's queue has moved past them they are counted, and the diagnostic WARNs naming the difference.
TEST_F(HandFedDetector, ExactSyncCountsImagesThatNeverPairAndWarns) {
  const cv::Mat black_frame = cv::Mat::zeros(pair.left.size(), CV_8UC3);
  const sensor_msgs::Image black = *cv_bridge::CvImage(std_msgs::Header(), "bgr8", black_frame).toImageMsg();
  ros::Time stamp(4000.0);
  {
    std::lock_guard<std::mutex> lock(listener.mutex);
    listener.diagnostics.clear();
  }
  stamp += ros::Duration(1.0);
  sensor_msgs::Image lonely = black;  // a left image (and its infos) without any right image
  lonely.header.stamp = stamp;
  sensor_msgs::CameraInfo li = left_info, ri = right_info;
  li.header.stamp = ri.header.stamp = stamp;
  pub.left_info.publish(li);
  pub.right_info.publish(ri);
  pub.left.publish(lonely);
  stamp += ros::Duration(1.0);
  pub.send(black, left_info, black, right_info, stamp, 0.001);  // 1 ms apart: exact sync never pairs them
  for (int i = 0; i < 12; ++i) {  // enough valid pairs to move every queue past them
    stamp += ros::Duration(0.1);
    pub.send(black, left_info, black, right_info, stamp);
    ros::WallDuration(0.05).sleep();
  }
  const std::string last = diagnosed(diagnostic_msgs::DiagnosticStatus::WARN, "never paired", 15.0);
  ASSERT_FALSE(last.empty()) << "no WARN diagnostic about images that never paired";
  EXPECT_NE(last.find(" ms away"), std::string::npos) << last;
  // The three are counted at two moments ~50 ms apart (as each queue moves past them): a report between them
  // holds part of the counts. The totals are read from a report made after every image was sent.
  {
    std::lock_guard<std::mutex> lock(listener.mutex);
    listener.diagnostics.clear();
  }
  std::string left_unpaired, right_unpaired;
  ASSERT_TRUE(waitFor(
      [&] {
        std::lock_guard<std::mutex> lock(listener.mutex);
        if (listener.diagnostics.empty()) return false;
        left_unpaired = diagnosticValue(listener.diagnostics.back(), "left images never paired");
        right_unpaired = diagnosticValue(listener.diagnostics.back(), "right images never paired");
        return true;
      },
      15.0))
      << "no detector diagnostic after the WARN";
  EXPECT_EQ(left_unpaired, "2");
  EXPECT_EQ(right_unpaired, "1");
}

int main(int argc, char** argv) {
  // Line-buffered: a test that rostest kills at its time limit still shows how far it got in its log.
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "detector_graph_test");
  return RUN_ALL_TESTS();
}

// Tracking's bad input, with fixed_frame odom (test/tracking_bad_input.test): no transform yet (tracked in the
// stereo frame), then one (tracks move to odom), a stamp going backwards, an odometry jump, a transform that
// stops arriving. Each is said by the tracking diagnostic; nothing crashes.
TEST_F(HandFedDetector, TrackingReportsMissingTransformsBackwardStampsAndJumps) {
  std::mutex mutex;
  std::map<ros::Time, DetectedObjectArrayConstPtr> landmarks;
  std::vector<std::string> problems;
  ros::Subscriber landmarks_sub = nh.subscribe<DetectedObjectArray>(
      "/stereo/detector/landmarks", 50, [&](const DetectedObjectArrayConstPtr& m) {
        std::lock_guard<std::mutex> lock(mutex);
        landmarks[m->header.stamp] = m;
      });
  ros::Subscriber diagnostics_sub = nh.subscribe<diagnostic_msgs::DiagnosticArray>(
      "/diagnostics", 50, [&](const diagnostic_msgs::DiagnosticArrayConstPtr& m) {
        std::lock_guard<std::mutex> lock(mutex);
        for (const auto& s : m->status) {
          if (s.name.find("tracking") != std::string::npos) {
            problems.push_back(s.message + " | " + diagnosticValue(s, "last tracking problem"));
          }
        }
      });
  // Published by hand (not a TransformBroadcaster) so that the test can wait for the detector to listen.
  ros::Publisher tf_pub = nh.advertise<tf2_msgs::TFMessage>("/tf", 50);
  // Whatever the detector says before these subscriptions connect is lost: wait for them first.
  ASSERT_TRUE(waitFor(
      [&] {
        return landmarks_sub.getNumPublishers() > 0 && diagnostics_sub.getNumPublishers() > 0 &&
               tf_pub.getNumSubscribers() > 0;
      },
      30.0))
      << "the detector's landmarks, diagnostics or transform listener did not connect";
  const auto send = [&](ros::Time stamp, double camera_x, bool with_tf) -> DetectedObjectArrayConstPtr {
    if (with_tf) {
      tf2_msgs::TFMessage tf;
      tf.transforms.resize(1);
      geometry_msgs::TransformStamped& t = tf.transforms[0];
      t.header.stamp = stamp;
      t.header.frame_id = "odom";
      t.child_frame_id = "stereo_left_optical_frame";
      t.transform.translation.x = camera_x;
      t.transform.rotation.w = 1.0;
      tf_pub.publish(tf);
      ros::WallDuration(0.1).sleep();
    }
    pub.send(left, left_info, right, right_info, stamp);
    DetectedObjectArrayConstPtr found;
    waitFor(
        [&] {
          std::lock_guard<std::mutex> lock(mutex);
          const auto l = landmarks.find(stamp);
          if (l == landmarks.end()) return false;
          found = l->second;
          return true;
        },
        20.0);
    return found;
  };
  const auto said = [&](const std::string& text) {
    return waitFor(
        [&] {
          std::lock_guard<std::mutex> lock(mutex);
          return std::any_of(problems.begin(), problems.end(),
                             [&](const std::string& p) { return p.find(text) != std::string::npos; });
        },
        10.0);
  };

  ros::Time stamp(3000.0);
  DetectedObjectArrayConstPtr l;
  for (int k = 0; k < 3; ++k) l = send(stamp += ros::Duration(0.2), 0.0, false);
  ASSERT_TRUE(l);
  EXPECT_EQ(l->header.frame_id, "stereo_left_optical_frame") << "no transform yet: tracked in the stereo frame";
  EXPECT_EQ(l->objects.size(), 2U);
  EXPECT_TRUE(said("no transform from odom yet"));

  for (int k = 0; k < 3; ++k) l = send(stamp += ros::Duration(0.2), 0.5, true);
  ASSERT_TRUE(l);
  EXPECT_EQ(l->header.frame_id, "odom");
  ASSERT_EQ(l->objects.size(), 2U);
  const std::uint32_t first_odom_id = std::min(l->objects[0].track_id, l->objects[1].track_id);
  EXPECT_GT(first_odom_id, 2U) << "tracks restarted in odom with new ids";
  EXPECT_NEAR(std::min(l->objects[0].position.x, l->objects[1].position.x), 0.5 - 0.4, 0.05) << "the red buoy";

  const ros::Time latest = stamp;
  l = send(stamp - ros::Duration(0.1), 0.5, true);  // late
  EXPECT_TRUE(said("stamp went backwards"));

  l = send(stamp = latest + ros::Duration(0.2), 5.5, true);  // odometry jumped 5 m in 0.2 s
  EXPECT_TRUE(said("camera pose jumped"));
  ASSERT_TRUE(l);
  for (const auto& o : l->objects) EXPECT_GT(o.track_id, first_odom_id + 1) << "tracks reset";

  l = send(stamp += ros::Duration(5.0), 5.5, false);  // the transform no longer arrives
  EXPECT_TRUE(said("no transform odom <- stereo_left_optical_frame"));
  std::lock_guard<std::mutex> lock(listener.mutex);
  ASSERT_EQ(listener.objects.count(stamp), 1U) << "the pair is still published";
  for (const auto& o : listener.objects[stamp]->objects) EXPECT_EQ(o.track_id, 0U);
}
