// SPDX-License-Identifier: BSD-3-Clause
#include <gtest/gtest.h>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "sim_test_helpers.h"
#include "underwater_stereo/sim/renderer.h"

using namespace underwater_stereo;
using namespace underwater_stereo::sim;
using underwater_stereo::sim::test::smallScene;
using underwater_stereo::sim::test::sphere;

namespace {

SceneObject panel(const Eigen::Vector3d& position, double width, double height, const Eigen::Vector3d& albedo) {
  SceneObject o;
  o.name = "panel";
  o.shape = ShapeType::kPanel;
  o.colour = "white";
  o.position_m = position;
  o.size_m = Eigen::Vector3d(width, height, 0.0);
  o.albedo = albedo;
  return o;
}

cv::Mat rectify(const cv::Mat& image, const CameraCalibration& c) {
  cv::Mat map1, map2, out;
  const cv::Matx33d new_k(c.P(0, 0), c.P(0, 1), c.P(0, 2), c.P(1, 0), c.P(1, 1), c.P(1, 2), 0, 0, 1);
  cv::initUndistortRectifyMap(cv::Mat(c.K), cv::Mat(c.D), cv::Mat(c.R), cv::Mat(new_k), cv::Size(c.width, c.height),
                              CV_32FC1, map1, map2);
  cv::remap(image, out, map1, map2, cv::INTER_LINEAR);
  return out;
}

}  // namespace

TEST(Renderer, SphereOutlineMatchesItsAnalyticProjection) {
  // Off-centre, so lens distortion shapes the outline.
  const Eigen::Vector3d centre(0.55, 0.35, 2.0);
  const double radius = 0.15;
  const Renderer renderer(smallScene(sphere("ball", centre, 2 * radius)));
  const RenderedPair pair = renderer.render(0.0, 0);
  const cv::Mat rendered = pair.left_labels == 1;

  // Silhouette: the circle where rays from the optical centre touch the sphere.
  const double c = centre.norm();
  const Eigen::Vector3d w = centre / c;
  const Eigen::Vector3d a = w.unitOrthogonal(), b = w.cross(a);
  std::vector<cv::Point3d> rim;
  for (int i = 0; i < 720; ++i) {
    const double th = 2 * M_PI * i / 720;
    const Eigen::Vector3d p = centre - (radius * radius / c) * w +
                              radius * std::sqrt(1 - radius * radius / (c * c)) * (std::cos(th) * a + std::sin(th) * b);
    rim.emplace_back(p.x(), p.y(), p.z());
  }
  std::vector<cv::Point2d> projected;
  cv::projectPoints(rim, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), cv::Mat(renderer.rig().left().K),
                    cv::Mat(renderer.rig().left().D), projected);
  // Pixel centres inside the projected rim (exact point-in-polygon, no rasteriser bias).
  std::vector<cv::Point2f> projected_f(projected.begin(), projected.end());
  cv::Mat analytic = cv::Mat::zeros(rendered.size(), CV_8UC1);
  const cv::Rect box = cv::boundingRect(projected_f) & cv::Rect(0, 0, analytic.cols, analytic.rows);
  for (int v = box.y; v < box.br().y; ++v) {
    for (int u = box.x; u < box.br().x; ++u) {
      if (cv::pointPolygonTest(projected_f, cv::Point2f(u, v), false) > 0) analytic.at<std::uint8_t>(v, u) = 255;
    }
  }
  const double area_rendered = cv::countNonZero(rendered);
  const double area_analytic = cv::countNonZero(analytic);
  const double perimeter = cv::arcLength(projected_f, true);
  cv::Mat disagreement;
  cv::bitwise_xor(rendered, analytic, disagreement);
  ASSERT_GT(area_analytic, 5000);
  EXPECT_NEAR(area_rendered / area_analytic, 1.0, 0.01);
  // Only pixels whose centre lies within a fraction of a pixel of the rim may disagree.
  EXPECT_LT(cv::countNonZero(disagreement), 0.1 * perimeter);
  const cv::Moments mr = cv::moments(rendered, true), ma = cv::moments(analytic, true);
  EXPECT_NEAR(mr.m10 / mr.m00, ma.m10 / ma.m00, 0.2);
  EXPECT_NEAR(mr.m01 / mr.m00, ma.m01 / ma.m00, 0.2);
  EXPECT_EQ(pair.ground_truth[0].visible_pixels, static_cast<int>(area_rendered));
  EXPECT_EQ(pair.ground_truth[0].roi_left, cv::boundingRect(rendered));
}

TEST(Renderer, RectifiedDisparityEqualsFocalTimesBaselineOverDepth) {
  for (const double depth : {1.0, 2.0, 4.0}) {
    Scene scene = smallScene(panel({0, 0, depth}, 6.0, 4.0, {0.7, 0.7, 0.7}));
    scene.objects[0].texture = 0.8;
    scene.seabed.enabled = false;
    scene.light.lamp_intensity = 0.0;
    scene.water.attenuation_per_m = Eigen::Vector3d::Constant(0.01);
    const Renderer renderer(scene);
    const StereoCalibration& calib = renderer.calibration();
    const RenderedPair pair = renderer.render(0.0, 0);
    cv::Mat left, right;
    cv::cvtColor(rectify(pair.left, calib.left), left, cv::COLOR_BGR2GRAY);
    cv::cvtColor(rectify(pair.right, calib.right), right, cv::COLOR_BGR2GRAY);
    left.convertTo(left, CV_32F);
    right.convertTo(right, CV_32F);

    // Depth, in the rectified frame, of the panel point seen at the rectified principal point.
    const cv::Vec3d ray_raw = calib.left.R.t() * cv::Vec3d(0, 0, 1);
    const double z_rect = depth / ray_raw[2];
    const double expected = calib.disparityAtDepth(z_rect);

    const int half = 64;
    const cv::Point centre(cvRound(calib.left.P(0, 2)), cvRound(calib.left.P(1, 2)));
    const int shift = cvRound(expected);
    const cv::Rect left_box(centre.x - half, centre.y - half, 2 * half, 2 * half);
    const cv::Rect right_box = left_box - cv::Point(shift, 0);
    cv::Mat window;
    cv::createHanningWindow(window, left_box.size(), CV_32F);
    const cv::Point2d residual = cv::phaseCorrelate(left(left_box), right(right_box), window);
    // The right patch was taken `shift` px to the left: what remains is the sub-pixel part.
    const double measured = shift - residual.x;
    EXPECT_NEAR(measured, expected, 0.2) << "depth " << depth << " m";
    EXPECT_NEAR(residual.y, 0.0, 0.2) << "rows must align after rectification, depth " << depth << " m";
  }
}

TEST(Renderer, GroundTruthFollowsCameraAndObjectMotion) {
  Scene scene = smallScene(sphere("ball", {0, 0, 3}, 0.3));
  scene.camera_motion.velocity_mps = {0.5, 0, 0};
  scene.camera_motion.yaw_rate_dps = 10.0;
  scene.objects[0].motion.velocity_mps = {0, 0, 0.2};
  scene.objects[0].motion.bob_amplitude_m = 0.1;
  scene.objects[0].motion.bob_period_s = 4.0;
  const Renderer renderer(scene);
  const double t = 1.0;
  const GroundTruthObject gt = renderer.render(t, 0).ground_truth[0];
  const Eigen::Vector3d world(0, 0.1 * std::sin(2 * M_PI * t / 4.0), 3 + 0.2 * t);
  const Eigen::AngleAxisd yaw(10.0 * M_PI / 180.0 * t, Eigen::Vector3d::UnitY());
  const Eigen::Vector3d expected = yaw.inverse() * (world - Eigen::Vector3d(0.5 * t, 0, 0));
  EXPECT_LT((gt.centre_world_m - world).norm(), 1e-9);
  EXPECT_LT((gt.centre_left_m - expected).norm(), 1e-9);
  EXPECT_NEAR(gt.range_m, expected.norm(), 1e-9);
  EXPECT_GT(gt.visible_pixels, 1000);
}

TEST(Renderer, CameraTurnsAwayAndBack) {
  Scene scene = smallScene(sphere("ball", {0, 0, 3}, 0.3));
  scene.camera_motion.yaw_rate_dps = 1.0;
  scene.camera_motion.yaw_amplitude_deg = 150.0;
  scene.camera_motion.yaw_period_s = 40.0;
  const Renderer renderer(scene);
  for (const double t : {0.0, 10.0, 20.0, 40.0}) {
    const RenderedPair pair = renderer.render(t, 0);
    const double expected_deg = t + 150.0 * (1 - std::cos(2 * M_PI * t / 40.0)) / 2;
    const Eigen::AngleAxisd yaw(pair.camera_pose.linear());
    EXPECT_NEAR(yaw.angle() * 180.0 / M_PI, std::abs(expected_deg), 1e-9) << "t=" << t;
    EXPECT_EQ(pair.ground_truth[0].visible_pixels > 0, t == 0.0) << "t=" << t << ": yaw " << expected_deg << " deg";
  }
}

TEST(Renderer, NearerObjectOccludesFartherOne) {
  Scene alone = smallScene(sphere("back", {0, 0, 3}, 0.4));
  const int visible_alone = Renderer(alone).render(0, 0).ground_truth[0].visible_pixels;
  Scene both = alone;
  both.objects.push_back(sphere("front", {0.1, 0, 2}, 0.2));
  const RenderedPair pair = Renderer(both).render(0, 0);
  EXPECT_LT(pair.ground_truth[0].visible_pixels, visible_alone);
  EXPECT_GT(pair.ground_truth[0].visible_pixels, 0);
  EXPECT_GT(pair.ground_truth[1].visible_pixels, 0);
  EXPECT_EQ(cv::countNonZero(pair.left_labels == 1) + cv::countNonZero(pair.left_labels == 2),
            pair.ground_truth[0].visible_pixels + pair.ground_truth[1].visible_pixels);
}

TEST(Renderer, RedFadesWithDistanceAsUnderwater) {
  auto redOverBlue = [](double depth) {
    Scene scene = smallScene(panel({0, 0, depth}, 8.0, 6.0, {0.8, 0.8, 0.8}));
    scene.objects[0].texture = 0.0;
    const RenderedPair pair = Renderer(scene).render(0, 0);
    const cv::Scalar mean = cv::mean(pair.left, pair.left_labels == 1);
    return mean[2] / mean[0];
  };
  const double near = redOverBlue(1.0), far = redOverBlue(4.0);
  EXPECT_GT(near, 1.3 * far) << "near R/B " << near << ", far R/B " << far;
}

TEST(Renderer, ExposureScalesBrightness) {
  Scene dark = smallScene(sphere("ball", {0, 0, 2}, 0.3));
  Scene bright = dark;
  dark.light.exposure = 0.03;
  bright.light.exposure = 3.0;
  const double mean_dark = cv::mean(Renderer(dark).render(0, 0).left)[1];
  const double mean_bright = cv::mean(Renderer(bright).render(0, 0).left)[1];
  EXPECT_LT(mean_dark, 40);  // the paper's "too dark" is below 20
  EXPECT_GT(mean_bright, 150);
}

TEST(Renderer, SameFrameIsReproducibleAndNoiseChangesPerFrame) {
  Scene scene = smallScene(sphere("ball", {0, 0, 2}, 0.3));
  scene.sensor.noise_sigma = 3.0;
  const Renderer renderer(scene);
  const RenderedPair a = renderer.render(0.5, 3), b = renderer.render(0.5, 3), c = renderer.render(0.5, 4);
  EXPECT_EQ(cv::norm(a.left, b.left, cv::NORM_INF), 0.0);
  EXPECT_GT(cv::norm(a.left, c.left, cv::NORM_L1), 0.0);
}

TEST(Renderer, BayerOutputDemosaicsBackToTheColourImage) {
  Scene scene = smallScene(sphere("ball", {0, 0, 2}, 0.6));
  const RenderedPair colour = Renderer(scene).render(0, 0);
  scene.sensor.encoding = "bayer_rggb8";
  const RenderedPair bayer = Renderer(scene).render(0, 0);
  ASSERT_EQ(bayer.left.type(), CV_8UC1);
  EXPECT_EQ(bayer.encoding, "bayer_rggb8");
  cv::Mat demosaiced;
  cv::cvtColor(bayer.left, demosaiced, cv::COLOR_BayerBG2BGR);  // OpenCV's name for RGGB (as cv_bridge uses)
  const cv::Scalar diff = cv::mean(cv::abs(demosaiced - colour.left) + cv::abs(colour.left - demosaiced));
  for (int ch = 0; ch < 3; ++ch) EXPECT_LT(diff[ch], 3.0) << "channel " << ch;
  EXPECT_THROW(mosaicRggb(bayer.left), std::invalid_argument);
}

TEST(Renderer, InvalidSceneIsRefused) {
  Scene scene = smallScene(sphere("ball", {0, 0, 2}, 0.3));
  scene.rig.baseline_m = -1.0;
  EXPECT_THROW(Renderer{scene}, std::invalid_argument);
}

// A camera inside an object sees only its inside: no picture of the scene, so the scene is refused with the object
// and the camera named; a camera just outside it is fine.
TEST(Renderer, CameraInsideAnObjectIsRefused) {
  const auto message = [](const Scene& scene) {
    try {
      Renderer{scene};
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(message(smallScene(sphere("ball", {0, 0, 0.1}, 0.5))).find("objects[0] (ball): the left camera lies inside it"),
            std::string::npos);
  Scene box = smallScene(sphere("crate", {0.1, 0, 0.3}, 0.2));
  box.objects[0].shape = ShapeType::kBox;
  box.objects[0].size_m = {0.4, 0.2, 0.8};
  const std::string boxed = message(box);
  EXPECT_NE(boxed.find("the left camera lies inside it"), std::string::npos) << boxed;
  EXPECT_NE(boxed.find("the right camera lies inside it"), std::string::npos) << boxed;
  Scene cylinder = smallScene(sphere("tube", {0, 0, 0.2}, 0.6));
  cylinder.objects[0].shape = ShapeType::kCylinder;
  EXPECT_NE(message(cylinder).find("(tube): the left camera lies inside it"), std::string::npos);
  cylinder.objects[0].position_m.z() = 0.31;  // its near end beyond the camera
  EXPECT_EQ(message(cylinder), "");
  // What counts is the object's own frame, its length along local z, turned roll x, then pitch y, then yaw z. A rod
  // 0.3 m thick (the cameras 0.12 m apart) and 1.2 m long along the optical axis holds both cameras; turned across
  // it (pitch 90 deg: its length along x) the cameras lie 0.5 m from its axis; rolled and pitched 90 deg (its length
  // along y) and raised 0.3 m it holds them again (pitched first, its length would lie along x).
  for (const ShapeType shape : {ShapeType::kCylinder, ShapeType::kBox}) {
    Scene rod = smallScene(sphere("rod", {0, 0, 0.5}, 0.3));
    rod.objects[0].shape = shape;
    rod.objects[0].size_m = {0.3, 0.3, 1.2};
    const std::string along = message(rod);
    EXPECT_NE(along.find("(rod): the left camera lies inside it"), std::string::npos) << shapeName(shape) << along;
    EXPECT_NE(along.find("(rod): the right camera lies inside it"), std::string::npos) << shapeName(shape) << along;
    rod.objects[0].rpy_deg = {0, 90, 0};
    EXPECT_EQ(message(rod), "") << shapeName(shape);
    rod.objects[0].rpy_deg = {90, 90, 0};
    rod.objects[0].position_m = {0, 0.3, 0};
    EXPECT_NE(message(rod).find("(rod): the left camera lies inside it"), std::string::npos) << shapeName(shape);
  }
  Scene panel = smallScene(sphere("sign", {0, 0, 0}, 1.0));
  panel.objects[0].shape = ShapeType::kPanel;  // a panel through the camera has no inside
  EXPECT_EQ(message(panel), "");
}

// A camera that moves into an object later than time 0 (which construction checks): render() refuses that time, and
// camerasInside names the frames of a run as ranges, once per object and camera.
TEST(Renderer, ACameraThatMeetsAnObjectLaterIsRefusedAtThoseTimes) {
  Scene scene = smallScene(sphere("buoy", {0, 0, 2}, 0.3));
  scene.camera_motion.velocity_mps = {0, 0, 1};  // inside the buoy from 1.85 s to 2.15 s
  const Renderer renderer(scene);
  EXPECT_NO_THROW(renderer.render(1.5, 0));
  try {
    renderer.render(2.0, 0);
    ADD_FAILURE() << "a camera inside the buoy at 2 s was rendered";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("objects[0] (buoy): the left camera lies inside it at time 2 s"),
              std::string::npos)
        << e.what();
  }
  const std::vector<std::string> run = renderer.camerasInside(30, 10.0);
  ASSERT_FALSE(run.empty());
  EXPECT_EQ(run[0], "objects[0] (buoy): the left camera lies inside it at frames 19-21 (of 30 at 10 Hz)");
  EXPECT_TRUE(renderer.camerasInside(18, 10.0).empty());
}
