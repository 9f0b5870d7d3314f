// SPDX-License-Identifier: BSD-3-Clause
// DetectionResult -> messages, and received pairs -> detector input, without a ROS master.
#include <cv_bridge/cv_bridge.h>
#include <gtest/gtest.h>

#include <limits>

#include "underwater_stereo/detection/annotator.h"
#include "underwater_stereo/ros_glue/calibration_conversions.h"
#include "underwater_stereo/ros_glue/detection_conversions.h"
#include "underwater_stereo/ros_glue/stereo_input.h"
#include "underwater_stereo/sim/renderer.h"

using namespace underwater_stereo;

namespace {

DetectionResult twoObjects() {
  DetectionResult r;
  Detection a;
  a.colour = "red";
  a.shape = ShapeKind::kSphere;
  a.size_m = Eigen::Vector3d::Constant(0.25);
  a.position_m = Eigen::Vector3d(-0.5, 0.1, 2.5);
  a.range_m = a.position_m.norm();
  a.roi = cv::Rect(100, 120, 60, 60);
  a.contour = {{100, 120}, {160, 120}, {160, 180}, {100, 180}};
  a.points = {{-0.5F, 0.1F, 2.4F}, {-0.45F, 0.1F, 2.4F}};
  Detection b = a;
  b.colour = "teal";  // not a common colour name: drawn in its measured colour
  b.measured_bgr = cv::Scalar(100, 80, 10);
  b.shape = ShapeKind::kCylinder;
  b.position_m = Eigen::Vector3d(0.3, 0.0, 3.0);
  b.points.resize(5);
  b.cut_by_border = true;
  r.objects = {a, b};
  r.quality.mean_brightness = 90;
  return r;
}

struct RenderedInput {
  sensor_msgs::Image left, right;
  sensor_msgs::CameraInfo left_info, right_info;
};

RenderedInput smallPool() {
  sim::Scene scene = sim::loadSceneFile(UWS_SOURCE_DIR "/test/scenes/small_pool.yaml");
  const sim::Renderer renderer(scene);
  const sim::RenderedPair pair = renderer.render(0, 0);
  RenderedInput in;
  in.left = *cv_bridge::CvImage(std_msgs::Header(), pair.encoding, pair.left).toImageMsg();
  in.right = *cv_bridge::CvImage(std_msgs::Header(), pair.encoding, pair.right).toImageMsg();
  in.left_info = ros_glue::toCameraInfo(renderer.calibration().left);
  in.right_info = ros_glue::toCameraInfo(renderer.calibration().right);
  return in;
}

}  // namespace

TEST(DetectionConversions, ObjectsMarkersCloudAndTransformsCarryEveryObject) {
  const DetectionResult r = twoObjects();
  std_msgs::Header h;
  h.frame_id = "stereo_left_optical_frame";
  h.stamp = ros::Time(5.0);
  const DetectedObjectArray objects = ros_glue::toObjectsMsg(r, h);
  ASSERT_EQ(objects.objects.size(), 2U);
  EXPECT_EQ(objects.objects[1].id, 1U);
  EXPECT_EQ(objects.objects[0].roi.width, 60U);
  EXPECT_NEAR(objects.objects[0].range, 2.5522, 1e-3);
  EXPECT_FALSE(objects.objects[0].cut_by_border);
  EXPECT_TRUE(objects.objects[1].cut_by_border);
  EXPECT_NEAR(objects.quality.mean_brightness, 90, 1e-6);
  const auto markers = ros_glue::toMarkers(r, h);
  ASSERT_EQ(markers.markers.size(), 5U);
  EXPECT_EQ(markers.markers[0].action, visualization_msgs::Marker::DELETEALL);
  EXPECT_EQ(markers.markers[1].type, visualization_msgs::Marker::SPHERE);
  EXPECT_GT(markers.markers[1].color.r, 0.9F);
  EXPECT_EQ(markers.markers[3].type, visualization_msgs::Marker::CYLINDER);
  EXPECT_NEAR(markers.markers[3].color.b, 1.0F, 1e-6) << "measured colour, brightened";
  EXPECT_EQ(markers.markers[4].type, visualization_msgs::Marker::TEXT_VIEW_FACING);
  EXPECT_EQ(ros_glue::toCloud(r, h).width, 7U);
}

TEST(DetectionConversions, ShapesAndOutlinesBecomeTheMessageConstants) {
  const std::vector<std::pair<ShapeKind, std::string>> shapes{
      {ShapeKind::kSphere, DetectedObject::SHAPE_SPHERE}, {ShapeKind::kCylinder, DetectedObject::SHAPE_CYLINDER},
      {ShapeKind::kBox, DetectedObject::SHAPE_BOX}, {ShapeKind::kPlane, DetectedObject::SHAPE_PLANE},
      {ShapeKind::kUnknown, DetectedObject::SHAPE_UNKNOWN}};
  const std::vector<std::pair<OutlineKind, std::string>> outlines{
      {OutlineKind::kCircle, DetectedObject::OUTLINE_CIRCLE}, {OutlineKind::kEllipse, DetectedObject::OUTLINE_ELLIPSE},
      {OutlineKind::kTriangle, DetectedObject::OUTLINE_TRIANGLE},
      {OutlineKind::kRectangle, DetectedObject::OUTLINE_RECTANGLE},
      {OutlineKind::kPolygon, DetectedObject::OUTLINE_POLYGON}};
  DetectionResult r;
  for (std::size_t i = 0; i < shapes.size(); ++i) {
    Detection d = twoObjects().objects[0];
    d.shape = shapes[i].first;
    d.outline = outlines[i].first;
    r.objects.push_back(d);
  }
  const DetectedObjectArray msg = ros_glue::toObjectsMsg(r, std_msgs::Header());
  const auto markers = ros_glue::toMarkers(r, std_msgs::Header());
  ASSERT_EQ(msg.objects.size(), shapes.size());
  for (std::size_t i = 0; i < shapes.size(); ++i) {
    EXPECT_EQ(msg.objects[i].shape, shapes[i].second);
    EXPECT_EQ(msg.objects[i].outline, outlines[i].second);
    const std::string label = markers.markers[2 + 2 * i].text;
    EXPECT_EQ(label.rfind("red " + shapes[i].second + " ", 0), 0U) << label;
  }
}

TEST(DetectionConversions, AnnotatedFrameKeepsTheSizeAndDrawsOnIt) {
  const cv::Mat frame(400, 640, CV_8UC3, cv::Scalar(120, 110, 60));
  const cv::Mat before = frame.clone();
  const cv::Mat drawn = annotate(frame, twoObjects());
  ASSERT_EQ(drawn.size(), frame.size());
  EXPECT_GT(cv::norm(drawn, frame, cv::NORM_L1), 1000.0);
  EXPECT_EQ(cv::norm(frame, before, cv::NORM_INF), 0.0) << "the input is not modified";
  EXPECT_THROW(annotate(cv::Mat(), twoObjects()), std::invalid_argument);
}

TEST(StereoInput, TakesEveryAcceptedEncoding) {
  const RenderedInput in = smallPool();  // bayer_rggb8
  const ros_glue::StereoInput out =
      ros_glue::toStereoInput(in.left, in.left_info, in.right, in.right_info, "left", "right", 0.0);
  EXPECT_EQ(out.left.layout(), PixelLayout::kBayerRggb);
  EXPECT_EQ(out.left.data().data, in.left.data.data()) << "the mosaic is shared, not copied";
  EXPECT_EQ(out.left.size(), cv::Size(640, 400));
  EXPECT_NEAR(out.calibration.baselineM(), 0.12, 0.005);
  const cv::Mat bgr = out.left.bgr().clone();
  cv::Mat as_bridge;  // what cv_bridge makes of the mosaic
  cv::cvtColor(out.left.data(), as_bridge, cv::COLOR_BayerBG2BGR);
  EXPECT_EQ(cv::norm(bgr, as_bridge, cv::NORM_INF), 0.0);
  for (const std::string enc : {"bgr8", "rgb8", "mono8"}) {
    cv::Mat converted = bgr.clone();  // cvtColor must not write into bgr
    if (enc == "rgb8") cv::cvtColor(bgr, converted, cv::COLOR_BGR2RGB);
    if (enc == "mono8") cv::cvtColor(bgr, converted, cv::COLOR_BGR2GRAY);
    sensor_msgs::Image img = *cv_bridge::CvImage(std_msgs::Header(), enc, converted).toImageMsg();
    const ros_glue::StereoInput o = ros_glue::toStereoInput(img, in.left_info, img, in.right_info, "l", "r", 0.0);
    EXPECT_EQ(o.left.layout(), enc == "mono8" ? PixelLayout::kMono : PixelLayout::kBgr) << enc;
    if (enc != "mono8") {
      EXPECT_EQ(cv::norm(o.left.bgr(), bgr, cv::NORM_INF), 0.0) << enc;
    }
  }
  EXPECT_TRUE(ros_glue::acceptedEncoding("bayer_grbg8"));
  EXPECT_FALSE(ros_glue::acceptedEncoding("16UC1"));
  EXPECT_FALSE(ros_glue::acceptedEncoding("yuv422"));
}

TEST(StereoInput, BadPairsThrowNamingTheTopicAndValue) {
  const RenderedInput good = smallPool();
  auto message = [&](const std::function<void(RenderedInput&)>& spoil, double max_skew = 0.0) {
    RenderedInput in = good;
    spoil(in);
    try {
      ros_glue::toStereoInput(in.left, in.left_info, in.right, in.right_info, "/s/left", "/s/right", max_skew);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no exception");
  };
  EXPECT_NE(message([](auto& in) { in.right.encoding = "32FC1"; }).find("/s/right: encoding '32FC1'"), std::string::npos);
  EXPECT_NE(message([](auto& in) { in.left.data.resize(10); }).find("/s/left: data has 10 bytes"), std::string::npos);
  EXPECT_NE(message([](auto& in) { in.left = sensor_msgs::Image(); in.left.encoding = "bgr8"; }).find("/s/left"),
            std::string::npos);
  EXPECT_NE(message([](auto& in) { in.left_info.width = 1920; }).find("its camera_info is 1920x400"), std::string::npos);
  EXPECT_NE(message([](auto& in) { in.right_info.P[0] = std::numeric_limits<double>::quiet_NaN(); }).find("camera_info"),
            std::string::npos);
  EXPECT_NE(message([](auto& in) { in.right.header.stamp = ros::Time(0.1); }).find("0.100000 s apart"), std::string::npos);
  EXPECT_EQ(message([](auto& in) { in.right.header.stamp = ros::Time(0.001); }, 0.005), "no exception");
  EXPECT_NE(message([](auto& in) {
              cv::Mat small(200, 320, CV_8UC1, cv::Scalar(0));
              in.right = *cv_bridge::CvImage(std_msgs::Header(), "bayer_rggb8", small).toImageMsg();
            }).find("/s/left is 640x400 but /s/right is 320x200"),
            std::string::npos);
  EXPECT_NE(message([](auto& in) {
              cv::Mat odd(399, 639, CV_8UC1, cv::Scalar(0));
              in.right = *cv_bridge::CvImage(std_msgs::Header(), "bayer_rggb8", odd).toImageMsg();
            }).find("/s/right: RawFrame: a Bayer frame needs even width and height, got 639x399"),
            std::string::npos);
}
