// SPDX-License-Identifier: BSD-3-Clause
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include <cmath>
#include <limits>

#include "sim_test_helpers.h"
#include "underwater_stereo/detection/roi_stereo_matcher.h"
#include "underwater_stereo/detection/sgbm_3way_matcher.h"
#include "underwater_stereo/sim/renderer.h"

using namespace underwater_stereo;

namespace {

struct GreyPair {
  cv::Mat left, right;
  StereoCalibration calibration;
};

GreyPair panelAt(double depth, double texture = 0.8, double baseline_m = sim::RigConfig{}.baseline_m) {
  sim::SceneObject panel;
  panel.name = "panel";
  panel.shape = sim::ShapeType::kPanel;
  panel.colour = "white";
  panel.position_m = {0, 0, depth};
  panel.size_m = {8, 6, 0};
  panel.texture = texture;
  sim::Scene scene = sim::test::smallScene(panel);
  scene.rig.baseline_m = baseline_m;
  const sim::Renderer renderer(scene);
  const sim::RenderedPair pair = renderer.render(0, 0);
  GreyPair out;
  cv::cvtColor(pair.left, out.left, cv::COLOR_BGR2GRAY);
  cv::cvtColor(pair.right, out.right, cv::COLOR_BGR2GRAY);
  out.calibration = renderer.calibration();
  return out;
}

/// Disparities between the default workspace's nearest and farthest depth.
double workspaceDisparities(const StereoCalibration& calibration) {
  const StereoMatchConfig workspace;
  const double fb = calibration.focalPx() * calibration.baselineM();
  return fb / workspace.min_depth_m - fb / workspace.max_depth_m;
}

/// The median depth [m] of matched points (there must be some).
double medianDepth(const RoiPoints& pts) {
  std::vector<float> z;
  for (const auto& p : pts.points) z.push_back(p.z());
  std::nth_element(z.begin(), z.begin() + z.size() / 2, z.end());
  return z[z.size() / 2];
}

/// A red object rendered by the small head: its grey views, both colour masks as the detector makes them, its roi and
/// the head's calibration.
struct RedViews {
  cv::Mat left, right, left_mask, right_mask;
  cv::Rect roi;
  StereoCalibration calibration;
};

/// A uniformly coloured red ball (no texture for block matching) on bluish water, 0.3 m across, `depth` ahead, and the
/// outline's expected disparity (the tangent circle R^2 / d in front of its centre).
struct RedBall : RedViews {
  double outline_disparity = 0;
};

cv::Mat redMask(const cv::Mat& bgr) {
  cv::Mat channels[3], mask;
  cv::split(bgr, channels);
  cv::compare(channels[2], channels[0], mask, cv::CMP_GT);
  return mask;
}

RedViews redViewsOf(const sim::SceneObject& object) {
  const sim::Renderer renderer(sim::test::smallScene(object));
  const sim::RenderedPair pair = renderer.render(0, 0);
  RedViews out;
  cv::cvtColor(pair.left, out.left, cv::COLOR_BGR2GRAY);
  cv::cvtColor(pair.right, out.right, cv::COLOR_BGR2GRAY);
  out.left_mask = redMask(pair.left);
  out.right_mask = redMask(pair.right);
  out.roi = pair.ground_truth.at(0).roi_left;
  out.calibration = renderer.calibration();
  return out;
}

RedBall redBallAt(double depth) {
  sim::SceneObject ball = sim::test::sphere("ball", {0.1, 0.05, depth}, 0.3);
  ball.albedo = {0.85, 0.08, 0.06};
  RedBall out{redViewsOf(ball)};
  const double d = ball.position_m.norm(), r = 0.15;
  out.outline_disparity = out.calibration.focalPx() * out.calibration.baselineM() / (depth * (1 - r * r / (d * d)));
  return out;
}

}  // namespace

TEST(RoiStereoMatcher, PointsOfAPanelLieAtItsDepth) {
  const GreyPair pair = panelAt(2.0);
  const RoiStereoMatcher matcher(pair.calibration, StereoMatchConfig{});
  const cv::Rect roi(300, 180, 60, 50);
  const RoiPoints pts = matcher.match(pair.left, pair.right, roi, cv::Mat(roi.size(), CV_8UC1, cv::Scalar(255)));
  ASSERT_GT(pts.points.size(), 500U);
  EXPECT_GT(pts.matched_pixels, 0.9 * pts.mask_pixels);
  EXPECT_NEAR(medianDepth(pts), 2.0, 0.02);
}

TEST(RoiStereoMatcher, AnObjectBeyondTheWorkspacesFarEndIsNotMatchedInsideIt) {
  // A textured panel 7 m ahead, beyond the workspace's 5 m: the half-size search also looks beyond the far end and
  // finds it there, and nothing is matched at full size (before, it was matched at a wrong disparity inside the
  // workspace). The same panel at 4.5 m is matched at its depth.
  const cv::Rect roi(300, 180, 60, 50);
  const cv::Mat mask(roi.size(), CV_8UC1, cv::Scalar(255));
  const GreyPair far = panelAt(7.0);
  const RoiStereoMatcher matcher(far.calibration, StereoMatchConfig{});
  const RoiPoints beyond = matcher.match(far.left, far.right, roi, mask);
  EXPECT_TRUE(beyond.beyond_far_end);
  EXPECT_TRUE(beyond.points.empty());
  EXPECT_EQ(beyond.searched_disparities, 0);
  // A plain panel as far: nothing for block matching to agree on, nothing said about its range (the search goes on
  // as for any object without a silhouette).
  const GreyPair plain = panelAt(7.0, 0.0);
  EXPECT_FALSE(matcher.match(plain.left, plain.right, roi, mask).beyond_far_end);
  const GreyPair inside = panelAt(4.5);
  const RoiPoints near_end = matcher.match(inside.left, inside.right, roi, mask);
  EXPECT_FALSE(near_end.beyond_far_end);
  ASSERT_GT(near_end.points.size(), 500U);
  EXPECT_NEAR(medianDepth(near_end), 4.5, 0.05);
}

TEST(RoiStereoMatcher, WithoutASilhouetteAHalfSizeSearchNarrowsTheWindow) {
  const GreyPair pair = panelAt(2.0);
  const RoiStereoMatcher matcher(pair.calibration, StereoMatchConfig{});
  const double workspace_disparities = workspaceDisparities(pair.calibration);
  const cv::Rect roi(300, 180, 60, 50);
  const RoiPoints pts = matcher.match(pair.left, pair.right, roi, cv::Mat(roi.size(), CV_8UC1, cv::Scalar(255)));
  EXPECT_TRUE(std::isnan(pts.silhouette_disparity));
  EXPECT_GT(pts.searched_disparities, 0);
  EXPECT_LT(pts.searched_disparities, workspace_disparities / 2);
  ASSERT_GT(pts.points.size(), 500U);
  EXPECT_NEAR(medianDepth(pts), 2.0, 0.02);
}

TEST(RoiStereoMatcher, WhenTheHalfSizeSearchFindsTooFewMatchesTheWholeWorkspaceIsSearched) {
  // A plain panel (nothing for block matching to hold on to): no median to narrow the window around, so the
  // full-size search covers the whole workspace, and finds no more than the half-size one did.
  const GreyPair pair = panelAt(2.0, 0.0);
  const RoiStereoMatcher matcher(pair.calibration, StereoMatchConfig{});
  const double workspace_disparities = workspaceDisparities(pair.calibration);
  const cv::Rect roi(300, 180, 60, 50);
  const RoiPoints pts = matcher.match(pair.left, pair.right, roi, cv::Mat(roi.size(), CV_8UC1, cv::Scalar(255)));
  EXPECT_GE(pts.searched_disparities, workspace_disparities);
  EXPECT_LT(pts.matched_pixels, 0.05 * pts.mask_pixels);
}

TEST(RoiStereoMatcher, AnObjectNearTheLeftEdgeIsMatchedWithoutASilhouette) {
  // Without a silhouette block matching searches (at half size first) every workspace disparity, more than
  // such an object has columns on its left: its pixels are matched all the same wherever the right camera
  // sees them.
  const GreyPair pair = panelAt(2.0);
  const RoiStereoMatcher matcher(pair.calibration, StereoMatchConfig{});
  const double disparity = pair.calibration.focalPx() * pair.calibration.baselineM() / 2.0;
  const cv::Rect roi(static_cast<int>(disparity) + 30, 180, 60, 50);
  const RoiPoints pts = matcher.match(pair.left, pair.right, roi, cv::Mat(roi.size(), CV_8UC1, cv::Scalar(255)));
  EXPECT_GT(pts.matched_pixels, 0.9 * pts.mask_pixels);
  ASSERT_GT(pts.points.size(), 500U);
  EXPECT_NEAR(medianDepth(pts), 2.0, 0.02);
}

TEST(RoiStereoMatcher, AWorkspaceWiderThanBlockMatchingSearchesLosesItsNearEndNotTheHead) {
  // A long baseline spreads 0.5-5 m over more disparities than block matching searches (1024): the head is taken,
  // the workspace's near end left out, and an object in the rest is matched and ranged as with any head.
  const GreyPair pair = panelAt(2.0, 0.8, 1.0);
  const double fb = pair.calibration.focalPx() * pair.calibration.baselineM();
  ASSERT_GT(workspaceDisparities(pair.calibration), kMaxSgbmDisparities);
  const RoiStereoMatcher matcher(pair.calibration, StereoMatchConfig{});
  // (block matching searches disparities far .. far + 1023; the tracker asks the same of the calibration alone)
  const double nearest = nearestMatchedDepthM(pair.calibration, StereoMatchConfig{});
  EXPECT_NEAR(nearest, fb / (std::floor(fb / StereoMatchConfig{}.max_depth_m) + kMaxSgbmDisparities - 1), 1e-9);
  EXPECT_EQ(matcher.nearestDepthM(), nearest);
  EXPECT_GT(nearest, StereoMatchConfig{}.min_depth_m);
  const cv::Rect roi(400, 180, 60, 50);
  const RoiPoints pts = matcher.match(pair.left, pair.right, roi, cv::Mat(roi.size(), CV_8UC1, cv::Scalar(255)));
  EXPECT_LE(pts.searched_disparities, kMaxSgbmDisparities);
  ASSERT_GT(pts.points.size(), 500U);
  EXPECT_NEAR(medianDepth(pts), 2.0, 0.02);
  // With the head's own baseline the workspace fits: its near end is min_depth_m.
  EXPECT_EQ(RoiStereoMatcher(panelAt(2.0).calibration, StereoMatchConfig{}).nearestDepthM(), StereoMatchConfig{}.min_depth_m);
}

TEST(RoiStereoMatcher, SilhouetteDisparityIsThatOfTheSphereOutline) {
  // The colour mask's shift between the rectified views of a plain ball is the disparity of its outline.
  for (const double depth : {1.5, 3.0}) {
    const RedBall ball = redBallAt(depth);
    const cv::Rect roi = ball.roi;
    const RoiStereoMatcher matcher(ball.calibration, StereoMatchConfig{});
    const RoiPoints pts = matcher.match(ball.left, ball.right, roi, ball.left_mask(roi), ball.right_mask);
    EXPECT_NEAR(pts.silhouette_disparity, ball.outline_disparity, 0.25) << "at " << depth << " m";
    // Only the part of the right mask the silhouette reads, at its place: the same disparity.
    const cv::Rect region = matcher.rightColourRegion(roi);
    ASSERT_FALSE(region.empty());
    EXPECT_LT(region.area(), ball.right_mask.total() / 2);
    const RoiPoints part =
        matcher.match(ball.left, ball.right, roi, ball.left_mask(roi), ball.right_mask(region).clone(), region.tl());
    EXPECT_DOUBLE_EQ(part.silhouette_disparity, pts.silhouette_disparity);
    const RoiPoints without = matcher.match(ball.left, ball.right, roi, ball.left_mask(roi));
    EXPECT_TRUE(std::isnan(without.silhouette_disparity));
  }
}

TEST(RoiStereoMatcher, ASilhouetteCutByTheLeftFramesRightEdgeIsComparedWhereBothFramesSeeIt) {
  // A plain red panel facing the head 2 m ahead, in view and reaching beyond the left frame's right edge (where the
  // right camera sees it run on): its silhouette's disparity is f * B / 2 m within 0.35 px either way when the right
  // silhouette is compared only as far as the left frame shows it (in view 0.26 px over; cut, see the docs; before,
  // with the three columns more that kSilhouetteSlackPx lets in at an outline, the cut one was 1.57 px short).
  for (const double x : {0.0, 0.95}) {
    sim::SceneObject panel;
    panel.name = "panel";
    panel.shape = sim::ShapeType::kPanel;
    panel.colour = "red";
    panel.albedo = {0.85, 0.08, 0.06};
    panel.texture = 0;
    panel.position_m = {x, 0, 2.0};
    panel.size_m = {0.6, 0.4, 0};
    const RedViews views = redViewsOf(panel);
    const cv::Rect roi = views.roi;
    ASSERT_EQ(roi.br().x == views.left.cols, x > 0) << "x " << x << ": roi " << roi;
    const StereoCalibration& calibration = views.calibration;
    const RoiStereoMatcher matcher(calibration, StereoMatchConfig{});
    const RoiPoints pts = matcher.match(views.left, views.right, roi, views.left_mask(roi), views.right_mask);
    EXPECT_NEAR(pts.silhouette_disparity, calibration.focalPx() * calibration.baselineM() / 2.0, 0.35)
        << (x > 0 ? "cut by the left frame's right edge" : "in view");
  }
}

TEST(RoiStereoMatcher, SilhouetteIsReadFromTheLeftColourMaskWhenGiven) {
  // A candidate's mask can be one filled piece of the object (here its core) while the right mask holds all
  // of it: their silhouettes do not align. Given the left frame's mask cut as the right one, they do.
  const RedBall ball = redBallAt(2.0);
  const cv::Rect roi = ball.roi;
  cv::Mat core;
  cv::erode(ball.left_mask(roi), core,
            cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(roi.width / 2 | 1, roi.width / 2 | 1)));
  ASSERT_GT(cv::countNonZero(core), 0);
  const RoiStereoMatcher matcher(ball.calibration, StereoMatchConfig{});
  EXPECT_TRUE(std::isnan(matcher.match(ball.left, ball.right, roi, core, ball.right_mask).silhouette_disparity));
  const cv::Mat left_colour = ball.left_mask(matcher.leftColourRegion(roi)).clone();
  EXPECT_NEAR(matcher.match(ball.left, ball.right, roi, core, ball.right_mask, cv::Point(), left_colour).silhouette_disparity,
              ball.outline_disparity, 0.25);
  EXPECT_THROW(matcher.match(ball.left, ball.right, roi, core, ball.right_mask, cv::Point(), cv::Mat(3, 3, CV_8UC1)),
               std::invalid_argument);
}

TEST(RoiStereoMatcher, AWindowThatMissedTheObjectsDisparityGivesWayToTheWholeWorkspace) {
  // A disc of the panel as the candidate, and a right colour mask whose disc lies some disparities beyond the panel's
  // true one (another object of its colour): the window around that silhouette misses the panel, block matching's
  // best costs pile up at the window's end, and the whole workspace is searched: the points lie at the panel's depth.
  const GreyPair pair = panelAt(2.0);
  const RoiStereoMatcher matcher(pair.calibration, StereoMatchConfig{});
  const int disparity = static_cast<int>(std::lround(pair.calibration.focalPx() * pair.calibration.baselineM() / 2.0));
  const cv::Rect roi(290, 170, 80, 70);
  cv::Mat mask(roi.size(), CV_8UC1, cv::Scalar(0));
  cv::ellipse(mask, cv::Point(40, 35), cv::Size(32, 27), 0, 0, 360, cv::Scalar(255), cv::FILLED);
  auto rightDiscAt = [&](int shift) {
    cv::Mat right_colour(pair.left.size(), CV_8UC1, cv::Scalar(0));
    mask.copyTo(right_colour(roi - cv::Point(shift, 0)));
    return right_colour;
  };
  for (const int wrong : {12, 40}) {
    const RoiPoints pts = matcher.match(pair.left, pair.right, roi, mask, rightDiscAt(disparity + wrong));
    // (the raw frames' discs, rectified, shift a few pixels less than they were moved: the cameras are turned)
    EXPECT_GT(pts.silhouette_disparity, disparity + wrong / 2) << wrong;
    EXPECT_TRUE(pts.window_missed) << wrong;
    EXPECT_GE(pts.searched_disparities, workspaceDisparities(pair.calibration)) << wrong;
    ASSERT_GT(pts.points.size(), 500U) << wrong;
    EXPECT_NEAR(medianDepth(pts), 2.0, 0.02) << wrong;
  }
  // The right disc moved by the panel's disparity: its window (with its slack for the turned cameras) holds the
  // panel's, nothing more is searched.
  const RoiPoints pts = matcher.match(pair.left, pair.right, roi, mask, rightDiscAt(disparity));
  EXPECT_FALSE(pts.window_missed);
  EXPECT_LT(pts.searched_disparities, workspaceDisparities(pair.calibration) / 2);
  ASSERT_GT(pts.points.size(), 500U);
  EXPECT_NEAR(medianDepth(pts), 2.0, 0.02);
}

TEST(RoiStereoMatcher, ARightSilhouetteThatRunsOnWhereTheLeftFrameShowsNothingIsNoSilhouette) {
  // A patch of a textured panel 2 m ahead as the candidate. In the right colour mask a much wider patch over the
  // same rows (a nearer object there, or the candidate's object seen more widely by the right camera): the column
  // profiles align at every shift that puts the left one inside it, and the one chosen is a guess. Given the left
  // frame's mask around the candidate (nothing beside it), that silhouette is refused and the whole workspace is
  // searched: the points lie at the panel's depth.
  const GreyPair pair = panelAt(2.0);
  const RoiStereoMatcher matcher(pair.calibration, StereoMatchConfig{});
  const int disparity = static_cast<int>(std::lround(pair.calibration.focalPx() * pair.calibration.baselineM() / 2.0));
  const cv::Rect roi(290, 170, 60, 50);
  const cv::Mat mask(roi.size(), CV_8UC1, cv::Scalar(255));
  const cv::Rect around = matcher.leftColourRegion(roi);
  ASSERT_GT(around.width, roi.width);
  cv::Mat left_colour(around.size(), CV_8UC1, cv::Scalar(0));
  left_colour(roi - around.tl()).setTo(255);
  // (Taller than the roi: rectification moves the right frame's rows against the left's; only the rows of the left
  // silhouette count.)
  const cv::Rect right_patch(roi.x - disparity, roi.y - 20, roi.width, roi.height + 40);
  cv::Mat wide(pair.left.size(), CV_8UC1, cv::Scalar(0));
  wide(cv::Rect(right_patch.x - 120, right_patch.y, right_patch.width + 240, right_patch.height)).setTo(255);
  const RoiPoints refused = matcher.match(pair.left, pair.right, roi, mask, wide, cv::Point(), left_colour);
  EXPECT_TRUE(std::isnan(refused.silhouette_disparity)) << refused.silhouette_disparity;
  ASSERT_GT(refused.points.size(), 500U);
  EXPECT_NEAR(medianDepth(refused), 2.0, 0.02);
  // The right patch alone at the panel's disparity: a silhouette (the cameras are turned: its rectified shift is a
  // few pixels less than the raw one).
  cv::Mat alone(pair.left.size(), CV_8UC1, cv::Scalar(0));
  alone(right_patch).setTo(255);
  const double own = matcher.match(pair.left, pair.right, roi, mask, alone, cv::Point(), left_colour).silhouette_disparity;
  EXPECT_GT(own, disparity - 10);
  EXPECT_LT(own, disparity + 1);
  // A neighbour touching it on the right in both frames: both masks run on alike, and the silhouette stands (the
  // centroid takes in what the slack columns let in of the neighbour).
  cv::Mat touching = alone.clone(), left_touching = left_colour.clone();
  touching(cv::Rect(right_patch.br().x, right_patch.y, 120, right_patch.height)).setTo(255);
  left_touching(cv::Rect(roi.br().x - around.x, 0, around.br().x - roi.br().x, around.height)).setTo(255);
  EXPECT_NEAR(matcher.match(pair.left, pair.right, roi, mask, touching, cv::Point(), left_touching).silhouette_disparity,
              own, 3.0);
  // Touching only in the right frame: refused.
  EXPECT_TRUE(std::isnan(matcher.match(pair.left, pair.right, roi, mask, touching, cv::Point(), left_colour).silhouette_disparity));
  // The left frame's mask must cover leftColourRegion(roi).
  EXPECT_THROW(matcher.match(pair.left, pair.right, roi, mask, alone, cv::Point(), cv::Mat(mask.size(), CV_8UC1)),
               std::invalid_argument);
}

/// A grey view tinted: each pixel's grey g as (b, g, r) = g * `tint`.
cv::Mat tinted(const cv::Mat& grey, const cv::Vec3f& tint) {
  cv::Mat f, out;
  grey.convertTo(f, CV_32F);
  cv::merge(std::vector<cv::Mat>{f * tint[0], f * tint[1], f * tint[2]}, out);
  out.convertTo(out, CV_8UC3);
  return out;
}

TEST(RoiStereoMatcher, PointsTheRightCameraSeesInAnotherColourAreDropped) {
  // The textured panel at 2 m, reddish in the left view; the right view shows the same texture (block matching
  // finds it) in a green of the same luma: what a far object hidden from the right camera by a nearer one of
  // another colour gives. Seen red by both, or grey by either, every point stays.
  const GreyPair pair = panelAt(2.0);
  const cv::Vec3f red(0.4F, 0.4F, 1.0F), green(0.4F, 0.7056F, 0.4F);  // BGR; luma 0.579 g either way
  const RoiStereoMatcher matcher(pair.calibration, StereoMatchConfig{});
  const cv::Rect roi(300, 180, 60, 50);
  const cv::Mat mask(roi.size(), CV_8UC1, cv::Scalar(255));
  const RoiPoints same = matcher.match(tinted(pair.left, red), tinted(pair.right, red), roi, mask);
  ASSERT_GT(same.points.size(), 500U);
  EXPECT_EQ(same.other_colour_points, 0);
  EXPECT_NEAR(medianDepth(same), 2.0, 0.02);
  const RoiPoints other = matcher.match(tinted(pair.left, red), tinted(pair.right, green), roi, mask);
  EXPECT_GT(other.matched_pixels, 0.9 * other.mask_pixels);  // block matching found the texture ...
  EXPECT_TRUE(other.points.empty());                          // ... in another colour
  EXPECT_EQ(other.other_colour_points, static_cast<int>(same.points.size()));
  const RoiPoints grey_right = matcher.match(tinted(pair.left, red), pair.right, roi, mask);
  EXPECT_EQ(grey_right.points.size(), same.points.size());
  StereoMatchConfig never;
  never.max_colour_difference = 1;
  EXPECT_EQ(RoiStereoMatcher(pair.calibration, never)
                .match(tinted(pair.left, red), tinted(pair.right, green), roi, mask)
                .points.size(),
            same.points.size());
}

TEST(RoiStereoMatcher, PointsWhoseRightViewLooksLikeTheWaterAreUnseen) {
  // The textured panel at 2 m, reddish in the left view against grey water; the right view shows the same texture
  // (block matching finds it) in the water's own grey: what a far object hidden from the right camera by the water
  // beside a nearer object gives. Its points are unseen and none is kept. Seen red by both, with the check off, or
  // with no point standing out at the level in the left view, every point stays.
  const GreyPair pair = panelAt(2.0);
  const cv::Vec3f red(0.4F, 0.4F, 1.0F), grey(1.0F, 1.0F, 1.0F);
  StereoMatchConfig views_only;
  views_only.max_colour_difference = 1;  // the colour check off (it too would drop grey): the view check alone
  const RoiStereoMatcher matcher(pair.calibration, views_only);
  const cv::Rect roi(300, 180, 60, 50);
  const cv::Mat mask(roi.size(), CV_8UC1, cv::Scalar(255));
  ViewAgreement water;
  water.water = cv::Mat(pair.left.size(), CV_8UC3, cv::Scalar::all(100));
  for (int k = 0; k < 2; ++k) {
    water.stats.median[k] = cv::Vec3f(0, 0, 0);
    water.stats.spread[k] = cv::Vec3f(0.05F, 0.05F, 0.05F);
  }
  water.kind = SaliencyKind::kChroma;
  water.ratio_offset = 4;
  water.level = 8;  // the red view's chroma stands out by about 14 spreads, the grey one's by 0
  const cv::Mat left = tinted(pair.left, red);
  const auto matchWith = [&](const RoiStereoMatcher& m, const cv::Vec3f& right_tint, const ViewAgreement& a) {
    return m.match(left, tinted(pair.right, right_tint), roi, mask, cv::Mat(), cv::Point(), cv::Mat(), a);
  };
  const RoiPoints seen = matchWith(matcher, red, water);
  ASSERT_GT(seen.points.size(), 500U);
  EXPECT_FALSE(seen.unseen);
  EXPECT_GT(seen.compared_points, 500);
  EXPECT_EQ(seen.unseen_points, 0);
  EXPECT_NEAR(medianDepth(seen), 2.0, 0.02);

  const RoiPoints hidden = matchWith(matcher, grey, water);
  EXPECT_TRUE(hidden.unseen);
  EXPECT_TRUE(hidden.points.empty());
  EXPECT_EQ(hidden.unseen_points, hidden.compared_points);

  StereoMatchConfig off = views_only;
  off.max_unseen_share = 1;
  const RoiPoints unchecked = matchWith(RoiStereoMatcher(pair.calibration, off), grey, water);
  EXPECT_FALSE(unchecked.unseen);
  EXPECT_EQ(unchecked.points.size(), seen.points.size());

  ViewAgreement higher = water;
  higher.level = 100;  // no left view stands out so far: nothing compared, nothing turned down
  const RoiPoints none_compared = matchWith(matcher, grey, higher);
  EXPECT_EQ(none_compared.compared_points, 0);
  EXPECT_FALSE(none_compared.unseen);
  EXPECT_EQ(none_compared.points.size(), seen.points.size());
}

TEST(RoiStereoMatcher, RoiAtTheLeftEdgeNeitherThrowsNorCrashes) {
  const GreyPair pair = panelAt(2.0);
  const RoiStereoMatcher matcher(pair.calibration, StereoMatchConfig{});
  for (const cv::Rect roi : {cv::Rect(0, 100, 20, 30), cv::Rect(0, 370, 30, 30), cv::Rect(610, 0, 30, 20)}) {
    EXPECT_NO_THROW(matcher.match(pair.left, pair.right, roi, cv::Mat(roi.size(), CV_8UC1, cv::Scalar(255)))) << roi;
  }
}

TEST(RoiStereoMatcher, BadInputThrows) {
  const GreyPair pair = panelAt(2.0);
  const RoiStereoMatcher matcher(pair.calibration, StereoMatchConfig{});
  const cv::Rect roi(300, 180, 60, 50);
  const cv::Mat mask(roi.size(), CV_8UC1, cv::Scalar(255));
  EXPECT_THROW(matcher.match(pair.left, pair.right(cv::Rect(0, 0, 320, 200)), roi, mask), std::invalid_argument);
  EXPECT_THROW(matcher.match(pair.left, pair.right, cv::Rect(600, 380, 60, 50), mask), std::invalid_argument);
  EXPECT_THROW(matcher.match(pair.left, pair.right, roi, cv::Mat(10, 10, CV_8UC1)), std::invalid_argument);
  EXPECT_THROW(matcher.match(pair.left, pair.right, roi, mask, cv::Mat(10, 10, CV_8UC3)), std::invalid_argument);
  EXPECT_THROW(matcher.match(pair.left, pair.right, roi, mask, cv::Mat(10, 10, CV_8UC1), cv::Point(pair.left.cols - 5, 0)),
               std::invalid_argument);
  ViewAgreement grey_water;  // the view check reads the water's colour
  grey_water.water = cv::Mat(10, 10, CV_8UC1, cv::Scalar(0));
  grey_water.level = 8;
  EXPECT_THROW(matcher.match(pair.left, pair.right, roi, mask, cv::Mat(), cv::Point(), cv::Mat(), grey_water),
               std::invalid_argument);
}

TEST(RoiStereoMatcher, InvalidCalibrationOrConfigIsRefused) {
  StereoCalibration c = panelAt(2.0).calibration;
  StereoMatchConfig bad;
  bad.min_depth_m = 6.0;
  bad.block_size = 4;
  bad.max_colour_difference = std::numeric_limits<double>::quiet_NaN();
  bad.max_unseen_share = 1.5;
  EXPECT_EQ(bad.validate().size(), 4U);
  EXPECT_THROW(RoiStereoMatcher(c, bad), std::invalid_argument);
  c.right.P(0, 3) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(RoiStereoMatcher(c, StereoMatchConfig{}), std::invalid_argument);
}
