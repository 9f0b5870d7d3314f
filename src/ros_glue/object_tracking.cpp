// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/ros_glue/object_tracking.h"

#include <ros/console.h>
#include <ros/package.h>

#include <cmath>

#include "underwater_stereo/detection/roi_stereo_matcher.h"
#include "underwater_stereo/ros_glue/detection_conversions.h"
#include "underwater_stereo/ros_glue/param_reader.h"
#include "underwater_stereo/ros_glue/tracking_conversions.h"

namespace underwater_stereo {
namespace ros_glue {
namespace {

constexpr double kProblemHoldS = 5.0;  ///< [s] of stamps a tracking problem keeps the diagnostic at WARN

}  // namespace

ObjectTracking::ObjectTracking(const ros::NodeHandle& pnh, std::vector<std::string>& problems)
    : config_file_(ros::package::getPath("underwater_stereo") + "/config/tracking.yaml") {
  ParamReader params(pnh, problems);
  params.optional("tracking_config_file", config_file_);
  params.optional("fixed_frame", fixed_frame_);
  params.optional("tf_timeout_s", tf_timeout_s_);
  params.optional("publish_tf", publish_tf_);
  params.optional("object_frame_prefix", frame_prefix_);
  if (!(tf_timeout_s_ >= 0.0 && tf_timeout_s_ <= 1.0)) {
    problems.push_back(pnh.resolveName("tf_timeout_s") + ": must be in [0, 1] s");
  }
  try {
    config_ = loadTrackingConfigFile(config_file_);
    matcher_ = std::make_unique<TargetMatcher>(config_);
    tracker_ = std::make_unique<Tracker>(config_);
  } catch (const std::invalid_argument& e) {
    problems.push_back(pnh.resolveName("tracking_config_file") + " (" + config_file_ + "): " + e.what());
  }
}

void ObjectTracking::start(ros::NodeHandle& pnh) {
  if (!fixed_frame_.empty()) {
    tf_buffer_ = std::make_unique<tf2_ros::Buffer>();
    tf_listener_ = std::make_unique<tf2_ros::TransformListener>(*tf_buffer_);
  }
  landmarks_pub_ = pnh.advertise<DetectedObjectArray>("landmarks", 10);
  markers_pub_ = pnh.advertise<visualization_msgs::MarkerArray>("landmark_markers", 2);
  reset_service_ = pnh.advertiseService("reset_tracks", &ObjectTracking::resetTracks, this);
  landmark_service_ = pnh.advertiseService("get_landmark", &ObjectTracking::getLandmark, this);
  ROS_INFO_STREAM("DetectorNodelet: tracking " << (fixed_frame_.empty() ? "in the stereo frame" : "in " + fixed_frame_)
                  << ", " << config_.targets.size() << " targets from " << config_file_
                  << (config_.targets_only ? " (only targets reported)" : "") << ", landmarks on "
                  << pnh.resolveName("landmarks"));
}

std::optional<Eigen::Isometry3d> ObjectTracking::cameraPose(const std_msgs::Header& header) {
  try {
    const geometry_msgs::TransformStamped t =
        tf_buffer_->lookupTransform(fixed_frame_, header.frame_id, header.stamp, ros::Duration(tf_timeout_s_));
    return toIsometry(t.transform);
  } catch (const tf2::TransformException& e) {
    last_tf_error_ = e.what();
    return std::nullopt;
  }
}

DetectedObjectArray ObjectTracking::track(DetectionResult& result, const std_msgs::Header& header,
                                          const StereoCalibration& calibration, const StereoMatchConfig& workspace) {
  std::vector<Observation> observations;
  std::vector<Detection> kept;
  for (Detection& d : result.objects) {
    const TargetMatch match = matcher_->match(d.colour, d.shape, d.size_m);
    if (!matcher_->keep(match)) continue;
    Observation o;
    o.position_m = d.position_m;
    o.colour = d.colour;
    o.shape = d.shape;
    o.size_m = d.size_m;
    o.target = match.target;
    o.cut_by_border = d.cut_by_border;
    observations.push_back(o);
    kept.push_back(std::move(d));
  }
  const long rejected = static_cast<long>(result.objects.size() - kept.size());
  result.objects = std::move(kept);
  DetectedObjectArray objects = toObjectsMsg(result, header);

  // The camera's pose off the lock: the wait for tf2 must not hold up a service call.
  std::optional<Eigen::Isometry3d> pose;
  if (!fixed_frame_.empty()) pose = cameraPose(header);

  std::lock_guard<std::mutex> lock(mutex_);
  rejected_ += rejected;
  bool tracked = true;
  if (fixed_frame_.empty() || (!pose && !fixed_frame_seen_)) {
    if (tracking_frame_ != header.frame_id) tracker_->reset();  // a new frame: old tracks mean nothing there
    tracking_frame_ = header.frame_id;
    pose = Eigen::Isometry3d::Identity();
  } else if (pose) {
    if (!fixed_frame_seen_) tracker_->reset();  // tracked in the stereo frame until now
    fixed_frame_seen_ = true;
    tracking_frame_ = fixed_frame_;
  } else {
    tracked = false;
    ++untracked_pairs_;
    last_problem_ = "no transform " + fixed_frame_ + " <- " + header.frame_id + " at the pair's stamp: pair not tracked (" +
                    last_tf_error_ + ")";
    last_problem_stamp_s_ = header.stamp.toSec();
    ROS_WARN_STREAM_THROTTLE(5.0, "DetectorNodelet: " << last_problem_);
  }
  if (tracked) {
    camera_pose_ = *pose;
    // From the nearest depth stereo matches (a long baseline leaves the workspace's near end out): a track nearer
    // than that is not expected to be seen.
    const double near_m = nearestMatchedDepthM(calibration, workspace), far_m = workspace.max_depth_m;
    if (!view_ || !(calibration == view_calibration_) || near_m != view_near_m_ || far_m != view_far_m_) {
      try {
        view_.emplace(calibration.left, near_m, far_m, config_.view_margin_px);
        view_calibration_ = calibration;
        view_near_m_ = near_m;
        view_far_m_ = far_m;
      } catch (const std::invalid_argument& e) {
        view_.reset();  // every track counts as in view
        last_problem_ = e.what();
        last_problem_stamp_s_ = header.stamp.toSec();
      }
    }
    TrackingFrame frame;
    frame.stamp_s = header.stamp.toSec();
    frame.camera_pose = *pose;
    if (view_) frame.in_view = [this](const Eigen::Vector3d& p) { return view_->sees(p); };
    frame.observations = std::move(observations);
    const TrackingUpdate update = tracker_->update(frame);
    if (update.outcome == FrameOutcome::kClockRestarted || update.outcome == FrameOutcome::kCameraJumped) ++resets_;
    if (!update.problems.empty()) {
      last_problem_ = frameOutcomeName(update.outcome) + ": ";
      for (const std::string& p : update.problems) last_problem_ += p + "; ";
      last_problem_stamp_s_ = header.stamp.toSec();
      ROS_WARN_STREAM_THROTTLE(5.0, "DetectorNodelet: tracking: " << last_problem_);
    }
    const Eigen::Matrix3d to_stereo = pose->linear().transpose();
    for (std::size_t i = 0; i < objects.objects.size(); ++i) {
      if (const Track* t = tracker_->find(update.track_ids[i])) fillTrackFields(*t, to_stereo, objects.objects[i]);
    }
  }
  std_msgs::Header landmarks_header = header;
  landmarks_header.frame_id = tracking_frame_;
  const DetectedObjectArray landmarks = toLandmarksMsg(tracker_->tracks(), landmarks_header, camera_pose_);
  landmarks_pub_.publish(landmarks);
  if (markers_pub_.getNumSubscribers() > 0) markers_pub_.publish(toLandmarkMarkers(landmarks));
  if (publish_tf_ && !landmarks.objects.empty()) broadcaster_.sendTransform(toTrackTransforms(landmarks, frame_prefix_));
  return objects;
}

bool ObjectTracking::resetTracks(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
  std::lock_guard<std::mutex> lock(mutex_);
  const std::size_t n = tracker_->tracks().size();
  tracker_->reset();
  ++resets_;
  res.success = true;
  res.message = std::to_string(n) + " tracks removed";
  return true;
}

bool ObjectTracking::getLandmark(GetLandmark::Request& req, GetLandmark::Response& res) {
  std::lock_guard<std::mutex> lock(mutex_);
  const Track* t = nullptr;
  if (!req.target.empty()) {
    if (!config_.target(req.target)) {
      std::string names;
      for (const Target& target : config_.targets) names += (names.empty() ? "" : ", ") + target.name;
      res.message = "no target named '" + req.target + "' (targets: " + (names.empty() ? "none" : names) + ")";
      return true;
    }
    t = tracker_->findConfirmed(req.target);
    if (!t) res.message = "no confirmed track of " + req.target + " (not seen, or not seen long enough)";
  } else {
    t = tracker_->find(req.track_id);
    if (!t || t->status != TrackStatus::kConfirmed) {
      res.message = "no confirmed track with id " + std::to_string(req.track_id);
      t = nullptr;
    }
  }
  if (!t) return true;
  DetectedObject o;
  fillTrackFields(*t, Eigen::Matrix3d::Identity(), o);
  res.found = true;
  res.message = "found";
  res.track_id = o.track_id;
  res.label = o.label;
  res.pose.header.frame_id = tracking_frame_;
  res.pose.header.stamp.fromSec(tracker_->lastStamp());
  const Eigen::Vector3d p = t->filter.position();
  res.pose.pose.position.x = p.x();
  res.pose.pose.position.y = p.y();
  res.pose.pose.position.z = p.z();
  res.pose.pose.orientation.w = 1.0;
  res.position_covariance = o.position_covariance;
  res.velocity = o.velocity;
  res.observations = o.observations;
  res.age_s = tracker_->lastStamp() - t->last_seen_s;
  res.in_view = t->in_view;
  return true;
}

void ObjectTracking::diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) {
  std::lock_guard<std::mutex> lock(mutex_);
  int confirmed = 0;
  for (const Track& t : tracker_->tracks()) confirmed += t.status == TrackStatus::kConfirmed;
  const double last = tracker_->lastStamp();
  const bool recent_problem = !last_problem_.empty() && !(last - last_problem_stamp_s_ > kProblemHoldS);
  if (!fixed_frame_.empty() && !fixed_frame_seen_ && !tracking_frame_.empty()) {
    stat.summary(diagnostic_msgs::DiagnosticStatus::WARN,
                 "no transform from " + fixed_frame_ + " yet: tracking in " + tracking_frame_);
  } else if (recent_problem) {
    stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, last_problem_);
  } else {
    stat.summary(diagnostic_msgs::DiagnosticStatus::OK,
                 std::to_string(confirmed) + " landmarks in " + (tracking_frame_.empty() ? "(no pair yet)" : tracking_frame_));
  }
  stat.add("tracking frame", tracking_frame_);
  stat.add("fixed frame", fixed_frame_.empty() ? std::string("(none: stereo frame)") : fixed_frame_);
  stat.add("confirmed tracks", confirmed);
  stat.add("tentative tracks", static_cast<int>(tracker_->tracks().size()) - confirmed);
  stat.add("pairs not tracked (no transform)", untracked_pairs_);
  stat.add("track resets", resets_);
  stat.add("detections rejected (targets)", rejected_);
  stat.add("last tracking problem", last_problem_.empty() ? std::string("none") : last_problem_);
}

}  // namespace ros_glue
}  // namespace underwater_stereo
