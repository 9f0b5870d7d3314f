// SPDX-License-Identifier: BSD-3-Clause
// Runs the Detector on synchronised stereo pairs: objects, annotated image and snapshot, markers, the
// objects' cloud, a TF frame per object, diagnostics. The pairs go to an OrderedWorkerPool (`worker_threads`
// workers, `max_waiting_pairs` waiting, the oldest beyond dropped and counted, results published in the order
// the pairs arrived); this file holds the configuration, the conversions and the publishing.
#include <cv_bridge/cv_bridge.h>
#include <diagnostic_updater/diagnostic_updater.h>
#include <dynamic_reconfigure/server.h>
#include <image_transport/image_transport.h>
#include <image_transport/subscriber_filter.h>
#include <message_filters/subscriber.h>
#include <message_filters/sync_policies/approximate_time.h>
#include <message_filters/sync_policies/exact_time.h>
#include <message_filters/synchronizer.h>
#include <nodelet/nodelet.h>
#include <opencv2/core/utility.hpp>
#include <pluginlib/class_list_macros.hpp>
#include <ros/package.h>
#include <ros/ros.h>
#include <std_srvs/SetBool.h>
#include <tf2/LinearMath/Quaternion.h>
#include <tf2_ros/static_transform_broadcaster.h>

#include <boost/bind/bind.hpp>

#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

#include "underwater_stereo/DetectorTuningConfig.h"
#include "underwater_stereo/common/ordered_worker_pool.h"
#include "underwater_stereo/config/yaml_fields.h"
#include "underwater_stereo/detection/annotator.h"
#include "underwater_stereo/detection/detector.h"
#include "underwater_stereo/detection/raw_frame.h"
#include "underwater_stereo/detection/stereo_order.h"
#include "underwater_stereo/ros_glue/compressed_image_publisher.h"
#include "underwater_stereo/ros_glue/detector_reconfigure.h"
#include "underwater_stereo/ros_glue/detection_conversions.h"
#include "underwater_stereo/ros_glue/object_tracking.h"
#include "underwater_stereo/ros_glue/pairing_monitor.h"
#include "underwater_stereo/ros_glue/param_reader.h"
#include "underwater_stereo/ros_glue/recent_problems.h"
#include "underwater_stereo/ros_glue/stereo_input.h"

namespace underwater_stereo {

namespace {

using namespace boost::placeholders;
using sensor_msgs::CameraInfo;
using sensor_msgs::CameraInfoConstPtr;
using sensor_msgs::Image;
using sensor_msgs::ImageConstPtr;
using ExactPolicy = message_filters::sync_policies::ExactTime<Image, CameraInfo, Image, CameraInfo>;
using ApproximatePolicy = message_filters::sync_policies::ApproximateTime<Image, CameraInfo, Image, CameraInfo>;

struct Pair {
  ImageConstPtr left, right;
  CameraInfoConstPtr left_info, right_info;
};

/// A processed pair waiting for its turn to be published (the input is kept for the annotated image).
struct Processed {
  Pair pair;
  ros_glue::StereoInput input;
  DetectionResult result;
  StereoMatchConfig workspace;  ///< the depths of the detector that processed it (dynamic_reconfigure may change them)
  ros::WallTime start;
};

}  // namespace

class DetectorNodelet : public nodelet::Nodelet {
 public:
  ~DetectorNodelet() override {
    if (pool_) pool_->stop();  // before the publishers and the detector it uses go
  }

 private:
  void onInit() override {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    std::vector<std::string> problems;
    ros_glue::ParamReader params(pnh, problems);
    std::string config_file = ros::package::getPath("underwater_stereo") + "/config/detector.yaml";
    bool approximate = false;
    int queue_size = 5;
    int worker_threads = 2;
    int max_waiting_pairs = 2;
    int opencv_threads = -1;
    std::string mount_frame;
    std::vector<double> mount_xyz{0, 0, 0}, mount_rpy{0, 0, 0};
    params.optional("config_file", config_file);
    params.optional("approximate_sync", approximate);
    params.optional("max_skew_s", max_skew_s_);
    params.optional("queue_size", queue_size);
    params.optional("worker_threads", worker_threads);
    params.optional("max_waiting_pairs", max_waiting_pairs);
    params.optional("opencv_threads", opencv_threads);
    params.optional("mount_frame", mount_frame);
    params.optional("mount_xyz", mount_xyz);
    params.optional("mount_rpy", mount_rpy);
    params.optional("stereo_frame", stereo_frame_);
    params.optional("max_dropped_share", max_dropped_share_);
    if (queue_size < 1 || queue_size > 100) problems.push_back(pnh.resolveName("queue_size") + ": must be 1..100");
    if (worker_threads < 1 || worker_threads > 16) {
      problems.push_back(pnh.resolveName("worker_threads") + ": must be 1..16");
    }
    if (max_waiting_pairs < 1 || max_waiting_pairs > 10) {
      problems.push_back(pnh.resolveName("max_waiting_pairs") + ": must be 1..10");
    }
    if (opencv_threads < -1 || opencv_threads > 64) {
      problems.push_back(pnh.resolveName("opencv_threads") + ": must be -1 (leave OpenCV as it is) or 0..64");
    }
    if (!(max_dropped_share_ >= 0 && max_dropped_share_ <= 1)) {
      problems.push_back(pnh.resolveName("max_dropped_share") + ": must be in [0, 1]");
    }
    if (!(max_skew_s_ >= 0 && max_skew_s_ < 1)) problems.push_back(pnh.resolveName("max_skew_s") + ": must be in [0, 1)");
    if (mount_xyz.size() != 3) problems.push_back(pnh.resolveName("mount_xyz") + ": needs 3 numbers [m]");
    if (mount_rpy.size() != 3) problems.push_back(pnh.resolveName("mount_rpy") + ": needs 3 numbers [rad]");
    if (!mount_frame.empty() && stereo_frame_.empty()) {
      problems.push_back(pnh.resolveName("stereo_frame") + ": needed with mount_frame (the left optical frame)");
    }
    const auto compressed_config = ros_glue::CompressedImagePublisher::readParams(pnh, problems);
    if (!approximate) max_skew_s_ = 0.0;
    try {
      config_ = loadDetectorConfigFile(config_file);
    } catch (const std::invalid_argument& e) {
      problems.push_back(pnh.resolveName("config_file") + " (" + config_file + "): " + e.what());
    }
    tracking_ = std::make_unique<ros_glue::ObjectTracking>(pnh, problems);
    search_scale_ = config_.search_scale;
    if (!problems.empty()) {
      const std::string message = joinProblems("DetectorNodelet: invalid configuration, not started", problems);
      NODELET_FATAL_STREAM(message);
      throw std::invalid_argument(message);
    }

    // OpenCV's thread count is one setting for the whole process (every nodelet in this manager): only set
    // when asked. With pairs in parallel, 1 saves the ~30 % CPU per pair that OpenCV's own loops spend handing
    // work between threads fighting for the same cores (launch/detector.launch asks for it then).
    if (opencv_threads >= 0) cv::setNumThreads(opencv_threads);
    pool_ = std::make_unique<Pool>(
        worker_threads, static_cast<std::size_t>(max_waiting_pairs), [this](Pair& pair) { return process(pair); },
        [this](std::optional<Processed>& done) {
          if (done) publish(*done);
        },
        [this](PoolStage stage, const std::string& what) {
          badInput((stage == PoolStage::kProcess ? "processing failed: " : "publishing failed: ") + what);
        });
    pairing_ = std::make_unique<ros_glue::PairingMonitor>(static_cast<std::size_t>(queue_size) + 2);
    objects_pub_ = pnh.advertise<DetectedObjectArray>("objects", 10);
    markers_pub_ = pnh.advertise<visualization_msgs::MarkerArray>("markers", 2);
    cloud_pub_ = pnh.advertise<sensor_msgs::PointCloud2>("cloud", 2);
    image_transport::ImageTransport private_it(pnh);
    image_pub_ = private_it.advertise("image", 2);
    snapshot_pub_ = private_it.advertise("snapshot", 2);
    compressed_pub_ = std::make_unique<ros_glue::CompressedImagePublisher>(pnh, "image", compressed_config);
    if (!mount_frame.empty()) publishMount(mount_frame, mount_xyz, mount_rpy);
    tracking_->start(pnh);
    enable_service_ = pnh.advertiseService("enable", &DetectorNodelet::onEnable, this);

    reconfigure_ = std::make_unique<dynamic_reconfigure::Server<DetectorTuningConfig>>(reconfigure_mutex_, pnh);
    DetectorTuningConfig start;
    ros_glue::toReconfigure(config_, start);
    reconfigure_->updateConfig(start);
    reconfigure_->setCallback([this](DetectorTuningConfig& r, std::uint32_t) { onReconfigure(r); });

    diagnostics_ = std::make_unique<diagnostic_updater::Updater>(nh, pnh, getName());
    diagnostics_->setHardwareID("underwater_stereo detector");
    diagnostics_->add("detector", this, &DetectorNodelet::diagnose);
    diagnostics_->add("tracking", tracking_.get(), &ros_glue::ObjectTracking::diagnose);
    diagnostics_timer_ = nh.createWallTimer(ros::WallDuration(1.0), [this](const ros::WallTimerEvent&) {
      diagnostics_->force_update();
    });

    left_topic_ = nh.resolveName("left/image_raw");
    right_topic_ = nh.resolveName("right/image_raw");
    queue_size_ = queue_size;
    subscribe();
    // An image the synchroniser drops (no partner within its queue) is counted, not lost unseen.
    left_image_sub_.registerCallback(boost::function<void(const ImageConstPtr&)>(
        [this](const ImageConstPtr& m) { pairing_->image(ros_glue::StereoSide::kLeft, m->header.stamp.toSec()); }));
    right_image_sub_.registerCallback(boost::function<void(const ImageConstPtr&)>(
        [this](const ImageConstPtr& m) { pairing_->image(ros_glue::StereoSide::kRight, m->header.stamp.toSec()); }));
    if (approximate) {
      approximate_sync_ = std::make_unique<message_filters::Synchronizer<ApproximatePolicy>>(
          ApproximatePolicy(queue_size), left_image_sub_, left_info_sub_, right_image_sub_, right_info_sub_);
      approximate_sync_->registerCallback(boost::bind(&DetectorNodelet::onPair, this, _1, _2, _3, _4));
    } else {
      exact_sync_ = std::make_unique<message_filters::Synchronizer<ExactPolicy>>(
          ExactPolicy(queue_size), left_image_sub_, left_info_sub_, right_image_sub_, right_info_sub_);
      exact_sync_->registerCallback(boost::bind(&DetectorNodelet::onPair, this, _1, _2, _3, _4));
    }
    NODELET_INFO_STREAM("DetectorNodelet: " << config_.colours.classes.size() << " designated colours from "
                        << config_file << ", " << (approximate ? "approximate" : "exact") << " sync on "
                        << left_topic_ << " / " << right_topic_ << ", objects on " << pnh.resolveName("objects")
                        << ", " << worker_threads << " worker(s) of " << config_.pair_threads
                        << " thread(s) each (pair_threads), OpenCV "
                        << (opencv_threads < 0 ? "threads as the process has them (" + std::to_string(cv::getNumThreads()) + ")"
                                               : "set to " + std::to_string(cv::getNumThreads()) +
                                                     " thread(s) for this whole process"));
  }

  void publishMount(const std::string& mount_frame, const std::vector<double>& xyz, const std::vector<double>& rpy) {
    geometry_msgs::TransformStamped t;
    t.header.stamp = ros::Time::now();
    t.header.frame_id = mount_frame;
    t.child_frame_id = stereo_frame_;
    t.transform.translation.x = xyz[0];
    t.transform.translation.y = xyz[1];
    t.transform.translation.z = xyz[2];
    tf2::Quaternion q;
    q.setRPY(rpy[0], rpy[1], rpy[2]);
    t.transform.rotation.x = q.x();
    t.transform.rotation.y = q.y();
    t.transform.rotation.z = q.z();
    t.transform.rotation.w = q.w();
    static_broadcaster_.sendTransform(t);
  }

  void subscribe() {
    ros::NodeHandle& nh = getNodeHandle();
    image_transport::ImageTransport it(nh);
    left_image_sub_.subscribe(it, "left/image_raw", queue_size_);
    right_image_sub_.subscribe(it, "right/image_raw", queue_size_);
    left_info_sub_.subscribe(nh, "left/camera_info", queue_size_);
    right_info_sub_.subscribe(nh, "right/camera_info", queue_size_);
  }

  /// ~enable false: unsubscribes from the images (no pair is received or processed; tracks are kept);
  /// true: subscribes again.
  bool onEnable(std_srvs::SetBool::Request& req, std_srvs::SetBool::Response& res) {
    std::lock_guard<std::mutex> lock(enable_mutex_);
    if (req.data != enabled_) {
      if (req.data) {
        subscribe();
      } else {
        left_image_sub_.unsubscribe();
        right_image_sub_.unsubscribe();
        left_info_sub_.unsubscribe();
        right_info_sub_.unsubscribe();
      }
      enabled_ = req.data;
    }
    res.success = true;
    res.message = enabled_ ? "detecting" : "paused: not subscribed to the images";
    NODELET_INFO_STREAM("DetectorNodelet: " << res.message);
    return true;
  }

  /// A refused set is written back over `r` with the values in use (dynamic_reconfigure then shows those).
  void onReconfigure(DetectorTuningConfig& r) {
    const DetectorConfig next = ros_glue::fromReconfigure(config_, r);
    const auto problems = next.validate();
    if (!problems.empty()) {
      NODELET_ERROR_STREAM(joinProblems("DetectorNodelet: reconfiguration refused, keeping the previous values",
                                        problems));
      ros_glue::toReconfigure(config_, r);
      return;
    }
    std::lock_guard<std::mutex> lock(detector_mutex_);
    config_ = next;
    rebuild_ = true;  // the next pair's worker builds the detector: not this thread, not the receiving one
  }

  void onPair(const ImageConstPtr& left, const CameraInfoConstPtr& left_info, const ImageConstPtr& right,
              const CameraInfoConstPtr& right_info) {
    ++received_;
    pairing_->paired(left->header.stamp.toSec(), right->header.stamp.toSec());
    pool_->submit(Pair{left, right, left_info, right_info});
  }

  void badInput(const std::string& what) {
    bad_inputs_.add(what, ros::WallTime::now().toSec());
    NODELET_ERROR_STREAM_THROTTLE(5.0, "DetectorNodelet: pair skipped: " << what);
  }

  /// Detection on one pair; nothing when the pair is refused (counted as bad input).
  std::optional<Processed> process(Pair& pair) {
    Processed out;
    out.start = ros::WallTime::now();
    try {
      out.input = ros_glue::toStereoInput(*pair.left, *pair.left_info, *pair.right, *pair.right_info, left_topic_,
                                          right_topic_, max_skew_s_, search_scale_);
    } catch (const std::invalid_argument& e) {
      badInput(e.what());
      return std::nullopt;
    }
    std::shared_ptr<const Detector> detector;
    {
      std::lock_guard<std::mutex> lock(detector_mutex_);
      if (!detector_ || rebuild_ || out.input.calibration != calibration_) {  // any field: new rectification maps
        try {
          // The old one released first: its rectification maps (27.6 MB at 1920x1200, heap chunks below the
          // launch files' mmap threshold) are freed before the new ones are allocated, which then reuse them
          // instead of raising the heap's high-water mark at each rebuild (unless a worker still holds it).
          detector_.reset();
          detector_ = std::make_shared<const Detector>(config_, out.input.calibration);
          calibration_ = out.input.calibration;
          rebuild_ = false;
          if (const std::string note = detector_->workspaceNote(); !note.empty()) {
            NODELET_WARN_STREAM("DetectorNodelet: " << note);
          }
        } catch (const std::invalid_argument& e) {
          detector_.reset();
          badInput(e.what());
          return std::nullopt;
        }
      }
      detector = detector_;  // workers still using a replaced detector keep it alive
    }
    try {
      out.result = detector->detect(out.input.left, out.input.right);
      out.workspace = detector->config().stereo;
    } catch (const std::invalid_argument& e) {
      badInput(e.what());
      return std::nullopt;
    }
    // A pair that looks swapped reports no object (Detector::detect): published, empty, unless the watch takes the
    // head's wiring for the cause: then refused as bad input, with an ERROR naming it.
    if (const int swapped = swapped_pairs_.add(out.result.looks_swapped, !out.result.objects.empty()); swapped > 0) {
      badInput("left and right images look swapped: in " + std::to_string(swapped) + " pairs since the last with "
               "objects most objects' right views lie right of their left ones (check the cameras' topics, serials "
               "or remappings)");
      return std::nullopt;
    }
    out.pair = std::move(pair);
    return out;
  }

  void publish(Processed& done) {
    const std_msgs::Header& header = done.pair.left->header;
    objects_pub_.publish(tracking_->track(done.result, header, done.input.calibration, done.workspace));  // drops rejected objects
    const DetectionResult& result = done.result;
    if (markers_pub_.getNumSubscribers() > 0) markers_pub_.publish(ros_glue::toMarkers(result, header));
    if (cloud_pub_.getNumSubscribers() > 0) cloud_pub_.publish(ros_glue::toCloud(result, header));
    const bool want_snapshot = snapshot_pub_.getNumSubscribers() > 0 && !result.objects.empty();
    const bool want_image = image_pub_.getNumSubscribers() > 0, want_compressed = compressed_pub_->due();
    if (want_image || want_snapshot || want_compressed) {
      const cv::Mat image = annotate(done.input.left.bgr(), result);
      if (want_compressed) compressed_pub_->publish(header, image);
      if (want_image || want_snapshot) {
        const sensor_msgs::ImagePtr annotated = cv_bridge::CvImage(header, "bgr8", image).toImageMsg();
        if (want_image) image_pub_.publish(annotated);
        if (want_snapshot) snapshot_pub_.publish(annotated);
      }
    }
    ++processed_;
    std::lock_guard<std::mutex> lock(stats_mutex_);
    for (const Rejection& r : result.rejected) ++rejected_by_stage_[static_cast<int>(r.stage)];
    last_quality_ = result.quality;
    last_search_scale_ = result.search_scale;
    last_searched_coarser_ = result.search_scale < search_scale_;
    if (last_searched_coarser_) ++searched_coarser_;
    last_without_colour_ = !carriesColour(done.input.left.layout());
    last_processing_ms_ = (ros::WallTime::now() - done.start).toSec() * 1000.0;
    max_processing_ms_ = std::max(max_processing_ms_, last_processing_ms_);
  }

  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) {
    const ros::WallTime now = ros::WallTime::now();
    const double elapsed = last_diagnosis_.isZero() ? 0.0 : (now - last_diagnosis_).toSec();
    const long received = received_, processed = processed_, dropped = static_cast<long>(pool_->dropped());
    const double input_hz = elapsed > 0 ? (received - last_received_) / elapsed : 0.0;
    const double processed_hz = elapsed > 0 ? (processed - last_processed_) / elapsed : 0.0;
    const long received_now = received - last_received_, dropped_now = dropped - last_dropped_;
    const ros_glue::PairingMonitor::Counts unpaired = pairing_->counts();
    const long unpaired_now = unpaired.unpaired_left + unpaired.unpaired_right - last_unpaired_;
    last_diagnosis_ = now;
    last_received_ = received;
    last_processed_ = processed;
    last_dropped_ = dropped;
    last_unpaired_ = unpaired.unpaired_left + unpaired.unpaired_right;
    std::lock_guard<std::mutex> lock(stats_mutex_);
    const std::string recent_errors = bad_inputs_.summary(now.toSec());
    if (!enabled_) {
      stat.summary(diagnostic_msgs::DiagnosticStatus::OK, "paused (~enable false): no pairs received or processed");
    } else if (!recent_errors.empty()) {
      stat.summary(diagnostic_msgs::DiagnosticStatus::ERROR, "bad input: " + recent_errors);
    } else if (unpaired_now > 0) {
      stat.summary(diagnostic_msgs::DiagnosticStatus::WARN,
                   std::to_string(unpaired_now) + " image(s) never paired since the last report; last: " + unpaired.last);
    } else if (received_now > 0 && dropped_now > max_dropped_share_ * received_now) {
      stat.summary(diagnostic_msgs::DiagnosticStatus::WARN,
                   std::to_string(dropped_now) + " of " + std::to_string(received_now) +
                       " pairs dropped while every worker was busy since the last report (more than max_dropped_share " +
                       cv::format("%g", max_dropped_share_) + ")");
    } else if (received == 0) {
      stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, "no stereo pairs received yet");
    } else if (last_without_colour_) {
      stat.summary(diagnostic_msgs::DiagnosticStatus::WARN,
                   "mono8 images carry no colour: no designated colour can be found in them (set the cameras to "
                   "a Bayer pixel format, bgr8 or rgb8)");
    } else if (last_quality_.spoiled()) {
      stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, "frames spoiled: " + qualityStatusName(last_quality_.status));
    } else if (last_searched_coarser_) {
      stat.summary(diagnostic_msgs::DiagnosticStatus::OK,
                   cv::format("detecting; dark frames (mean brightness %.0f) searched coarser, at %g of full size",
                              last_quality_.mean_brightness, last_search_scale_));
    } else {
      stat.summary(diagnostic_msgs::DiagnosticStatus::OK, "detecting");
    }
    stat.add("input rate [Hz]", input_hz);
    stat.add("processed rate [Hz]", processed_hz);
    stat.add("pairs received", received);
    stat.add("pairs processed", processed);
    stat.add("pairs dropped (detector busy)", dropped);
    stat.add("left images never paired", unpaired.unpaired_left);
    stat.add("right images never paired", unpaired.unpaired_right);
    stat.add("last unpaired image", unpaired.last.empty() ? std::string("none") : unpaired.last);
    const std::string last_error = bad_inputs_.last();
    stat.add("bad input pairs", bad_inputs_.count());
    stat.add("last bad input", last_error.empty() ? std::string("none") : last_error);
    stat.add("processing time [ms]", last_processing_ms_);
    stat.add("max processing time [ms]", max_processing_ms_);
    stat.add("quality", qualityStatusName(last_quality_.status));
    stat.add("mean brightness", last_quality_.mean_brightness);
    stat.add("search scale", last_search_scale_);
    stat.add("pairs searched coarser (dark)", searched_coarser_);
    for (int k = 0; k < kRejectionStageCount; ++k) {
      stat.add("regions rejected: " + rejectionStageName(static_cast<RejectionStage>(k)), rejected_by_stage_[k]);
    }
  }

  static constexpr double kErrorHoldS = 5.0;  ///< a bad pair keeps the diagnostic at ERROR this long
  static constexpr std::size_t kErrorKindsNamed = 4;  ///< distinct bad inputs named in the summary, then counted

  // Configuration.
  DetectorConfig config_;
  double max_skew_s_ = 0.005;
  double search_scale_ = 1.0;        ///< config_.search_scale (not reconfigurable): sets the smallest image
  double max_dropped_share_ = 0.05;  ///< more pairs dropped while busy per report: WARN
  std::string stereo_frame_ = "stereo_left_optical_frame";
  int queue_size_ = 5;
  std::string left_topic_, right_topic_;

  // Input.
  image_transport::SubscriberFilter left_image_sub_, right_image_sub_;
  message_filters::Subscriber<CameraInfo> left_info_sub_, right_info_sub_;
  std::unique_ptr<message_filters::Synchronizer<ExactPolicy>> exact_sync_;
  std::unique_ptr<message_filters::Synchronizer<ApproximatePolicy>> approximate_sync_;
  std::unique_ptr<ros_glue::PairingMonitor> pairing_;

  // The detector for the latest configuration and calibration; the workers share it (guarded by detector_mutex_
  // with config_ and rebuild_).
  std::mutex detector_mutex_;
  bool rebuild_ = false;
  std::shared_ptr<const Detector> detector_;
  StereoCalibration calibration_;
  using Pool = OrderedWorkerPool<Pair, std::optional<Processed>>;
  std::unique_ptr<Pool> pool_;

  // Output.
  ros::Publisher objects_pub_, markers_pub_, cloud_pub_;
  image_transport::Publisher image_pub_, snapshot_pub_;
  std::unique_ptr<ros_glue::CompressedImagePublisher> compressed_pub_;  ///< image/compressed for a tether
  tf2_ros::StaticTransformBroadcaster static_broadcaster_;
  std::unique_ptr<ros_glue::ObjectTracking> tracking_;  ///< targets, tracks, landmarks (publish() calls it in order)
  ros::ServiceServer enable_service_;
  std::mutex enable_mutex_;
  std::atomic<bool> enabled_{true};
  boost::recursive_mutex reconfigure_mutex_;
  std::unique_ptr<dynamic_reconfigure::Server<DetectorTuningConfig>> reconfigure_;

  // Diagnostics.
  std::unique_ptr<diagnostic_updater::Updater> diagnostics_;
  ros::WallTimer diagnostics_timer_;
  std::atomic<long> received_{0}, processed_{0};
  SwappedPairWatch swapped_pairs_;
  ros_glue::RecentProblems bad_inputs_{kErrorHoldS, kErrorKindsNamed};
  std::mutex stats_mutex_;
  ros::WallTime last_diagnosis_;
  long last_received_ = 0, last_processed_ = 0, last_dropped_ = 0, last_unpaired_ = 0;
  QualityReport last_quality_;
  bool last_without_colour_ = false;  ///< the last pair processed was grey
  double last_search_scale_ = 0.0;     ///< the 2D search's scale for the last pair (DetectionResult; 0 before the first)
  bool last_searched_coarser_ = false; ///< the last pair was searched coarser than search_scale (dark_search_width_px)
  long searched_coarser_ = 0;          ///< pairs searched coarser than search_scale, since start
  std::array<long, kRejectionStageCount> rejected_by_stage_{};  ///< regions looked at and not reported, since start
  double last_processing_ms_ = 0.0, max_processing_ms_ = 0.0;
};

}  // namespace underwater_stereo

PLUGINLIB_EXPORT_CLASS(underwater_stereo::DetectorNodelet, nodelet::Nodelet)
