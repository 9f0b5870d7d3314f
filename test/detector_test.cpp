// SPDX-License-Identifier: BSD-3-Clause
// The whole pipeline on rendered scenes with ground truth, plus its configuration and bad input.
#include <gtest/gtest.h>
#include <opencv2/core/utility.hpp>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <limits>
#include <string>
#include <thread>

#include "sim_test_helpers.h"
#include "underwater_stereo/detection/detector.h"
#include "underwater_stereo/sim/renderer.h"
#include "underwater_stereo/sim/scene_sampler.h"

using namespace underwater_stereo;

namespace {

DetectorConfig defaultConfig() { return loadDetectorConfigFile(UWS_SOURCE_DIR "/config/detector.yaml"); }

sim::Scene twoBuoys() {
  sim::Scene s = sim::loadSceneFile(UWS_SOURCE_DIR "/test/scenes/small_pool.yaml");
  s.sensor.encoding = "bgr8";
  return s;
}

/// The two buoys at the camera's shortest exposure: mean luma ~15, under the paper's gate (20), over the shipped one.
sim::Scene twoBuoysInTheDark() {
  sim::Scene dark = twoBuoys();
  dark.light.exposure = 0.01;
  return dark;
}

/// The same objects, in the same order, at the same place, from the same number of points.
void expectSameObjects(const DetectionResult& got, const DetectionResult& expected, const std::string& what) {
  ASSERT_EQ(got.objects.size(), expected.objects.size()) << what;
  for (std::size_t k = 0; k < expected.objects.size(); ++k) {
    EXPECT_EQ(got.objects[k].colour, expected.objects[k].colour) << what;
    EXPECT_EQ(got.objects[k].shape, expected.objects[k].shape) << what;
    EXPECT_EQ(got.objects[k].position_m, expected.objects[k].position_m) << what;
    EXPECT_EQ(got.objects[k].points.size(), expected.objects[k].points.size()) << what;
  }
}

/// The ground truth of the object named `name` in `pair`, or nullptr.
const sim::GroundTruthObject* truthNamed(const sim::RenderedPair& pair, const std::string& name) {
  const auto it = std::find_if(pair.ground_truth.begin(), pair.ground_truth.end(),
                               [&](const sim::GroundTruthObject& g) { return g.name == name; });
  return it == pair.ground_truth.end() ? nullptr : &*it;
}

}  // namespace

TEST(Detector, FindsBothBuoysWithRangeAndPositionWithin3Percent) {
  const sim::Renderer renderer(twoBuoys());
  Detector detector(defaultConfig(), renderer.calibration());
  const sim::RenderedPair pair = renderer.render(0.0, 0);
  const DetectionResult r = detector.detect(pair.left, pair.right);
  EXPECT_EQ(r.quality.status, QualityStatus::kOk);
  ASSERT_EQ(r.objects.size(), 2U);
  for (const auto& gt : pair.ground_truth) {
    const auto d = std::find_if(r.objects.begin(), r.objects.end(), [&](const Detection& o) { return o.colour == gt.colour; });
    ASSERT_NE(d, r.objects.end()) << gt.name;
    EXPECT_NEAR(d->range_m, gt.range_m, 0.03 * gt.range_m) << gt.name;
    EXPECT_LT((d->position_m - gt.centre_left_m).norm(), 0.03 * gt.range_m) << gt.name;
    // Size within 10 % up to 3 m (at this test's 640x400 a buoy at 3.2 m is 48 px across).
    if (gt.range_m <= 3.0) {
      EXPECT_NEAR(d->size_m.x(), gt.size_m.x(), 0.1 * gt.size_m.x()) << gt.name;
    }
    EXPECT_GT(d->points.size(), 30U);
    EXPECT_GT(d->confidence, 0.0);
    EXPECT_LE(d->confidence, 1.0);
    EXPECT_TRUE(gt.roi_left.contains((d->roi.tl() + d->roi.br()) / 2)) << gt.name;
    EXPECT_FALSE(d->cut_by_border) << gt.name;
  }
  EXPECT_GT(r.timings.total_ms, 0.0);
}

// A green buoy just behind the red one, touching it in the image: one region at every saliency level, proposed also
// as its pieces (colour_model.piece_step), so both buoys are found, each in its colour within 5 % of its range (the
// green one, partly hidden, 1.5 % short and the red one 2.1 % far when written; the green one 3.6 % short when a
// piece was still moved to its silhouette's depth, part of which is its neighbour's edge; 3.2 % far since session 43,
// read as a cylinder by the shape model learnt from twice the records); without pieces neither is (one orange
// detection over both when written).
TEST(Detector, TouchingBuoysOfTwoColoursAreBothFound) {
  sim::Scene scene = twoBuoys();
  scene.objects[1].position_m = {-0.256, 0.128, 3.2};  // 0.08 rad right of the red buoy, their radii 0.05 + 0.039
  const sim::Renderer renderer(scene);
  const sim::RenderedPair pair = renderer.render(0.0, 0);
  ASSERT_GT((pair.ground_truth[0].roi_left & pair.ground_truth[1].roi_left).area(), 0) << "the buoys touch";
  for (const double step : {defaultConfig().learned.proposals.piece_step, 0.0}) {
    DetectorConfig config = defaultConfig();
    config.learned.proposals.piece_step = step;
    const DetectionResult r = Detector(config, renderer.calibration()).detect(pair.left, pair.right);
    int found = 0;
    for (const auto& gt : pair.ground_truth) {
      found += std::any_of(r.objects.begin(), r.objects.end(), [&](const Detection& d) {
        return d.colour == gt.colour && gt.roi_left.contains((d.roi.tl() + d.roi.br()) / 2) &&
               std::abs(d.range_m - gt.range_m) < 0.05 * gt.range_m;
      });
    }
    if (step > 0) {
      EXPECT_EQ(found, 2) << r.objects.size() << " objects";
    } else {
      EXPECT_EQ(found, 0) << "without pieces: " << r.objects.size() << " objects";
    }
  }
}

// Two red buoys touching in the image, the near one at 2.5 m and a duller, larger one at 3.5 m, make one region that
// the image's chromaticity steps cut into two red pieces. In one image nothing tells two objects from one cut in two,
// so detect2d reports the region; the detector measures the pieces in its place, and as their 3D clusters lie a
// metre apart, reports both, each at its own range (before: one object at 3.65 m over both).
TEST(Detector, TouchingBuoysOfOneColourAtTwoRangesAreBothFound) {
  sim::Scene scene = twoBuoys();
  sim::SceneObject& far = scene.objects[1];
  far.colour = "red";
  far.albedo = {0.7, 0.03, 0.1};
  far.position_m = {-0.2, 0.1, 3.5};
  far.size_m = Eigen::Vector3d::Constant(0.4);
  const sim::Renderer renderer(scene);
  const sim::RenderedPair pair = renderer.render(0.0, 0);
  ASSERT_GT((pair.ground_truth[0].roi_left & pair.ground_truth[1].roi_left).area(), 0) << "the buoys touch";
  const Detector detector(defaultConfig(), renderer.calibration());
  const DetectionResult r = detector.detect(pair.left, pair.right);
  EXPECT_EQ(r.objects.size(), 2U);
  // Each at its own range (2.53 and 3.51 m: a detection within 5 % of one is not within 5 % of the other).
  for (const auto& gt : pair.ground_truth) {
    EXPECT_TRUE(std::any_of(r.objects.begin(), r.objects.end(), [&](const Detection& d) {
      return d.colour == "red" && gt.roi_left.contains((d.roi.tl() + d.roi.br()) / 2) &&
             std::abs(d.range_m - gt.range_m) < 0.05 * gt.range_m;
    })) << gt.name << " at " << gt.range_m << " m";
  }
  const DetectionResult flat = detector.detect2d(pair.left);
  ASSERT_EQ(flat.objects.size(), 1U) << "in 2D the region stands for its pieces of one colour";
  EXPECT_GT((flat.objects[0].roi & pair.ground_truth[0].roi_left).area(), 0);
  EXPECT_GT((flat.objects[0].roi & pair.ground_truth[1].roi_left).area(), 0);
}

// crossing.yaml at 33 s: the far red buoy (3.5 m) emerges from behind the near one (2 m), a sliver of ~2000 px. Their
// region, red, is cut into two red pieces, which stand in its place for stereo to tell apart. The sliver is found
// at its own range and keeps its region's colour: the check after stereo, reading its few pixels and its edge, named
// it orange (a false detection, and a landmark of its own in the tracking crossing test).
TEST(Detector, ABuoyEmergingFromBehindOneOfItsColourKeepsTheRegionsColour) {
  const sim::Renderer renderer(sim::loadSceneFile(UWS_SOURCE_DIR "/config/scenes/crossing.yaml"));
  const sim::RenderedPair pair = renderer.render(33.0, 0);
  const sim::GroundTruthObject* far = truthNamed(pair, "red_buoy_far");
  ASSERT_NE(far, nullptr);
  ASSERT_GT(far->visible_pixels, 1000);
  ASSERT_LT(far->visible_pixels, 3000) << "partly hidden by the near buoy";
  const RawFrame left(pair.left, pixelLayoutOf(pair.encoding)), right(pair.right, pixelLayoutOf(pair.encoding));
  const DetectionResult r = Detector(defaultConfig(), renderer.calibration()).detect(left, right);
  EXPECT_EQ(r.objects.size(), 2U);
  for (const Detection& d : r.objects) EXPECT_EQ(d.colour, "red") << "at " << d.range_m << " m";
  EXPECT_TRUE(std::any_of(r.objects.begin(), r.objects.end(), [&](const Detection& d) {
    return far->roi_left.contains((d.roi.tl() + d.roi.br()) / 2) && std::abs(d.range_m - far->range_m) < 0.05 * far->range_m;
  })) << "the far buoy at its own range";
  // The near buoy, the front piece, is measured again with its own outline: within 2 % of its range (its points
  // alone put it at 1.92 m, 4 % near).
  const sim::GroundTruthObject* near = truthNamed(pair, "red_buoy_near");
  ASSERT_NE(near, nullptr);
  const auto on_near = std::find_if(r.objects.begin(), r.objects.end(), [&](const Detection& d) {
    return near->roi_left.contains((d.roi.tl() + d.roi.br()) / 2);
  });
  ASSERT_NE(on_near, r.objects.end());
  EXPECT_NEAR(on_near->range_m, near->range_m, 0.02 * near->range_m);
}

// An object whose region is cut into pieces of one colour (distractors.yaml's green box at 3.08 m: its lit top face
// and the rest) is measured by its pieces, whose 3D clusters touch, and then again as the region they stood in place
// of (cut at its edge), not as the union of the pieces: within 1 % of its range, as when the region alone was measured
// (the union's outline put it 2-3 % near).
TEST(Detector, PiecesOfOneObjectAreMeasuredAsTheirRegion) {
  const sim::Renderer renderer(sim::loadSceneFile(UWS_SOURCE_DIR "/config/scenes/distractors.yaml"));
  const sim::RenderedPair pair = renderer.render(0.0, 0);
  const sim::GroundTruthObject* box = truthNamed(pair, "green_box");
  ASSERT_NE(box, nullptr);
  const RawFrame left(pair.left, pixelLayoutOf(pair.encoding)), right(pair.right, pixelLayoutOf(pair.encoding));
  const DetectionResult r = Detector(defaultConfig(), renderer.calibration()).detect(left, right);
  const auto found = std::find_if(r.objects.begin(), r.objects.end(), [&](const Detection& d) {
    return d.colour == "green" && box->roi_left.contains((d.roi.tl() + d.roi.br()) / 2);
  });
  ASSERT_NE(found, r.objects.end());
  EXPECT_NEAR(found->range_m, box->range_m, 0.01 * box->range_m);
  EXPECT_GE((found->roi & box->roi_left).area(), 0.9 * box->roi_left.area()) << "the whole box, not a piece";
  EXPECT_TRUE(std::any_of(r.rejected.begin(), r.rejected.end(), [&](const Rejection& j) {
    return j.stage == RejectionStage::kPieceOfObject && j.colour == "green" &&
           box->roi_left.contains((j.roi.tl() + j.roi.br()) / 2);
  })) << "the box came in pieces";
}

// In a dark frame (its steps are mostly noise) nothing is cut into pieces: the touching buoys in the dark give the
// same objects with and without piece_step (a guard: it does not show that pieces would differ here).
TEST(Detector, NoPiecesInADarkFrame) {
  sim::Scene scene = twoBuoysInTheDark();
  scene.objects[1].position_m = {-0.256, 0.128, 3.2};  // touching, as above
  const sim::Renderer renderer(scene);
  const sim::RenderedPair pair = renderer.render(0.0, 0);
  DetectorConfig without = defaultConfig();
  without.learned.proposals.piece_step = 0;
  const DetectionResult r = Detector(defaultConfig(), renderer.calibration()).detect(pair.left, pair.right);
  ASSERT_TRUE(r.quality.enhanced) << "a dark frame";
  expectSameObjects(r, Detector(without, renderer.calibration()).detect(pair.left, pair.right), "dark");
}

// A buoy partly out of view is reported as cut by the border (its centre is partly a guess); the whole one is not.
TEST(Detector, ABuoyPartlyOutOfViewIsReportedCutByTheBorder) {
  sim::Scene scene = twoBuoys();
  scene.objects[0].position_m.x() = 1.3;  // the red buoy at 2.5 m, over the right edge of the 640x400 view
  const sim::Renderer renderer(scene);
  const sim::RenderedPair pair = renderer.render(0.0, 0);
  const cv::Rect red = pair.ground_truth[0].roi_left;
  ASSERT_EQ(red.br().x, pair.left.cols) << "the scene puts the red buoy over the right edge " << red;
  ASSERT_GT(red.width, 20) << "and partly in view";
  const DetectionResult r = Detector(defaultConfig(), renderer.calibration()).detect(pair.left, pair.right);
  for (const auto& gt : pair.ground_truth) {
    const auto d = std::find_if(r.objects.begin(), r.objects.end(), [&](const Detection& o) { return o.colour == gt.colour; });
    ASSERT_NE(d, r.objects.end()) << gt.name;
    EXPECT_EQ(d->cut_by_border, gt.name == "red_buoy") << gt.name;
  }
  for (const Detection& d : Detector(defaultConfig()).detect2d(pair.left).objects) {
    EXPECT_EQ(d.cut_by_border, d.colour == "red") << "2D alike: " << d.colour;
  }
}

// A tube's silhouette is its sides (tangent lines, about level with its axis) and its ends (near halves of the
// rims when neither cap faces the camera; balancing each other when one does): moved to the silhouette's depth, a
// tube lying across the view, standing upright or turned towards the camera is centred on its axis (before: a
// radius in front of the axis taken for the ends of every tube not upright, 4-14 % too far here; with the sides
// alone, a tube lying across is 3-6 % too near). Not here: a short tube turned 30 degrees, whose fit reads its
// turn too small and so counts its ends (2.5 m, 0.24 x 0.3 m: 3.8 % too far; docs/accuracy.md).
TEST(Detector, ATubeIsCentredOnItsAxisLyingStandingOrTurned) {
  // One OpenCV thread, as the nodelet's workers run: block matching's stripes, and so its result, depend on it.
  struct OneOpenCvThread {
    const int before = cv::getNumThreads();
    OneOpenCvThread() { cv::setNumThreads(1); }
    ~OneOpenCvThread() { cv::setNumThreads(before); }
  } one_thread;
  struct Pose {
    Eigen::Vector3d rpy_deg;
    double z, diameter, length;
  };
  for (const Pose& pose : {Pose{{0, 90, 0}, 1.5, 0.24, 0.6}, Pose{{90, 0, 0}, 1.5, 0.24, 0.6},
                           Pose{{0, 70, 0}, 1.5, 0.24, 0.6}, Pose{{30, 60, 0}, 3.0, 0.3, 0.3}}) {
    sim::SceneObject tube = sim::test::sphere("red_tube", {0.1, 0.05, pose.z}, pose.diameter);
    tube.shape = sim::ShapeType::kCylinder;
    tube.size_m.z() = pose.length;
    tube.rpy_deg = pose.rpy_deg;
    sim::Scene scene = sim::test::smallScene(tube);
    scene.rig.width = 1920;  // at the head's own resolution: the 640x400 view finds no silhouette for it
    scene.rig.height = 1200;
    scene.rig.pixel_size_um = 5.86;
    const sim::Renderer renderer(scene);
    const sim::RenderedPair pair = renderer.render(0.0, 0);
    const DetectionResult r = Detector(defaultConfig(), renderer.calibration()).detect(pair.left, pair.right);
    const std::string what = "turned " + std::to_string(pose.rpy_deg.x()) + ", " + std::to_string(pose.rpy_deg.y()) +
                             " deg at " + std::to_string(pose.z) + " m";
    const double range = pair.ground_truth.front().range_m;
    const auto tube_found = std::find_if(r.objects.begin(), r.objects.end(), [&](const Detection& d) {
      return d.shape == ShapeKind::kCylinder && std::abs(d.range_m - range) < 0.2 * range;
    });
    ASSERT_NE(tube_found, r.objects.end()) << what;
    EXPECT_NEAR(tube_found->range_m, range, 0.025 * range) << what;
  }
}

// The nodelet's workers share one detector (OpenCV single-threaded, as the nodelet runs them: with its
// parallel loops block matching's stripes, and so its result, depend on the threads free): concurrent calls
// must give what a call alone gives.
TEST(Detector, ConcurrentCallsOnOneDetectorGiveTheSameResults) {
  const int opencv_threads = cv::getNumThreads();
  cv::setNumThreads(1);
  const sim::Renderer renderer(twoBuoys());
  const Detector detector(defaultConfig(), renderer.calibration());
  const sim::RenderedPair near = renderer.render(0.0, 0), later = renderer.render(2.0, 4);
  const DetectionResult expected[2] = {detector.detect(near.left, near.right), detector.detect(later.left, later.right)};
  ASSERT_EQ(expected[0].objects.size(), 2U);
  std::vector<DetectionResult> got(8);
  std::vector<std::thread> threads;
  for (std::size_t i = 0; i < got.size(); ++i) {
    threads.emplace_back([&, i] {
      const sim::RenderedPair& pair = i % 2 == 0 ? near : later;
      got[i] = detector.detect(pair.left, pair.right);
    });
  }
  for (std::thread& t : threads) t.join();
  for (std::size_t i = 0; i < got.size(); ++i) expectSameObjects(got[i], expected[i % 2], "call " + std::to_string(i));
  cv::setNumThreads(opencv_threads);
}

// A pair's objects measured on the detector's own threads give what they give one after another.
TEST(Detector, ObjectThreadsChangeNothingButTheTime) {
  const int opencv_threads = cv::getNumThreads();
  cv::setNumThreads(1);
  const sim::Renderer renderer(twoBuoys());
  const sim::RenderedPair pair = renderer.render(0.0, 0);
  DetectorConfig one_by_one = defaultConfig();
  one_by_one.pair_threads = 1;
  const DetectionResult expected = Detector(one_by_one, renderer.calibration()).detect(pair.left, pair.right);
  ASSERT_EQ(expected.objects.size(), 2U);
  for (int threads : {2, 3, 16}) {
    DetectorConfig config = defaultConfig();
    config.pair_threads = threads;
    const Detector detector(config, renderer.calibration());
    for (int repeat = 0; repeat < 3; ++repeat) {
      expectSameObjects(detector.detect(pair.left, pair.right), expected, std::to_string(threads) + " threads");
    }
  }
  cv::setNumThreads(opencv_threads);
}

TEST(Detector, DarkFrameOverTheGateIsSearched) {
  const sim::Renderer renderer(twoBuoysInTheDark());
  Detector detector(defaultConfig(), renderer.calibration());
  const sim::RenderedPair pair = renderer.render(0.0, 0);
  const DetectionResult r = detector.detect(pair.left, pair.right);
  ASSERT_LT(r.quality.mean_brightness, 20.0);
  EXPECT_EQ(r.quality.status, QualityStatus::kOk);
  EXPECT_TRUE(r.quality.enhanced);
  ASSERT_EQ(r.objects.size(), 2U);
  for (const auto& gt : pair.ground_truth) {
    const auto d = std::find_if(r.objects.begin(), r.objects.end(), [&](const Detection& o) { return o.colour == gt.colour; });
    ASSERT_NE(d, r.objects.end()) << gt.name;
    EXPECT_TRUE(gt.roi_left.contains((d->roi.tl() + d->roi.br()) / 2)) << gt.name;
    EXPECT_LT((d->position_m - gt.centre_left_m).norm(), 0.1 * gt.range_m) << gt.name;
  }
}

// A dark frame (under quality.enhance_below) is searched at dark_search_width_px across where that is coarser than
// search_scale: the head's 1920x1200 at a quarter; the test scene's 640x400 (480 would be finer), a frame lit
// above the threshold, a frame searched under kMinSearchSidePx or dark_search_width_px 0 at search_scale.
TEST(Detector, DarkFramesAreSearchedCoarser) {
  sim::Scene head = twoBuoysInTheDark();
  head.rig.width = 1920;
  head.rig.height = 1200;
  head.rig.pixel_size_um /= 3;
  const sim::Renderer dark(head);
  const sim::RenderedPair pair = dark.render(0.0, 0);
  const DetectionResult r = Detector(defaultConfig(), dark.calibration()).detect(pair.left, pair.right);
  ASSERT_TRUE(r.quality.enhanced);
  EXPECT_EQ(r.search_scale, 0.25);
  ASSERT_EQ(r.objects.size(), 2U) << "both buoys found at a quarter";
  for (const auto& gt : pair.ground_truth) {
    const auto d = std::find_if(r.objects.begin(), r.objects.end(), [&](const Detection& o) { return o.colour == gt.colour; });
    ASSERT_NE(d, r.objects.end()) << gt.name;
    EXPECT_LT((d->position_m - gt.centre_left_m).norm(), 0.1 * gt.range_m) << gt.name;
  }
  DetectorConfig off = defaultConfig();
  off.dark_search_width_px = 0;
  EXPECT_EQ(Detector(off, dark.calibration()).detect(pair.left, pair.right).search_scale, 0.5);

  const sim::Renderer small(twoBuoysInTheDark());
  EXPECT_EQ(Detector(defaultConfig(), small.calibration()).detect(small.render(0.0, 0).left, small.render(0.0, 0).right)
                .search_scale,
            0.5);
  const sim::Renderer lit(twoBuoys());
  const DetectionResult bright =
      Detector(defaultConfig(), lit.calibration()).detect(lit.render(0.0, 0).left, lit.render(0.0, 0).right);
  EXPECT_FALSE(bright.quality.enhanced);
  EXPECT_EQ(bright.search_scale, 0.5);
  // 2D: a dark 1920x60 frame at a quarter would be 15 px high: searched at 0.5; 1920x64 (16 px): at a quarter.
  const Detector two_d(defaultConfig());
  EXPECT_EQ(two_d.detect2d(cv::Mat(60, 1920, CV_8UC3, cv::Scalar::all(15))).search_scale, 0.5);
  EXPECT_EQ(two_d.detect2d(cv::Mat(64, 1920, CV_8UC3, cv::Scalar::all(15))).search_scale, 0.25);
}

TEST(Detector, SpoiledFrameIsReportedNotSearched) {
  const sim::Renderer renderer(twoBuoysInTheDark());
  DetectorConfig paper_gate = defaultConfig();
  paper_gate.quality.too_dark_below = 20.0;
  Detector detector(paper_gate, renderer.calibration());
  const sim::RenderedPair pair = renderer.render(0.0, 0);
  const DetectionResult r = detector.detect(pair.left, pair.right);
  EXPECT_EQ(r.quality.status, QualityStatus::kTooDark);
  EXPECT_TRUE(r.objects.empty());
}

TEST(Detector, EmptySceneGivesNothing) {
  sim::Scene empty = twoBuoys();
  empty.objects.clear();
  const sim::Renderer renderer(empty);
  Detector detector(defaultConfig(), renderer.calibration());
  const sim::RenderedPair pair = renderer.render(0.0, 0);
  EXPECT_TRUE(detector.detect(pair.left, pair.right).objects.empty());
}

// The red buoy 2.5 m away with a yellow panel 0.6 m away that hides it from the right camera only (the left one sees
// it beside the panel's edge): block matching puts the buoy's pixels on the panel (0.58 m without the colour and view
// checks, stereo.max_colour_difference and max_unseen_share 1), and the right camera sees them yellow. Either check
// turns the buoy down (the view check first); the colour check alone says why.
TEST(Detector, AnObjectHiddenFromTheRightCameraIsNotRangedAtWhatHidesIt) {
  sim::Scene scene = twoBuoys();
  scene.objects.pop_back();  // the green buoy (the panel would hide it from both cameras)
  sim::SceneObject panel;
  panel.name = "panel";
  panel.shape = sim::ShapeType::kPanel;
  panel.colour = "yellow";
  panel.albedo = {0.85, 0.75, 0.1};
  panel.position_m = {0.1, 0.024, 0.6};
  panel.size_m = {0.3, 0.3, 0};
  panel.texture = 0.8;
  scene.objects.push_back(panel);
  const sim::Renderer renderer(scene);
  const sim::RenderedPair pair = renderer.render(0.0, 0);
  const sim::GroundTruthObject& buoy = pair.ground_truth.at(0);
  ASSERT_EQ(buoy.colour, "red");
  ASSERT_GT(buoy.visible_pixels, 2000);  // whole in the left view
  const auto onTheBuoy = [&](const cv::Rect& roi) { return buoy.roi_left.contains((roi.tl() + roi.br()) / 2); };
  DetectorConfig unchecked = defaultConfig();
  unchecked.stereo.max_colour_difference = 1;
  unchecked.stereo.max_unseen_share = 1;
  const DetectionResult before = Detector(unchecked, renderer.calibration()).detect(pair.left, pair.right);
  const auto wrong = std::find_if(before.objects.begin(), before.objects.end(),
                                  [&](const Detection& d) { return onTheBuoy(d.roi); });
  ASSERT_NE(wrong, before.objects.end()) << "the scene no longer shows the case";
  EXPECT_LT(wrong->range_m, 1.0);

  for (const double unseen : {1.0, defaultConfig().stereo.max_unseen_share}) {
    DetectorConfig config = defaultConfig();
    config.stereo.max_unseen_share = unseen;
    for (const Detection& d : Detector(config, renderer.calibration()).detect(pair.left, pair.right).objects) {
      if (onTheBuoy(d.roi)) {
        EXPECT_NEAR(d.range_m, buoy.range_m, 0.03 * buoy.range_m) << "no made-up range (max_unseen_share " << unseen << ")";
      }
    }
  }
  DetectorConfig colour_alone = defaultConfig();  // the view check (max_unseen_share) turns it down first
  colour_alone.stereo.max_unseen_share = 1;
  const DetectionResult r = Detector(colour_alone, renderer.calibration()).detect(pair.left, pair.right);
  const auto why = std::find_if(r.rejected.begin(), r.rejected.end(), [&](const Rejection& j) {
    return onTheBuoy(j.roi) && j.reason.find("another colour in the right image") != std::string::npos;
  });
  EXPECT_NE(why, r.rejected.end()) << "the buoy's rejection says the right camera sees it in another colour";
}

TEST(Detector, APairWithLeftAndRightSwappedIsRejectedAsSuchNotMeasured) {
  const sim::Renderer renderer(twoBuoys());
  Detector detector(defaultConfig(), renderer.calibration());
  const sim::RenderedPair pair = renderer.render(0.0, 0);
  EXPECT_FALSE(detector.detect(pair.left, pair.right).looks_swapped);
  const DetectionResult r = detector.detect(pair.right, pair.left);
  EXPECT_TRUE(r.looks_swapped);
  EXPECT_TRUE(r.objects.empty());  // not two buoys at confident, wrong ranges
  int swapped = 0;
  for (const Rejection& rejected : r.rejected) {
    // Whatever stereo turned down (second views too) was matched the wrong way round as well.
    EXPECT_FALSE(turnedDownByStereo(rejected.stage)) << rejected.reason;
    if (rejected.stage != RejectionStage::kLeftRightSwapped) continue;
    ++swapped;
    EXPECT_NE(rejected.reason.find("swapped"), std::string::npos) << rejected.reason;
  }
  EXPECT_EQ(swapped, 2);
}

// The small pool's two buoys as its cameras send them (Bayer), swapped. Stereo turns the buoys' regions down (their
// right views do not stand out from the water where they matched), and a skipped view of one is measured in its
// place and finds a silhouette on the other buoy. Counted as a third object, that view outvoted the buoy that looked
// swapped, and the pair was measured (scripts/malformed_inputs' "3 pairs in a row" published them): one verdict per
// object.
TEST(Detector, ASecondViewIsNoExtraVoteOnThePairsOrder) {
  const sim::Renderer renderer(sim::loadSceneFile(UWS_SOURCE_DIR "/test/scenes/small_pool.yaml"));
  const sim::RenderedPair pair = renderer.render(0.0, 0);
  const RawFrame left(pair.left, pixelLayoutOf(pair.encoding)), right(pair.right, pixelLayoutOf(pair.encoding));
  const Detector detector(defaultConfig(), renderer.calibration());
  EXPECT_FALSE(detector.detect(left, right).looks_swapped);
  const DetectionResult r = detector.detect(right, left);
  EXPECT_TRUE(r.looks_swapped);
  EXPECT_TRUE(r.objects.empty());
}

// A far object: seed 100016's orange panel 4.7 m away (its 1160 stereo points scatter along their rays by stereo's
// depth step, 10 cm per pixel of disparity there; docs/accuracy.md, "The cluster radius follows stereo's depth step").
TEST(Detector, AFarObjectsPointsAreClusteredAtTheRadiusOfItsDepthStep) {
  const sim::SampledScene sampled = sim::sampleScene(100016);
  const sim::Renderer renderer(sampled.scene);
  const sim::RenderedPair pair = renderer.render(0.0, 0);
  const sim::GroundTruthObject* truth = truthNamed(pair, "orange_plane_0");
  ASSERT_NE(truth, nullptr);
  ASSERT_NEAR(truth->range_m, 4.7, 0.05);
  const auto onIt = [&](const cv::Rect& roi) { return (roi & truth->roi_left).area() > 0.5 * roi.area(); };
  const RawFrame left(pair.left, pixelLayoutOf(pair.encoding)), right(pair.right, pixelLayoutOf(pair.encoding));
  DetectorConfig config = defaultConfig();
  const DetectionResult r = Detector(config, renderer.calibration()).detect(left, right);
  const auto found = std::find_if(r.objects.begin(), r.objects.end(), [&](const Detection& d) { return onIt(d.roi); });
  ASSERT_NE(found, r.objects.end()) << "the far panel is reported";
  EXPECT_NEAR(found->range_m, truth->range_m, 0.03 * truth->range_m);
  config.cluster.eps_disparity_px = 0;  // eps_m alone: its points fall apart
  const DetectionResult fixed = Detector(config, renderer.calibration()).detect(left, right);
  EXPECT_FALSE(std::any_of(fixed.objects.begin(), fixed.objects.end(), [&](const Detection& d) { return onIt(d.roi); }));
  EXPECT_TRUE(std::any_of(fixed.rejected.begin(), fixed.rejected.end(), [&](const Rejection& j) {
    return onIt(j.roi) && j.stage == RejectionStage::kTooFewPoints;
  }));
}

TEST(Detector, OneImageGivenAsBothViewsIsRefusedNotRanged) {
  const sim::Renderer renderer(twoBuoys());
  Detector detector(defaultConfig(), renderer.calibration());
  const sim::RenderedPair pair = renderer.render(0.0, 0);
  const cv::Mat copy = pair.left.clone();  // the same pixels in another buffer, as a second file holds them
  for (const cv::Mat& right : {pair.left, copy}) {
    try {
      detector.detect(pair.left, right);
      ADD_FAILURE() << "one image as both views gave objects at made-up ranges";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("the same image"), std::string::npos) << e.what();
    }
  }
  EXPECT_EQ(detector.detect(pair.left, pair.right).objects.size(), 2U);  // a true pair still measured
}

TEST(Detector, TwoDimensionalModeNeedsNoCalibration) {
  const sim::Renderer renderer(twoBuoys());
  Detector detector(defaultConfig());
  const sim::RenderedPair pair = renderer.render(0.0, 0);
  const DetectionResult r = detector.detect2d(pair.left);
  ASSERT_EQ(r.objects.size(), 2U);
  EXPECT_EQ(r.objects[0].shape, ShapeKind::kUnknown);
  EXPECT_THROW(detector.detect(pair.left, pair.right), std::invalid_argument);
}

TEST(Detector, GarbageInputThrows) {
  const sim::Renderer renderer(twoBuoys());
  Detector detector(defaultConfig(), renderer.calibration());
  const cv::Mat good(400, 640, CV_8UC3, cv::Scalar(100, 100, 100));
  EXPECT_THROW(detector.detect(cv::Mat(), good), std::invalid_argument);
  EXPECT_THROW(detector.detect(good, cv::Mat(400, 640, CV_16UC1, cv::Scalar(0))), std::invalid_argument);
  EXPECT_THROW(detector.detect(good, cv::Mat(200, 320, CV_8UC3, cv::Scalar(0))), std::invalid_argument);
  EXPECT_THROW(detector.detect(cv::Mat(200, 320, CV_8UC3), cv::Mat(200, 320, CV_8UC3)), std::invalid_argument);
  EXPECT_THROW(detector.detect2d(cv::Mat()), std::invalid_argument);
}

TEST(Detector, NanOrMissingCalibrationIsRefused) {
  StereoCalibration calibration = sim::Renderer(twoBuoys()).calibration();
  calibration.left.K(0, 0) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(Detector(defaultConfig(), calibration), std::invalid_argument);
  EXPECT_THROW(Detector(defaultConfig(), StereoCalibration{}), std::invalid_argument);
}

TEST(DetectorConfig, ShippedFileIsValidWithItsDefaults) {
  const DetectorConfig c = defaultConfig();
  // The paper's 20 and 200 widened (docs/accuracy.md, "Dark and bright frames").
  EXPECT_EQ(c.quality.too_dark_below, 10.0);
  EXPECT_EQ(c.quality.too_bright_above, 240.0);
  EXPECT_EQ(c.colours.open_kernel_px, 10);
  EXPECT_EQ(c.colours.close_kernel_px, 10);
  ASSERT_GE(c.colours.classes.size(), 2U);
  EXPECT_EQ(c.colours.classes[0].name, "red");
  EXPECT_GT(c.colours.classes[0].hue_min, c.colours.classes[0].hue_max) << "red wraps through 0";
}

// yaml-cpp keeps both values of a repeated key and a lookup gives the first: an edit appended to a file (the
// second value) would be ignored without a word. A file with a repeated key is refused, naming key and lines.
TEST(DetectorConfig, AKeyGivenTwiceIsRefusedNamingItsLines) {
  const std::string path = ::testing::TempDir() + "/twice.yaml";
  std::ofstream(path) << "search_scale: 0.5\nstereo: {min_depth_m: 0.3, min_depth_m: 0.4}\ncolours: [{name: red}]\n"
                         "search_scale: 0.05\n";
  try {
    loadDetectorConfigFile(path);
    ADD_FAILURE() << "a repeated key was accepted";
  } catch (const std::invalid_argument& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find(path + ": keys given twice (2 problems)"), std::string::npos) << m;
    EXPECT_NE(m.find("key 'search_scale' twice (lines 1 and 4)"), std::string::npos) << m;
    EXPECT_NE(m.find("key 'stereo.min_depth_m' twice (lines 2 and 2)"), std::string::npos) << m;
  }
  // A map holding an alias of itself is walked once (it was an endless recursion), and refused by the reader.
  std::ofstream(path) << "colours: [{name: red}]\nstereo: &x {min_depth_m: 0.3, again: *x}\n";
  EXPECT_THROW(loadDetectorConfigFile(path), std::invalid_argument);
  std::remove(path.c_str());
}

TEST(DetectorConfig, ListsEveryProblem) {
  try {
    parseDetectorConfig(YAML::Load(R"(
quality: {too_dark_below: 250}
colours:
  - {name: red, hue: [170]}
  - {hue: [10, 20]}
  - {name: green, hue: [.nan, 60], saturation: [1e10, 255], value: [20.5, 255]}
candidates: {source: magic, min_area_px: abc}
stereo: {min_depth_m: 6}
speed: fast
)"));
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("speed: unknown key"), std::string::npos) << m;
    EXPECT_NE(m.find("colours[0].hue: expected 2 numbers"), std::string::npos) << m;
    EXPECT_NE(m.find("colours[1].name: missing"), std::string::npos) << m;
    // HSV bounds that are no whole numbers are named as written, not cast to an int.
    EXPECT_NE(m.find("colours[2].hue: nan is not a whole number"), std::string::npos) << m;
    EXPECT_NE(m.find("colours[2].saturation: 1e+10 is not a whole number"), std::string::npos) << m;
    EXPECT_NE(m.find("colours[2].value: 20.5 is not a whole number"), std::string::npos) << m;
    EXPECT_NE(m.find("'magic' is not colour_mask, grey_threshold or learned"), std::string::npos) << m;
    EXPECT_NE(m.find("candidates.min_area_px: expected a number"), std::string::npos) << m;
    EXPECT_NE(m.find("stereo: min_depth_m must be under max_depth_m"), std::string::npos) << "value problems too: " << m;
  }
  EXPECT_THROW(parseDetectorConfig(YAML::Load("stereo: {min_depth_m: 6}\ncolours: [{name: red, hue: [0, 10]}]")),
               std::invalid_argument);
  EXPECT_THROW(loadDetectorConfigFile("/nonexistent.yaml"), std::invalid_argument);
}

// A tool's edit of the file (evaluate_detector --shape-rules leaves the shape model out) changes only what it
// edits: the colour model next to the file is still found.
TEST(DetectorConfig, AnEditedFileKeepsItsFolder) {
  const DetectorConfig as_is = defaultConfig();
  const DetectorConfig edited = loadDetectorConfigFile(UWS_SOURCE_DIR "/config/detector.yaml", [](YAML::Node& root) {
    root["shape"].remove("model_file");
  });
  EXPECT_TRUE(as_is.shape.model);
  EXPECT_FALSE(edited.shape.model);
  ASSERT_TRUE(edited.learned.model) << "colour_model.file found beside the file";
  EXPECT_EQ(edited.learned.file, as_is.learned.file);
  EXPECT_THROW(loadDetectorConfigFile(UWS_SOURCE_DIR "/config/detector.yaml",
                                      [](YAML::Node& root) { root["colour_model"]["min_confidence"] = 2; }),
               std::invalid_argument)
      << "the edit is validated like the file";
}
