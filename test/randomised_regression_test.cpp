// SPDX-License-Identifier: BSD-3-Clause
// Regression guard on randomised scenes (issue 14): the default configuration on a few held-out sampled pairs
// must stay near its documented figures (docs/accuracy.md; thresholds a little below them: a small sample); and
// validation pairs whose object came in two pieces or touched another.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <string>

#include "../src/tools/random_evaluation.h"
#include "underwater_stereo/detection/detector.h"
#include "underwater_stereo/detection/raw_frame.h"
#include "underwater_stereo/sim/renderer.h"
#include "underwater_stereo/sim/scene_sampler.h"

using namespace underwater_stereo;

TEST(RandomisedRegression, DefaultConfigOnHeldOutSampledScenes) {
  // Seeds 100000 and up are held out: never used to learn or tune (docs/accuracy.md).
  constexpr std::uint64_t kFirstSeed = 100000;
  constexpr int kPairs = 12;
  const sim::SceneSamplerConfig sampler;
  const sim::Renderer head(sim::sampleScene(kFirstSeed, sampler).scene);
  const Detector detector(loadDetectorConfigFile(UWS_SOURCE_DIR "/config/detector.yaml"), head.calibration());
  int eligible = 0, found = 0, colour_right = 0, shape_judged = 0, shape_right = 0, false_detections = 0;
  for (int i = 0; i < kPairs; ++i) {
    const sim::SampledScene sampled = sim::sampleScene(kFirstSeed + i, sampler);
    const sim::RenderedPair pair = head.withScene(sampled.scene).render(0.0, 0);
    const RawFrame left(pair.left, pixelLayoutOf(pair.encoding)), right(pair.right, pixelLayoutOf(pair.encoding));
    const tools::PairRecord r = tools::evaluatePair(sampled, pair, detector.detect(left, right), sim::meanLuma(left.bgr()));
    for (const tools::ObjectRecord& o : r.objects) {
      if (!o.eligible) continue;
      ++eligible;
      found += o.found;
      colour_right += o.found && o.detected_colour == o.colour;
      if (o.found && o.visible_pixels >= tools::kMinShapePixels) {
        ++shape_judged;
        shape_right += o.detected_shape == o.shape;
      }
    }
    false_detections += static_cast<int>(r.false_detections.size());
  }
  SCOPED_TRACE("seeds 100000-100011");
  ASSERT_GT(eligible, 15);
  EXPECT_GE(found, 0.6 * eligible) << found << " of " << eligible << " found";
  EXPECT_GE(colour_right, 0.65 * found) << colour_right << " of " << found << " named right";
  ASSERT_GE(shape_judged, 10);
  EXPECT_GE(shape_right, 0.55 * shape_judged) << shape_right << " of " << shape_judged << " shapes named right";
  EXPECT_LE(false_detections, 1.5 * kPairs) << false_detections << " false in " << kPairs << " pairs";
}

// A pair whose run throws is named with what it threw; every other pair is still run and kept, in index order,
// whatever the number of jobs.
TEST(RandomisedRegression, APairThatFailsIsNamedAndTheOthersAreKept) {
  for (int jobs : {1, 3}) {
    const tools::PairRuns runs = tools::runPairs(10, jobs, [](int i) {
      if (i == 3 || i == 7) throw std::runtime_error("pair " + std::to_string(i) + " broke");
      tools::PairRecord r;
      r.seed = 500 + static_cast<std::uint64_t>(i);
      return r;
    });
    ASSERT_EQ(runs.records.size(), 8U) << jobs << " jobs";
    std::vector<std::uint64_t> seeds;
    for (const tools::PairRecord& r : runs.records) seeds.push_back(r.seed);
    EXPECT_EQ(seeds, (std::vector<std::uint64_t>{500, 501, 502, 504, 505, 506, 508, 509})) << jobs << " jobs";
    ASSERT_EQ(runs.failures.size(), 2U) << jobs << " jobs";
    EXPECT_EQ(runs.failures[0], (std::pair<int, std::string>{3, "pair 3 broke"}));
    EXPECT_EQ(runs.failures[1], (std::pair<int, std::string>{7, "pair 7 broke"}));
  }
}

// A detection lies on the object whose box it matches (intersection over union from 0.5), not on a nearer object
// whose pixels fill more of that box: seed 100219's orange sphere, half hidden by a red panel and detected with its
// own box, counted as a second detection of the panel until session 49. A box of part of an object lies on the object
// with most pixels in it; a box on no object on none.
TEST(RandomisedRegression, ADetectionLiesOnTheObjectWhoseBoxItMatches) {
  cv::Mat labels(100, 100, CV_16UC1, cv::Scalar(0));
  labels(cv::Rect(20, 20, 60, 60)).setTo(2);  // object 1, far
  labels(cv::Rect(10, 35, 60, 65)).setTo(1);  // object 0, nearer, hides most of it
  std::vector<tools::ObjectRecord> objects(2);
  objects[0].roi = cv::Rect(10, 35, 60, 65);
  objects[0].visible_pixels = 60 * 65;
  objects[1].roi = cv::Rect(20, 20, 60, 60);
  objects[1].visible_pixels = cv::countNonZero(labels == 2);
  ASSERT_LT(objects[1].visible_pixels, cv::countNonZero(labels(objects[1].roi) == 1))
      << "the nearer object fills more of the far one's box than the far one does";
  EXPECT_EQ(tools::objectUnder(labels, objects, objects[1].roi), 1);
  EXPECT_EQ(tools::objectUnder(labels, objects, objects[0].roi), 0);
  EXPECT_EQ(tools::objectUnder(labels, objects, cv::Rect(72, 22, 8, 8)), 1) << "a piece of the far object";
  EXPECT_EQ(tools::objectUnder(labels, objects, cv::Rect(0, 0, 15, 15)), -1) << "water";
  EXPECT_EQ(tools::objectUnder(labels, objects, cv::Rect(200, 200, 10, 10)), -1) << "outside the image";
  EXPECT_THROW(tools::objectUnder(cv::Mat(100, 100, CV_8UC1, cv::Scalar(0)), objects, objects[0].roi),
               std::invalid_argument);
}

namespace {

/// A validation pair detected with the default configuration and scored against its truth.
struct ScoredPair {
  DetectionResult result;
  tools::PairRecord record;

  /// The record of the scene's object `name` (nullptr when the scene has none).
  const tools::ObjectRecord* object(const std::string& name) const {
    const auto o = std::find_if(record.objects.begin(), record.objects.end(),
                                [&](const tools::ObjectRecord& r) { return r.name == name; });
    return o == record.objects.end() ? nullptr : &*o;
  }
};

/// The sampled scene of `seed` detected with the shipped config (changed by `edit`) and scored.
ScoredPair detectSampledPair(std::uint64_t seed, const std::function<void(DetectorConfig&)>& edit = {}) {
  const sim::SampledScene sampled = sim::sampleScene(seed);
  const sim::Renderer head(sampled.scene);
  const sim::RenderedPair pair = head.render(0.0, 0);
  DetectorConfig config = loadDetectorConfigFile(UWS_SOURCE_DIR "/config/detector.yaml");
  if (edit) edit(config);
  const Detector detector(config, head.calibration());
  const RawFrame left(pair.left, pixelLayoutOf(pair.encoding)), right(pair.right, pixelLayoutOf(pair.encoding));
  ScoredPair out;
  out.result = detector.detect(left, right);
  out.record = tools::evaluatePair(sampled, pair, out.result, sim::meanLuma(left.bgr()));
  return out;
}

/// Expects object `name` of `p` eligible, found, named `colour` and within `range_tolerance` of its range, and no false
/// detection in the pair.
void expectFoundAlone(const ScoredPair& p, const std::string& name, const std::string& colour,
                      double range_tolerance = 0.03) {
  const tools::ObjectRecord* object = p.object(name);
  ASSERT_NE(object, nullptr) << name;
  ASSERT_TRUE(object->eligible);
  ASSERT_TRUE(object->found);
  EXPECT_EQ(object->detected_colour, colour);
  EXPECT_LT(std::abs(object->range_error), range_tolerance);
  EXPECT_TRUE(p.record.false_detections.empty()) << p.record.false_detections.size() << " false";
}

/// Detects validation pair `seed` with the default configuration and expects its object `name` found once, in
/// `colour`, with no false detection in the pair, a piece of it in `piece_colour` rejected as such, and the whole at
/// least as sure as it.
void expectOnePieceJoined(std::uint64_t seed, const std::string& name, const std::string& colour,
                          const std::string& piece_colour) {
  SCOPED_TRACE("seed " + std::to_string(seed));
  const ScoredPair p = detectSampledPair(seed);
  const DetectionResult& result = p.result;
  const tools::ObjectRecord* object = p.object(name);
  ASSERT_NE(object, nullptr);
  ASSERT_TRUE(object->found);
  EXPECT_EQ(object->detected_colour, colour);
  EXPECT_TRUE(p.record.false_detections.empty())
      << p.record.false_detections.size() << " false, e.g. a second detection of " << name;
  const auto piece = std::find_if(result.rejected.begin(), result.rejected.end(), [&](const Rejection& j) {
    return j.stage == RejectionStage::kPieceOfObject && j.colour == piece_colour;
  });
  ASSERT_NE(piece, result.rejected.end());
  // The whole is reported at least as sure as the piece (the check may score the joined region lower).
  const auto whole = std::find_if(result.objects.begin(), result.objects.end(), [&](const Detection& d) {
    return d.colour == colour && (d.roi & piece->roi).area() > 0;
  });
  ASSERT_NE(whole, result.objects.end());
  EXPECT_GE(whole->confidence, piece->confidence);
}

}  // namespace

// Two pieces of one object that the colour model named apart (validation seed 60176: a near yellow ball's top band
// taken for orange) and the check after stereo renamed alike are reported once, the other piece rejected as a piece
// of it: they are joined by the colour they are reported in, not the colour model's.
TEST(RandomisedRegression, PiecesTheCheckRenamedAlikeAreOneObject) {
  expectOnePieceJoined(60176, "yellow_sphere_0", "yellow", "yellow");
}

// Two pieces of a near red tube (validation seed 60187), each passed by the check after stereo, whose joined region
// the check alone would have turned down (0.48 < 0.50): the pieces are objects, their join a matter of geometry, so
// the tube is reported once.
TEST(RandomisedRegression, PiecesTheCheckPassedAreJoinedWhateverItThinksOfTheWhole) {
  expectOnePieceJoined(60187, "red_cylinder_2", "red", "red");
}

// A red tube at 2.5 m cut by the image's top (validation seed 60299) is read as two overlapping regions, one named red
// and one orange, whose 3D clusters touch. Detections in neighbouring colours whose boxes overlap are pieces of one
// object too: the tube is reported once, red (the colour of the larger summed piece area), in the orange piece's place,
// the red one rejected as its piece (before: found orange, and the red piece a second detection).
TEST(RandomisedRegression, PiecesInNeighbouringColoursAreOneObject) {
  expectOnePieceJoined(60299, "red_cylinder_3", "red", "red");
}

// A yellow ball at 2.9 m in front of a purple tube (validation seed 60297) makes one region with it at every saliency
// level, which the colour model names red (0.56 of the votes) and the check after stereo turns down; cut along the
// image's steps, the ball's piece is named yellow with all the votes and the tube's piece nothing. A piece named a
// colour other than its region's is proposed besides it, so the ball is found, yellow and within 3 % of its range
// (missed with "no votes" when only a region holding pieces of two named colours gave way to them).
TEST(RandomisedRegression, APieceNamedOtherThanItsRegionIsProposed) {
  expectFoundAlone(detectSampledPair(60297), "yellow_sphere_1", "yellow");
}

// A red ball 2.0 m away (validation seed 60194) and a faint blue tube 4.6 m away behind it make one region, which the
// check after stereo turns down (two objects at two ranges); the ball's own region was skipped as a weaker view of it.
// A candidate turned down after stereo gives way to its most confident skipped view (LearnedSearch::second_views), so
// the ball is found within 1 % of its range, while the region stays among the rejections with why. (Until session 57
// validation seed 60187 showed this with an orange box, whose region stereo turned down for too few points; since
// the silhouette check of session 57 its own region is measured first.)
TEST(RandomisedRegression, ARegionTurnedDownAfterStereoGivesWayToItsObjectsOwnView) {
  const ScoredPair p = detectSampledPair(60194);
  const tools::ObjectRecord* ball = p.object("red_sphere_0");
  ASSERT_NE(ball, nullptr);
  ASSERT_TRUE(ball->eligible);
  ASSERT_TRUE(ball->found);
  EXPECT_LT(std::abs(ball->range_error), 0.01);
  EXPECT_TRUE(p.record.false_detections.empty()) << p.record.false_detections.size() << " false";
  const cv::Rect found = ball->detected_roi;
  EXPECT_TRUE(std::any_of(p.result.rejected.begin(), p.result.rejected.end(), [&](const Rejection& j) {
    return turnedDownByStereo(j.stage) && j.colour == ball->detected_colour && (j.roi & found) == found && j.roi != found;
  })) << "the turned-down region holding the ball is not among the rejections";
}

// A red plate 0.61 m ahead, 161 px from the image's left edge (validation seed 60023): its disparity (~360 px) puts it
// out of the right camera's view, so no point block matching finds for it stands out from the water in the right
// image as it does in the left, none is kept, and the plate is missed. Its record says why in the detector's own
// words (the rejection's reason), beside the stage.
TEST(RandomisedRegression, AMissedObjectsRecordCarriesTheRejectionsReason) {
  const ScoredPair p = detectSampledPair(60023);
  const tools::ObjectRecord* plate = p.object("red_plane_2");
  ASSERT_NE(plate, nullptr);
  ASSERT_TRUE(plate->eligible);
  ASSERT_FALSE(plate->found);
  EXPECT_EQ(plate->miss_cause, "not seen by the right camera");
  EXPECT_NE(plate->miss_reason.find("do not stand out from the water there"), std::string::npos) << plate->miss_reason;
}

// A yellow plate 4.7 m away in green water (development seed 62239), just left of an orange plate 1.05 m ahead that
// hides it from the right camera. Block matching put its points on the water beside the near plate, which looks like
// the far plate's faded colour, so the colour check kept them: it was reported at the near plate's range. Where they
// matched, the right frame does not stand out from the water as the left one does, so it is turned down, saying why.
TEST(RandomisedRegression, AnObjectTheRightCameraDoesNotSeeIsNotRangedAtWhatHidesIt) {
  const ScoredPair unchecked = detectSampledPair(62239, [](DetectorConfig& c) { c.stereo.max_unseen_share = 1; });
  const tools::ObjectRecord* before = unchecked.object("yellow_plane_2");
  ASSERT_NE(before, nullptr);
  ASSERT_TRUE(before->eligible);
  ASSERT_TRUE(before->found) << "the scene no longer shows the case";
  EXPECT_GT(before->range_error, 0.5);

  const ScoredPair p = detectSampledPair(62239);
  const tools::ObjectRecord* plate = p.object("yellow_plane_2");
  ASSERT_NE(plate, nullptr);
  EXPECT_FALSE(plate->found) << "reported " << plate->detected_range_m << " m away, not " << plate->range_m;
  EXPECT_EQ(plate->miss_cause, "not seen by the right camera");
  EXPECT_NE(plate->miss_reason.find("not seen by the right camera"), std::string::npos) << plate->miss_reason;
  const tools::ObjectRecord* near = p.object("orange_plane_0");
  ASSERT_NE(near, nullptr);
  ASSERT_TRUE(near->found) << "what hides it is still measured";
  EXPECT_LT(near->range_error, 0.1);
}
