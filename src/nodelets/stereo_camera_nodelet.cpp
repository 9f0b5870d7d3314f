// SPDX-License-Identifier: BSD-3-Clause
// Publishes synchronised stereo pairs (left/right image_raw + camera_info) from a StereoSource chosen by
// the `source` parameter. The simulated source also publishes its ground truth on `ground_truth`.
#include <cv_bridge/cv_bridge.h>
#include <image_transport/image_transport.h>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <ros/ros.h>

#include <memory>
#include <stdexcept>

#include "underwater_stereo/config/yaml_fields.h"
#include "underwater_stereo/ros_glue/calibration_conversions.h"
#include "underwater_stereo/ros_glue/ground_truth_conversions.h"
#include "underwater_stereo/ros_glue/param_reader.h"
#include "underwater_stereo/sim/sim_stereo_source.h"

namespace underwater_stereo {

class StereoCameraNodelet : public nodelet::Nodelet {
 public:
  ~StereoCameraNodelet() override {
    if (source_) source_->stop();
  }

 private:
  void onInit() override {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    std::vector<std::string> problems;
    ros_glue::ParamReader params(pnh, problems);
    std::string source = "sim";
    std::string scene_path;
    sim::SimSourceConfig sim_config;
    params.optional("source", source);
    params.optional("frame_id", frame_id_);
    if (source == "sim") {
      params.required("scene", scene_path);
      params.optional("rate_hz", sim_config.rate_hz);
      params.optional("loop_frames", sim_config.loop_frames);
      const auto sim_problems = sim_config.validate();
      problems.insert(problems.end(), sim_problems.begin(), sim_problems.end());
    } else {
      problems.push_back(pnh.resolveName("source") + ": '" + source + "' is not a known source (known: sim)");
    }
    if (frame_id_.empty()) problems.push_back(pnh.resolveName("frame_id") + ": empty");
    std::shared_ptr<sim::Renderer> renderer;
    if (problems.empty()) {
      try {
        renderer = std::make_shared<sim::Renderer>(sim::loadSceneFile(scene_path));
      } catch (const std::invalid_argument& e) {
        problems.push_back(pnh.resolveName("scene") + ": " + e.what());
      }
    }
    if (!problems.empty()) {
      const std::string message = joinProblems("StereoCameraNodelet: invalid configuration", problems);
      NODELET_FATAL_STREAM(message);
      throw std::invalid_argument(message);
    }
    calibration_ = renderer->calibration();
    NODELET_INFO_STREAM("StereoCameraNodelet: source=sim scene=" << scene_path << " ("
                        << renderer->scene().objects.size() << " objects, " << calibration_.left.width << "x"
                        << calibration_.left.height << ", baseline " << calibration_.baselineM() << " m, f "
                        << calibration_.focalPx() << " px) rate_hz=" << sim_config.rate_hz
                        << " loop_frames=" << sim_config.loop_frames << " frame_id=" << frame_id_);

    image_transport::ImageTransport it(nh);
    left_pub_ = it.advertiseCamera("left/image_raw", 2);
    right_pub_ = it.advertiseCamera("right/image_raw", 2);
    ground_truth_pub_ = nh.advertise<GroundTruth>("ground_truth", 10);
    source_ = std::make_unique<sim::SimStereoSource>(renderer, sim_config);
    source_->start([this](const StereoFrame& frame) { publish(frame); });
  }

  // Both sides carry one header: the same stamp and the left optical frame, as stereo consumers
  // (image_geometry::StereoCameraModel, stereo_image_proc) require; the right camera's pose is in its P.
  void publish(const StereoFrame& frame) {
    std_msgs::Header header;
    header.stamp = ros::Time::now();
    header.seq = static_cast<std::uint32_t>(frame.sequence);
    header.frame_id = frame_id_;
    const auto left_info = boost::make_shared<sensor_msgs::CameraInfo>(ros_glue::toCameraInfo(calibration_.left));
    const auto right_info = boost::make_shared<sensor_msgs::CameraInfo>(ros_glue::toCameraInfo(calibration_.right));
    left_info->header = header;
    right_info->header = header;
    ground_truth_pub_.publish(ros_glue::toGroundTruthMsg(frame.ground_truth, header));
    left_pub_.publish(cv_bridge::CvImage(header, frame.encoding, frame.left).toImageMsg(), left_info);
    right_pub_.publish(cv_bridge::CvImage(header, frame.encoding, frame.right).toImageMsg(), right_info);
  }

  std::string frame_id_ = "stereo_left_optical_frame";
  StereoCalibration calibration_;
  image_transport::CameraPublisher left_pub_;
  image_transport::CameraPublisher right_pub_;
  ros::Publisher ground_truth_pub_;
  std::unique_ptr<StereoSource> source_;
};

}  // namespace underwater_stereo

PLUGINLIB_EXPORT_CLASS(underwater_stereo::StereoCameraNodelet, nodelet::Nodelet)
