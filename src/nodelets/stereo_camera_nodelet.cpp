// SPDX-License-Identifier: BSD-3-Clause
// Publishes synchronised stereo pairs (left/right image_raw + camera_info) from a StereoSource chosen by
// the `source` parameter: `sim` (the simulated scene; also its ground truth on `ground_truth`) or `aravis`
// (two GigE Vision cameras; calibration from camera_info_manager, diagnostics per camera, exposure/gain/rate
// while streaming through dynamic_reconfigure, and per side and frame a FrameMetadata on <side>/frame_metadata).
#include <camera_info_manager/camera_info_manager.h>
#include <diagnostic_updater/diagnostic_updater.h>
#include <dynamic_reconfigure/server.h>
#include <image_transport/image_transport.h>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <ros/ros.h>
#include <tf2_ros/transform_broadcaster.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <memory>
#include <mutex>
#include <stdexcept>

#include "underwater_stereo/FrameMetadata.h"
#include "underwater_stereo/StereoCameraConfig.h"
#include "underwater_stereo/camera/aravis_stereo_source.h"
#include "underwater_stereo/camera/pixel_buffer_pool.h"
#include "underwater_stereo/config/yaml_fields.h"
#include "underwater_stereo/ros_glue/calibration_conversions.h"
#include "underwater_stereo/ros_glue/ground_truth_conversions.h"
#include "underwater_stereo/ros_glue/param_reader.h"
#include "underwater_stereo/sim/sim_stereo_source.h"

namespace underwater_stereo {

namespace {

/// The controls <-> dynamic_reconfigure (auto_roi and the law's deadband and step stay as configured).
void toReconfigure(const StereoControls& c, StereoCameraConfig& r) {
  r.exposure_sync = exposureSyncName(c.exposure_sync);
  r.exposure_us = c.exposure_us;
  r.gain = c.gain;
  r.exposure_auto_min_us = c.auto_exposure.exposure_min_us;
  r.exposure_auto_max_us = c.auto_exposure.exposure_max_us;
  r.gain_auto_min_db = c.auto_exposure.gain_min_db;
  r.gain_auto_max_db = c.auto_exposure.gain_max_db;
  r.auto_target = c.auto_exposure.target;
  r.rate_hz = c.rate_hz;
  r.packet_delay_ns = c.packet_delay_ns;
}

StereoControls fromReconfigure(StereoControls c, const StereoCameraConfig& r, std::vector<std::string>& problems) {
  try {
    c.exposure_sync = exposureSyncFromName(r.exposure_sync);
  } catch (const std::invalid_argument& e) {
    problems.push_back(e.what());
  }
  c.exposure_us = r.exposure_us;
  c.gain = r.gain;
  c.auto_exposure.exposure_min_us = r.exposure_auto_min_us;
  c.auto_exposure.exposure_max_us = r.exposure_auto_max_us;
  c.auto_exposure.gain_min_db = r.gain_auto_min_db;
  c.auto_exposure.gain_max_db = r.gain_auto_max_db;
  c.auto_exposure.target = r.auto_target;
  c.rate_hz = r.rate_hz;
  c.packet_delay_ns = r.packet_delay_ns;
  return c;
}

FrameMetadataPtr toMetadata(const FrameCapture& c, const std_msgs::Header& header) {
  auto m = boost::make_shared<FrameMetadata>();
  m->header = header;
  m->camera = c.camera;
  m->camera_frame_id = c.frame_id;
  m->camera_timestamp_ns = c.device_ns;
  m->ptp = c.ptp;
  m->exposure_us = c.exposure_us;
  m->gain = c.gain;
  m->gain_unit = c.gain_unit;
  m->temperature_c = c.temperature_c;
  return m;
}

/// The image message, its data one of the frame pool's buffers: a real camera's frame (copied once in all, out
/// of the camera's buffer) or a copy of a simulated image. The buffer goes back to the pool when the message's
/// last holder lets go (in one manager the detector receives the message itself, without serialisation), so
/// image memory is recycled, not freed into the heap arena of whichever thread allocated it.
sensor_msgs::ImagePtr toImage(const std_msgs::Header& header, const std::string& encoding, const cv::Mat& image,
                              PixelBufferPool::Buffer pixels) {
  if (!pixels) {
    pixels = PixelBufferPool::frames().acquire(image.total() * image.elemSize());
    cv::Mat copy(image.rows, image.cols, image.type(), pixels->data());
    image.copyTo(copy);
  }
  sensor_msgs::ImagePtr m(new sensor_msgs::Image, [pixels](sensor_msgs::Image* done) {
    pixels->swap(done->data);  // the pixels back into the pool's buffer, released with this deleter
    delete done;
  });
  m->header = header;
  m->encoding = encoding;
  m->height = static_cast<std::uint32_t>(image.rows);
  m->width = static_cast<std::uint32_t>(image.cols);
  m->step = static_cast<std::uint32_t>(image.cols * image.elemSize());
  m->is_bigendian = 0;
  m->data.swap(*pixels);
  return m;
}

}  // namespace

class StereoCameraNodelet : public nodelet::Nodelet {
 public:
  ~StereoCameraNodelet() override {
    if (source_) source_->stop();
  }

 private:
  void onInit() override {
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    std::vector<std::string> problems;
    ros_glue::ParamReader params(pnh, problems);
    std::string source = "sim";
    params.optional("source", source);
    params.optional("frame_id", frame_id_);
    if (frame_id_.empty()) problems.push_back(pnh.resolveName("frame_id") + ": empty");
    params.optional("fixed_frame", fixed_frame_);
    if (source == "sim") {
      initSim(params, problems);
    } else if (source == "aravis") {
      initAravis(params, problems);
    } else {
      problems.push_back(pnh.resolveName("source") + ": '" + source + "' is not a known source (sim, aravis)");
    }
    if (!problems.empty()) {
      const std::string message = joinProblems("StereoCameraNodelet: invalid configuration", problems);
      NODELET_FATAL_STREAM(message);
      throw std::invalid_argument(message);
    }
    image_transport::ImageTransport it(getNodeHandle());
    left_pub_ = it.advertiseCamera("left/image_raw", 2);
    right_pub_ = it.advertiseCamera("right/image_raw", 2);
    if (source == "sim") ground_truth_pub_ = getNodeHandle().advertise<GroundTruth>("ground_truth", 10);
    if (aravis_) {
      left_metadata_pub_ = getNodeHandle().advertise<FrameMetadata>("left/frame_metadata", 10);
      right_metadata_pub_ = getNodeHandle().advertise<FrameMetadata>("right/frame_metadata", 10);
      reconfigure_ = std::make_unique<dynamic_reconfigure::Server<StereoCameraConfig>>(reconfigure_mutex_,
                                                                                       getPrivateNodeHandle());
      StereoCameraConfig start;
      toReconfigure(aravis_->controls(), start);
      reconfigure_->updateConfig(start);
      reconfigure_->setCallback([this](StereoCameraConfig& r, std::uint32_t) { onReconfigure(r); });
    }
    source_->start([this](const StereoFrame& frame) { publish(frame); });
  }

  void initSim(ros_glue::ParamReader& params, std::vector<std::string>& problems) {
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    std::string scene_path;
    sim::SimSourceConfig sim_config;
    params.required("scene", scene_path);
    params.optional("rate_hz", sim_config.rate_hz);
    params.optional("loop_frames", sim_config.loop_frames);
    const auto sim_problems = sim_config.validate();
    problems.insert(problems.end(), sim_problems.begin(), sim_problems.end());
    if (!problems.empty()) return;
    std::shared_ptr<sim::Renderer> renderer;
    try {
      renderer = std::make_shared<sim::Renderer>(sim::loadSceneFile(scene_path));
    } catch (const std::invalid_argument& e) {
      problems.push_back(pnh.resolveName("scene") + ": " + e.what());
      return;
    }
    calibration_ = renderer->calibration();
    NODELET_INFO_STREAM("StereoCameraNodelet: source=sim scene=" << scene_path << " ("
                        << renderer->scene().objects.size() << " objects, " << calibration_.left.width << "x"
                        << calibration_.left.height << ", baseline " << calibration_.baselineM() << " m, f "
                        << calibration_.focalPx() << " px) rate_hz=" << sim_config.rate_hz
                        << " loop_frames=" << sim_config.loop_frames << " frame_id=" << frame_id_);
    source_ = std::make_unique<sim::SimStereoSource>(renderer, sim_config, [this](const std::string& message) {
      NODELET_ERROR_STREAM_THROTTLE(5.0, "StereoCameraNodelet: " << message);
    });
  }

  /// Reads <side>/... camera parameters (shared defaults from the private namespace).
  CameraSettings readCamera(ros_glue::ParamReader& params, const std::string& side) {
    CameraSettings c;
    for (const std::string& prefix : {std::string(), side + "/"}) {
      params.optional(prefix + "pixel_format", c.pixel_format);
      params.optional(prefix + "exposure_us", c.exposure_us);
      params.optional(prefix + "exposure_auto_min_us", c.exposure_auto_min_us);
      params.optional(prefix + "exposure_auto_max_us", c.exposure_auto_max_us);
      params.optional(prefix + "gain", c.gain);
      params.optional(prefix + "binning", c.binning);
      params.optional(prefix + "roi_x", c.roi_x);
      params.optional(prefix + "roi_y", c.roi_y);
      params.optional(prefix + "roi_width", c.roi_width);
      params.optional(prefix + "roi_height", c.roi_height);
      params.optional(prefix + "packet_size", c.packet_size);
      params.optional(prefix + "packet_delay_ns", c.packet_delay_ns);
      params.optional(prefix + "packet_resend", c.packet_resend);
      params.optional(prefix + "socket_buffer_bytes", c.socket_buffer_bytes);
      params.optional(prefix + "buffers", c.buffers);
      params.optional(prefix + "trigger_line", c.trigger_line);
      params.optional(prefix + "trigger_activation", c.trigger_activation);
    }
    params.required(side + "/id", c.id);
    return c;
  }

  void initAravis(ros_glue::ParamReader& params, std::vector<std::string>& problems) {
    AravisStereoConfig config;
    config.left = readCamera(params, "left");
    config.right = readCamera(params, "right");
    std::string sync = "software", exposure_sync = "master_slave";
    params.optional("sync", sync);
    StereoControls& c = config.controls;
    AutoExposureSettings& a = c.auto_exposure;
    params.optional("exposure_sync", exposure_sync);
    params.optional("exposure_us", c.exposure_us);
    params.optional("gain", c.gain);
    params.optional("exposure_auto_min_us", a.exposure_min_us);
    params.optional("exposure_auto_max_us", a.exposure_max_us);
    params.optional("gain_auto_min_db", a.gain_min_db);
    params.optional("gain_auto_max_db", a.gain_max_db);
    params.optional("auto_target", a.target);
    params.optional("auto_deadband", a.deadband);
    params.optional("auto_max_step", a.max_step);
    std::vector<double> roi;
    params.optional("auto_roi", roi);
    if (roi.size() == 4) {
      a.roi = AutoRoi{roi[0], roi[1], roi[2], roi[3]};
    } else if (getPrivateNodeHandle().hasParam("auto_roi")) {
      problems.push_back(getPrivateNodeHandle().resolveName("auto_roi") + ": need [x, y, width, height] (shares of the image)");
    }
    params.optional("rate_hz", c.rate_hz);
    params.optional("packet_delay_ns", c.packet_delay_ns);
    params.optional("ptp", config.ptp);
    params.optional("ptp_timeout_s", config.ptp_timeout_s);
    params.optional("max_skew_s", config.max_skew_s);
    params.optional("frame_timeout_s", config.frame_timeout_s);
    params.optional("max_backoff_s", config.max_backoff_s);
    try {
      config.sync = triggerModeFromName(sync);
    } catch (const std::invalid_argument& e) {
      problems.push_back(getPrivateNodeHandle().resolveName("sync") + ": " + e.what());
    }
    try {
      c.exposure_sync = exposureSyncFromName(exposure_sync);
    } catch (const std::invalid_argument& e) {
      problems.push_back(getPrivateNodeHandle().resolveName("exposure_sync") + ": " + e.what());
    }
    const auto config_problems = config.validate();
    problems.insert(problems.end(), config_problems.begin(), config_problems.end());
    std::string left_url, right_url;
    params.optional("left/camera_info_url", left_url);
    params.optional("right/camera_info_url", right_url);
    // camera_info_manager's names (its default file is ~/.ros/camera_info/<name>.yaml): <namespace>_left and
    // <namespace>_right, so that two heads on one vehicle do not share a calibration.
    std::string ns = getNodeHandle().getNamespace().substr(1);
    std::replace(ns.begin(), ns.end(), '/', '_');
    std::string left_name = ns.empty() ? "left" : ns + "_left", right_name = ns.empty() ? "right" : ns + "_right";
    params.optional("left/camera_name", left_name);
    params.optional("right/camera_name", right_name);
    for (const auto& [key, name] : {std::make_pair("left/camera_name", left_name),
                                    std::make_pair("right/camera_name", right_name)}) {
      const auto valid = [](unsigned char c) { return std::isalnum(c) || c == '_'; };
      if (name.empty() || !std::all_of(name.begin(), name.end(), valid)) {
        problems.push_back(getPrivateNodeHandle().resolveName(key) + ": '" + name +
                           "' is not a camera_info_manager name (letters, digits, '_')");
      }
    }
    if (!problems.empty()) return;
    ros::NodeHandle left_nh(getNodeHandle(), "left"), right_nh(getNodeHandle(), "right");
    left_info_ = std::make_unique<camera_info_manager::CameraInfoManager>(left_nh, left_name, left_url);
    right_info_ = std::make_unique<camera_info_manager::CameraInfoManager>(right_nh, right_name, right_url);
    for (const auto& [side, manager, url] : {std::make_tuple("left", left_info_.get(), left_url),
                                             std::make_tuple("right", right_info_.get(), right_url)}) {
      if (!manager->isCalibrated()) {
        NODELET_WARN_STREAM("StereoCameraNodelet: " << side << " camera not calibrated (camera_info_url '" << url
                            << "'): its camera_info has zero K and P, the detector will refuse it; calibrate in "
                               "water (README)");
      }
    }
    auto source = std::make_unique<AravisStereoSource>(config, [this](bool error, const std::string& m) {
      if (error) {
        NODELET_ERROR_STREAM_THROTTLE(2.0, "StereoCameraNodelet: " << m);
      } else {
        NODELET_INFO_STREAM("StereoCameraNodelet: " << m);
      }
    });
    aravis_ = source.get();
    source_ = std::move(source);
    diagnostics_ = std::make_unique<diagnostic_updater::Updater>(getNodeHandle(), getPrivateNodeHandle(), getName());
    diagnostics_->setHardwareID("underwater_stereo stereo head " + config.left.id + " + " + config.right.id);
    diagnostics_->add("left camera", [this](diagnostic_updater::DiagnosticStatusWrapper& s) { diagnoseCamera(s, 0); });
    diagnostics_->add("right camera", [this](diagnostic_updater::DiagnosticStatusWrapper& s) { diagnoseCamera(s, 1); });
    diagnostics_->add("pairing", [this](diagnostic_updater::DiagnosticStatusWrapper& s) { diagnosePairing(s); });
    diagnostics_timer_ = getNodeHandle().createWallTimer(ros::WallDuration(1.0), [this](const ros::WallTimerEvent&) {
      last_status_ = aravis_->status();
      warnUnsupported(last_status_.left, 0);
      warnUnsupported(last_status_.right, 1);
      diagnostics_->force_update();
    });
    NODELET_INFO_STREAM("StereoCameraNodelet: source=aravis left=" << config.left.id << " right=" << config.right.id
                        << " sync=" << sync << " rate_hz=" << c.rate_hz << " max skew "
                        << config.effectiveMaxSkewS() * 1e3 << " ms exposure_sync=" << exposure_sync
                        << " auto_roi=[" << a.roi.x << ", " << a.roi.y << ", " << a.roi.width << ", " << a.roi.height
                        << "] auto_target=" << a.target << " ptp=" << (config.ptp ? "true" : "false")
                        << " frame_id=" << frame_id_);
  }

  /// A new set from dynamic_reconfigure: applied whole, or refused whole with the reasons; either way `r` is
  /// set to the values in use, so the client shows them.
  void onReconfigure(StereoCameraConfig& r) {
    std::vector<std::string> problems;
    const StereoControls wanted = fromReconfigure(aravis_->controls(), r, problems);
    if (problems.empty()) problems = aravis_->reconfigure(wanted);
    if (!problems.empty()) {
      NODELET_WARN_STREAM(joinProblems("StereoCameraNodelet: reconfigure refused, the values in use are kept", problems));
    } else {
      NODELET_INFO_STREAM("StereoCameraNodelet: reconfigured: exposure_sync=" << r.exposure_sync << " exposure_us="
                          << r.exposure_us << " gain=" << r.gain << " auto [" << r.exposure_auto_min_us << ", "
                          << r.exposure_auto_max_us << "] us target " << r.auto_target << " rate_hz=" << r.rate_hz
                          << " packet_delay_ns=" << r.packet_delay_ns);
    }
    toReconfigure(aravis_->controls(), r);
  }

  /// A feature the configuration asks for and the camera lacks is a WARN in the log, once per list.
  void warnUnsupported(const CameraStatus& c, int side) {
    if (c.unsupported == warned_unsupported_[side]) return;
    warned_unsupported_[side] = c.unsupported;
    for (const auto& u : c.unsupported) {
      NODELET_WARN_STREAM("StereoCameraNodelet: " << (side == 0 ? "left" : "right") << " camera lacks " << u);
    }
  }

  void diagnoseCamera(diagnostic_updater::DiagnosticStatusWrapper& stat, int side) {
    const CameraStatus& c = side == 0 ? last_status_.left : last_status_.right;
    const std::uint64_t previous = last_frames_[side];
    last_frames_[side] = c.frames;
    const double fps = static_cast<double>(c.frames - std::min(previous, c.frames));  // per 1 s update
    if (c.state == CameraState::kStreaming) {
      // A feature the camera lacks stays in the summary through a second without frames (a stall under load).
      std::string message = fps > 0 ? "streaming" : "streaming, no frames in the last second";
      if (!c.unsupported.empty()) {
        std::string features;
        for (const auto& u : c.unsupported) features += (features.empty() ? "" : ", ") + u.substr(0, u.find(':'));
        message += (fps > 0 ? ", but" : ", and") + std::string(" the camera lacks ") + features +
                   " (see 'unsupported ...')";
      }
      stat.summary(fps > 0 && c.unsupported.empty() ? diagnostic_msgs::DiagnosticStatus::OK
                                                     : diagnostic_msgs::DiagnosticStatus::WARN,
                   message);
    } else {
      stat.summary(diagnostic_msgs::DiagnosticStatus::ERROR, cameraStateName(c.state) + (c.last_error.empty() ? "" : ": " + c.last_error));
    }
    stat.add("camera", c.description);
    stat.add("state", std::string(cameraStateName(c.state)));
    stat.add("exposure [us]", c.exposure.exposure_us);
    stat.add("gain [" + c.gain_unit + "]", c.exposure.gain_db);
    stat.add("PTP", c.ptp);
    stat.add("frame rate [Hz]", fps);
    stat.add("frames", c.frames);
    stat.add("missed frames (frame-id gaps)", c.missed_frames);
    stat.add("outages", c.outages);
    stat.add("last error", c.last_error.empty() ? std::string("none") : c.last_error);
    for (const auto& u : c.unsupported) stat.add("unsupported " + u.substr(0, u.find(':')), u);
    stat.add("completed buffers", c.stream.completed);
    stat.add("failed (incomplete) buffers", c.stream.failed);
    stat.add("buffer underruns", c.stream.underruns);
    stat.add("missing packets", c.stream.missing_packets);
    stat.add("resent packets", c.stream.resent_packets);
    if (std::isfinite(c.stream.temperature_c)) stat.add("temperature [C]", c.stream.temperature_c);
  }

  void diagnosePairing(diagnostic_updater::DiagnosticStatusWrapper& stat) {
    const std::uint64_t unpaired_now = last_status_.unpaired - std::min(last_unpaired_, last_status_.unpaired);
    last_unpaired_ = last_status_.unpaired;
    if (unpaired_now > 0) {
      stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, std::to_string(unpaired_now) +
                   " frame(s) dropped without a partner since the last report; last: " + last_status_.last_unpaired);
    } else {
      stat.summary(diagnostic_msgs::DiagnosticStatus::OK, "pairing");
    }
    stat.add("pairs", last_status_.pairs);
    stat.add("unpaired frames dropped", last_status_.unpaired);
    stat.add("last unpaired frame", last_status_.last_unpaired.empty() ? std::string("none") : last_status_.last_unpaired);
    stat.add("pairs dropped (capture time not after the previous)", last_status_.out_of_order);
    stat.add("pairs dropped (publisher busy)", last_status_.overflowed);
    stat.add("left/right skew of the last pair [ms]", last_status_.last_skew_ms);
    stat.add("stamps", last_status_.ptp_stamps ? "PTP (both cameras settled)" : "clock mapping per camera");
  }

  // Both sides carry one header: the same stamp and the left optical frame, as stereo consumers
  // (image_geometry::StereoCameraModel, stereo_image_proc) require; the right camera's pose is in its P.
  void publish(const StereoFrame& frame) {
    std_msgs::Header header;
    header.stamp = ros::Time::now();
    if (frame.capture_time_ns > 0 && !ros::Time::isSimTime()) header.stamp.fromNSec(frame.capture_time_ns);
    header.seq = static_cast<std::uint32_t>(frame.sequence);
    header.frame_id = frame_id_;
    auto left_info = boost::make_shared<sensor_msgs::CameraInfo>(
        left_info_ ? left_info_->getCameraInfo() : ros_glue::toCameraInfo(calibration_.left));
    auto right_info = boost::make_shared<sensor_msgs::CameraInfo>(
        right_info_ ? right_info_->getCameraInfo() : ros_glue::toCameraInfo(calibration_.right));
    for (auto* info : {left_info.get(), right_info.get()}) {
      if (info->width == 0) {  // not calibrated: at least the size
        info->width = static_cast<std::uint32_t>(frame.left.cols);
        info->height = static_cast<std::uint32_t>(frame.left.rows);
      }
    }
    left_info->header = header;
    right_info->header = header;
    if (frame.camera_pose_world && !fixed_frame_.empty()) {  // the simulated head's true pose, before its images
      broadcaster_.sendTransform(ros_glue::toCameraTransform(*frame.camera_pose_world, header, fixed_frame_));
    }
    if (ground_truth_pub_) {
      ground_truth_pub_.publish(ros_glue::toGroundTruthMsg(
          frame.ground_truth, header, frame.camera_pose_world.value_or(Eigen::Isometry3d::Identity()), fixed_frame_));
    }
    if (frame.left_capture) left_metadata_pub_.publish(toMetadata(*frame.left_capture, header));
    if (frame.right_capture) right_metadata_pub_.publish(toMetadata(*frame.right_capture, header));
    left_pub_.publish(toImage(header, frame.encoding, frame.left, frame.left_pixels), left_info);
    right_pub_.publish(toImage(header, frame.encoding, frame.right, frame.right_pixels), right_info);
  }

  std::string frame_id_ = "stereo_left_optical_frame";
  std::string fixed_frame_ = "odom";  ///< sim: the scene's world frame, parent of frame_id_ on TF ("" = no TF)
  tf2_ros::TransformBroadcaster broadcaster_;
  StereoCalibration calibration_;
  image_transport::CameraPublisher left_pub_;
  image_transport::CameraPublisher right_pub_;
  ros::Publisher ground_truth_pub_;
  std::unique_ptr<StereoSource> source_;
  // aravis source only
  AravisStereoSource* aravis_ = nullptr;
  std::unique_ptr<camera_info_manager::CameraInfoManager> left_info_, right_info_;
  std::unique_ptr<diagnostic_updater::Updater> diagnostics_;
  ros::Publisher left_metadata_pub_, right_metadata_pub_;
  boost::recursive_mutex reconfigure_mutex_;
  std::unique_ptr<dynamic_reconfigure::Server<StereoCameraConfig>> reconfigure_;
  ros::WallTimer diagnostics_timer_;
  StereoStatus last_status_;
  std::vector<std::string> warned_unsupported_[2];
  std::uint64_t last_frames_[2] = {0, 0};
  std::uint64_t last_unpaired_ = 0;  // unpaired frames at the last pairing report
};

}  // namespace underwater_stereo

PLUGINLIB_EXPORT_CLASS(underwater_stereo::StereoCameraNodelet, nodelet::Nodelet)
