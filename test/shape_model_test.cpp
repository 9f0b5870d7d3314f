// SPDX-License-Identifier: BSD-3-Clause
// The learnt shape decision: the 2D cues, the model file's round trip and errors, known synthetic point clouds
// named right by the shipped model, and a box seen face-on centred at its centre.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <opencv2/imgproc.hpp>

#include <cstdio>
#include <fstream>
#include <functional>
#include <random>

#include "underwater_stereo/detection/candidate_finder.h"
#include "underwater_stereo/detection/detector_config.h"
#include "underwater_stereo/detection/shape_fitter.h"
#include "underwater_stereo/detection/shape_model.h"

using namespace underwater_stereo;

namespace {

constexpr unsigned kSeed = 11;
const std::string kShippedModel = std::string(UWS_SOURCE_DIR) + "/config/detector.shape_model.yml.gz";

/// Rays through the image outline of a 3D polygon or curve given by its points.
std::vector<Eigen::Vector3d> raysThrough(const std::vector<Eigen::Vector3d>& outline) {
  std::vector<Eigen::Vector3d> rays;
  for (const auto& p : outline) rays.push_back(p.normalized());
  return rays;
}

/// A candidate whose contour and mask are `filled` (a white shape on black), shaded by `shade`(u, v).
Candidate candidateOf(const cv::Mat& filled, cv::Mat& bgr, const std::function<double(int, int)>& shade) {
  Candidate c;
  std::vector<std::vector<cv::Point>> contours;
  cv::findContours(filled.clone(), contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_NONE);
  c.contour = contours.front();
  c.roi = cv::boundingRect(c.contour);
  c.mask = filled(c.roi).clone();
  c.outline = classifyOutline(c.contour);
  bgr = cv::Mat(c.roi.size(), CV_8UC3);
  for (int v = 0; v < bgr.rows; ++v) {
    for (int u = 0; u < bgr.cols; ++u) bgr.at<cv::Vec3b>(v, u) = cv::Vec3b::all(cv::saturate_cast<std::uint8_t>(shade(u, v)));
  }
  return c;
}

struct Cloud {
  std::vector<Eigen::Vector3f> points;
  std::vector<Eigen::Vector3d> rays;
};

/// The camera-facing cap of a sphere (2 mm noise) and its silhouette.
Cloud sphereCloud(const Eigen::Vector3d& c, double r, std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  Cloud cloud;
  while (cloud.points.size() < 1200) {
    const Eigen::Vector3d dir = Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized(), p = c + r * dir;
    if (dir.dot(-p.normalized()) < 0.2) continue;
    cloud.points.push_back((p + p.normalized() * 0.002 * n(rng)).cast<float>());
  }
  const double d = c.norm();
  const Eigen::Vector3d w = c / d, a = w.unitOrthogonal(), b = w.cross(a);
  std::vector<Eigen::Vector3d> outline;
  for (int i = 0; i < 360; ++i) {
    const double t = 2 * M_PI * i / 360;
    outline.push_back(c - (r * r / d) * w + r * std::sqrt(1 - r * r / (d * d)) * (std::cos(t) * a + std::sin(t) * b));
  }
  cloud.rays = raysThrough(outline);
  return cloud;
}

/// The visible faces of a box (half extents `half`, rotated by `rot`, 2 mm noise) and its outline: the
/// projection's convex hull of its corners.
Cloud boxCloud(const Eigen::Vector3d& c, const Eigen::Vector3d& half, const Eigen::Matrix3d& rot, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  std::normal_distribution<double> n(0.0, 0.002);
  Cloud cloud;
  for (int axis = 0; axis < 3; ++axis) {
    for (const double side : {-1.0, 1.0}) {
      const Eigen::Vector3d normal = rot.col(axis) * side;
      if (normal.dot(c + normal * half[axis]) >= 0) continue;  // faces away from the camera
      for (int i = 0; i < 500; ++i) {
        Eigen::Vector3d local(u(rng) * half.x(), u(rng) * half.y(), u(rng) * half.z());
        local[axis] = side * half[axis];
        cloud.points.push_back((c + rot * local + Eigen::Vector3d(n(rng), n(rng), n(rng))).cast<float>());
      }
    }
  }
  std::vector<cv::Point2f> corners;
  for (int k = 0; k < 8; ++k) {
    const Eigen::Vector3d p = c + rot * Eigen::Vector3d(k & 1 ? half.x() : -half.x(), k & 2 ? half.y() : -half.y(),
                                                        k & 4 ? half.z() : -half.z());
    corners.emplace_back(static_cast<float>(p.x() / p.z()), static_cast<float>(p.y() / p.z()));
  }
  std::vector<cv::Point2f> hull;
  cv::convexHull(corners, hull);
  for (std::size_t i = 0; i < hull.size(); ++i) {
    const cv::Point2f a = hull[i], b = hull[(i + 1) % hull.size()];
    for (int s = 0; s < 40; ++s) {
      const cv::Point2f q = a + (b - a) * (s / 40.0F);
      cloud.rays.push_back(Eigen::Vector3d(q.x, q.y, 1.0).normalized());
    }
  }
  return cloud;
}

/// A tube lying across the view (its camera-facing half, 2 mm noise) and its outline.
Cloud tubeCloud(const Eigen::Vector3d& c, double radius, double length, std::mt19937& rng) {
  std::uniform_real_distribution<double> along(-length / 2, length / 2), angle(-M_PI / 2 + 0.15, M_PI / 2 - 0.15);
  std::normal_distribution<double> n(0.0, 0.002);
  Cloud cloud;
  for (int i = 0; i < 1200; ++i) {
    const double a = angle(rng);
    cloud.points.push_back((c + Eigen::Vector3d(along(rng), radius * std::sin(a), -radius * std::cos(a)) +
                            Eigen::Vector3d::Constant(n(rng))).cast<float>());
  }
  std::vector<Eigen::Vector3d> outline;
  for (int i = 0; i <= 100; ++i) {
    const double x = -length / 2 + length * i / 100.0;
    outline.push_back(c + Eigen::Vector3d(x, -radius, 0));
    outline.push_back(c + Eigen::Vector3d(x, radius, 0));
  }
  cloud.rays = raysThrough(outline);
  return cloud;
}

/// A tilted flat panel (2 mm noise) and its rectangular outline.
Cloud panelCloud(const Eigen::Vector3d& c, const Eigen::Matrix3d& rot, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-0.25, 0.25), v(-0.2, 0.2);
  std::normal_distribution<double> n(0.0, 0.002);
  Cloud cloud;
  for (int i = 0; i < 1200; ++i) cloud.points.push_back((c + rot * Eigen::Vector3d(u(rng), v(rng), n(rng))).cast<float>());
  std::vector<Eigen::Vector3d> outline;
  for (int i = 0; i < 100; ++i) {
    const double t = -1 + 2 * i / 99.0;
    for (const Eigen::Vector3d& local : {Eigen::Vector3d(0.25 * t, -0.2, 0), Eigen::Vector3d(0.25 * t, 0.2, 0),
                                         Eigen::Vector3d(-0.25, 0.2 * t, 0), Eigen::Vector3d(0.25, 0.2 * t, 0)}) {
      outline.push_back(c + rot * local);
    }
  }
  cloud.rays = raysThrough(outline);
  return cloud;
}

ShapeFitConfig withShippedModel() {
  ShapeFitConfig config;
  config.model = std::make_shared<const ShapeModel>(ShapeModel::load(kShippedModel));
  return config;
}

}  // namespace

TEST(OutlineCues, OutlineAndShadingOfKnownRegions) {
  cv::Mat disc = cv::Mat::zeros(400, 400, CV_8U), square = disc.clone(), bgr;
  cv::circle(disc, {200, 200}, 120, 255, cv::FILLED);
  cv::rectangle(square, cv::Rect(100, 150, 200, 100), 255, cv::FILLED);
  // A disc lit like a ball (bright centre), a rectangle shaded by a ramp.
  const Candidate ball = candidateOf(disc, bgr, [](int u, int v) { return 220 - 0.01 * ((u - 120) * (u - 120) + (v - 120) * (v - 120)); });
  const OutlineCues round = outlineCues(ball, bgr, disc.size());
  EXPECT_GT(round.circularity, 0.85);  // a pixel staircase is longer than the circle
  EXPECT_NEAR(round.solidity, 1.0, 0.02);
  EXPECT_NEAR(round.rect_fill, M_PI / 4, 0.03);
  EXPECT_NEAR(round.aspect, 1.0, 0.03);
  EXPECT_EQ(round.border_share, 0.0);
  EXPECT_GT(round.shading_quadratic, 0.9);
  EXPECT_LT(round.ellipse_residual, 0.01);
  EXPECT_NEAR(round.quad_tolerance, 0.16, 0.03);  // a circle's sagitta over a quarter turn, over sqrt(area)
  EXPECT_GT(round.hexagon_tolerance, 0.05);
  const Candidate panel = candidateOf(square, bgr, [](int u, int) { return 50 + 0.5 * u; });
  const OutlineCues flat = outlineCues(panel, bgr, square.size());
  EXPECT_NEAR(flat.rect_fill, 1.0, 0.03);
  EXPECT_NEAR(flat.aspect, 2.0, 0.05);
  EXPECT_EQ(flat.corners, 4.0);
  EXPECT_GT(flat.ellipse_residual, 0.08);
  EXPECT_LT(flat.quad_tolerance, 0.02);
  EXPECT_LT(flat.hexagon_tolerance, 0.02);
  // A hexagon (a box seen corner-on) is six-sided, not four.
  cv::Mat hexagon = cv::Mat::zeros(400, 400, CV_8U);
  std::vector<cv::Point> corners;
  for (int k = 0; k < 6; ++k) corners.emplace_back(200 + 120 * std::cos(k * M_PI / 3), 200 + 120 * std::sin(k * M_PI / 3));
  cv::fillConvexPoly(hexagon, corners, 255);
  cv::Mat hexagon_bgr;
  const Candidate hexagonal = candidateOf(hexagon, hexagon_bgr, [](int, int) { return 120.0; });
  const OutlineCues six = outlineCues(hexagonal, hexagon_bgr, hexagon.size());
  EXPECT_LT(six.hexagon_tolerance, 0.02);
  EXPECT_NEAR(six.ellipse_residual, 0.04, 0.02);
  EXPECT_GT(six.quad_tolerance, 0.1);
  EXPECT_GT(flat.shading_linear, 0.98);
  EXPECT_LT(flat.shading_quadratic, 0.02);
  EXPECT_LT(flat.shading_across, 0.02);  // its ramp runs along its longest direction
  EXPECT_LT(six.octagon_tolerance, 0.01);
  // A tube seen from the side: two straight sides and rounded ends, lit across its axis (brightest along it).
  cv::Mat stadium = cv::Mat::zeros(400, 400, CV_8U), stadium_bgr;
  cv::rectangle(stadium, cv::Rect(120, 160, 160, 80), 255, cv::FILLED);
  cv::circle(stadium, {120, 200}, 40, 255, cv::FILLED);
  cv::circle(stadium, {280, 200}, 40, 255, cv::FILLED);
  const Candidate lit_tube = candidateOf(stadium, stadium_bgr, [](int, int v) { return 200 - 0.1 * (v - 40) * (v - 40); });
  const OutlineCues tube = outlineCues(lit_tube, stadium_bgr, stadium.size());
  EXPECT_GT(tube.shading_across, 0.95);
  EXPECT_LT(round.shading_across, 0.7);  // a ball's highlight changes along every direction
  EXPECT_GT(tube.octagon_tolerance, 0.03);  // rounded ends need more than eight vertices, a box's outline six
  EXPECT_LT(six.decagon_tolerance, 0.01);
  EXPECT_GT(tube.decagon_tolerance, 0.01);  // and more than ten
  EXPECT_LT(tube.decagon_tolerance, tube.octagon_tolerance);
  // A region cut by the image border says so.
  EXPECT_GT(outlineCues(panel, bgr, cv::Size(300, 250)).border_share, 0.2);
  EXPECT_THROW(outlineCues(panel, cv::Mat(10, 10, CV_8UC3), square.size()), std::invalid_argument);
}

TEST(ShapeFeatureRow, HandsOutTheFeaturesInTheNamesOrderAndRefusesMistakes) {
  const std::vector<std::string>& names = shapeFeatureNames();
  ASSERT_EQ(static_cast<int>(names.size()), kShapeFeatureCount);
  ShapeFeatureRow row;
  for (int i = kShapeFeatureCount - 1; i >= 0; --i) {  // set in reverse: the order is the names'
    EXPECT_THROW(row.values(), std::logic_error);  // not all set yet
    row.set(names[i], i + 0.5);
  }
  const std::vector<float> values = row.values();
  for (int i = 0; i < kShapeFeatureCount; ++i) EXPECT_EQ(values[i], i + 0.5F) << names[i];
  EXPECT_THROW(row.set(names[3], 1.0), std::logic_error);  // set twice
  EXPECT_THROW(ShapeFeatureRow().set("no_such_feature", 1.0), std::logic_error);
}

TEST(ShapeModel, KnownCloudsAreNamedRightByTheShippedModel) {
  std::mt19937 rng(kSeed);
  const ShapeFitConfig config = withShippedModel();
  const Eigen::Matrix3d tilt = Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitY()).toRotationMatrix();
  const Eigen::Matrix3d corner_on = (Eigen::AngleAxisd(0.6, Eigen::Vector3d::UnitY()) *
                                     Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitX())).toRotationMatrix();
  struct Case {
    const char* name;
    Cloud cloud;
    OutlineCues cues;
    ShapeKind truth;
  };
  // Outline cues of each shape as the simulator's uncut objects show them (medians of the shape model's training set).
  OutlineCues ball{OutlineKind::kCircle, 2.0};
  ball.circularity = 0.9;
  ball.rect_fill = M_PI / 4;
  ball.corners = 8;
  ball.shading_spread = 0.15;
  ball.shading_quadratic = 0.6;
  ball.ellipse_residual = 0.01;
  ball.quad_tolerance = 0.18;
  ball.hexagon_tolerance = 0.15;
  OutlineCues panel{OutlineKind::kRectangle, 1.0};
  panel.circularity = M_PI / 4;
  panel.corners = 4;
  panel.shading_spread = 0.03;
  panel.shading_linear = 0.5;
  panel.ellipse_residual = 0.095;
  panel.quad_tolerance = 0.03;
  panel.hexagon_tolerance = 0.02;
  OutlineCues tube{OutlineKind::kRectangle, 3.0};
  tube.aspect = 6.0;
  tube.circularity = 0.45;
  tube.corners = 4;
  tube.shading_spread = 0.12;
  tube.shading_quadratic = 0.5;
  tube.ellipse_residual = 0.08;
  tube.quad_tolerance = 0.16;
  tube.hexagon_tolerance = 0.08;
  OutlineCues box{OutlineKind::kPolygon, 80.0};
  box.circularity = 0.75;
  box.rect_fill = 0.8;
  box.corners = 6;
  box.shading_spread = 0.25;
  box.shading_linear = 0.3;
  box.ellipse_residual = 0.08;
  box.quad_tolerance = 0.15;
  box.hexagon_tolerance = 0.03;
  const std::vector<Case> cases{
      {"sphere", sphereCloud({0.2, 0.1, 2.0}, 0.15, rng), ball, ShapeKind::kSphere},
      {"plane", panelCloud({-0.2, 0.1, 2.5}, tilt, rng), panel, ShapeKind::kPlane},
      {"cylinder", tubeCloud({0.0, 0.2, 2.0}, 0.06, 0.7, rng), tube, ShapeKind::kCylinder},
      {"box", boxCloud({0.1, 0.0, 2.5}, {0.2, 0.15, 0.12}, corner_on, rng), box, ShapeKind::kBox}};
  for (const Case& c : cases) {
    const ShapeFit fit = fitShape(c.cloud.points, c.cloud.rays, c.cues, config);
    EXPECT_EQ(fit.shape, c.truth) << c.name << ", seed " << kSeed;
    EXPECT_EQ(fit.features.size(), static_cast<std::size_t>(kShapeFeatureCount)) << c.name;
  }
}

TEST(ShapeModel, LearntFromFeaturesAndReadBackFromItsFile) {
  // Four shapes, each a tight cluster in feature space: the model names held-out rows right after a save and load.
  std::mt19937 rng(kSeed);
  std::normal_distribution<float> n(0.0F, 0.05F);
  const std::vector<ShapeKind> shapes{ShapeKind::kSphere, ShapeKind::kCylinder, ShapeKind::kBox, ShapeKind::kPlane};
  cv::Mat samples(0, kShapeFeatureCount, CV_32F);
  std::vector<ShapeKind> labels;
  auto row = [&](int k) {
    cv::Mat r(1, kShapeFeatureCount, CV_32F);
    for (int j = 0; j < kShapeFeatureCount; ++j) r.at<float>(j) = static_cast<float>((k * 7 + j) % 4) + n(rng);
    return r;
  };
  for (int i = 0; i < 200; ++i) {
    samples.push_back(row(i % 4));
    labels.push_back(shapes[i % 4]);
  }
  const std::string path = testing::TempDir() + "/shape_model_test.yml.gz";
  ShapeModel::train(samples, labels, ShapeModelTraining{}).save(path);
  const ShapeModel model = ShapeModel::load(path);
  for (int k = 0; k < 4; ++k) {
    const cv::Mat r = row(k);
    const ShapeVerdict v = model.classify(std::vector<float>(r.begin<float>(), r.end<float>()));
    EXPECT_EQ(v.shape, shapes[k]);
    EXPECT_GT(v.confidence, 0.8);
  }
  EXPECT_THROW(model.classify(std::vector<float>(3, 0.0F)), std::invalid_argument);
  EXPECT_THROW(ShapeModel::train(samples.rowRange(0, 3), labels, ShapeModelTraining{}), std::invalid_argument);
  std::vector<ShapeKind> no_planes(labels.size(), ShapeKind::kSphere);
  EXPECT_THROW(ShapeModel::train(samples, no_planes, ShapeModelTraining{}), std::invalid_argument);
  std::remove(path.c_str());
}

TEST(ShapeModel, FileErrorsAreNamed) {
  auto message = [](const std::string& path) {
    try {
      ShapeModel::load(path);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("/nonexistent/m.yml.gz").find("shape model /nonexistent/m.yml.gz: No such file or directory"), std::string::npos);
  EXPECT_NE(message(testing::TempDir()).find(": a folder, not a file"), std::string::npos) << message(testing::TempDir());
  const std::string garbage = testing::TempDir() + "/shape_model_garbage.yml";
  std::ofstream(garbage) << "%YAML:1.0\nfeatures: [a, b]\n";
  EXPECT_NE(message(garbage).find("made for other features"), std::string::npos) << message(garbage);
  const std::string colour = std::string(UWS_SOURCE_DIR) + "/config/detector.colour_model.yml.gz";
  EXPECT_NE(message(colour).find("made for other features"), std::string::npos) << message(colour);
  std::ofstream(garbage) << "not: [a yaml";
  EXPECT_NE(message(garbage).find("shape model " + garbage), std::string::npos) << message(garbage);
  std::remove(garbage.c_str());
  // In the detector configuration: the key and the file are named.
  try {
    parseDetectorConfig(YAML::Load("shape: {model_file: missing.yml.gz}"), "/nonexistent");
    ADD_FAILURE() << "a missing shape model was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("shape.model_file: shape model /nonexistent/missing.yml.gz"), std::string::npos)
        << e.what();
  }
}

TEST(ShapeFitter, BoxSeenFaceOnIsCentredBehindItsFace) {
  // Only the front face (0.4 x 0.3) of a 0.4 x 0.3 x 0.3 box at 2.5 m is seen: its hidden depth is taken as the
  // mean of its visible sides, so the centre goes ~0.175 m behind the face, not onto it.
  std::mt19937 rng(kSeed);
  const Eigen::Vector3d c(0.1, 0.05, 2.5);
  Cloud cloud = boxCloud(c, {0.2, 0.15, 0.15}, Eigen::Matrix3d::Identity(), rng);
  OutlineCues cues{OutlineKind::kRectangle, 80.0};
  const ShapeFit fit = fitShape(cloud.points, cloud.rays, cues, ShapeFitConfig{});
  ASSERT_EQ(fit.shape, ShapeKind::kBox) << "seed " << kSeed;
  EXPECT_NEAR(fit.centre.z(), c.z() - 0.15 + 0.175, 0.02);  // the face at 2.35 m
  EXPECT_NEAR(fit.hidden_depth_m, 0.175, 0.02);
  EXPECT_LT((fit.centre - c).norm(), 0.04);
}
