// SPDX-License-Identifier: BSD-3-Clause
// The tracker against ground truth: objects and a moving, turning camera simulated here, detections with the
// measurement noise the tracker assumes.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>
#include <set>

#include "underwater_stereo/sim/stereo_rig.h"
#include "underwater_stereo/tracking/camera_view.h"
#include "underwater_stereo/tracking/tracker.h"

using namespace underwater_stereo;

namespace {

struct TrueObject {
  std::string name, colour;
  Eigen::Vector3d position;  ///< world frame at t = 0
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
  Eigen::Vector3d at(double t) const { return position + velocity * t; }
};

/// Camera in the world (optical axes: x right, y down, z forward) yawing about y.
Eigen::Isometry3d cameraPose(const Eigen::Vector3d& position, double yaw_deg) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::AngleAxisd(yaw_deg * M_PI / 180.0, Eigen::Vector3d::UnitY()).toRotationMatrix();
  pose.translation() = position;
  return pose;
}

/// Feeds the tracker frames of `objects` seen from `pose(t)` at 15 Hz for `seconds`; records which track each
/// object got in every frame where it was detected.
class Scenario {
 public:
  Scenario(std::vector<TrueObject> objects, unsigned seed, TrackingConfig config = {})
      : objects(std::move(objects)),
        config(config),
        tracker(config),
        view(sim::StereoRig(sim::RigConfig{}).calibration().left, 0.5, 5.0, 40.0),
        rng(seed),
        seed(seed) {}

  /// Detections of the objects the camera sees (nearer objects hide farther ones within 1.2 diameters).
  TrackingFrame frame(double t, const Eigen::Isometry3d& pose) {
    TrackingFrame f;
    f.stamp_s = t;
    f.camera_pose = pose;
    f.in_view = [this](const Eigen::Vector3d& p) { return view.sees(p); };
    std::vector<Eigen::Vector3d> in_camera;
    for (const TrueObject& o : objects) in_camera.push_back(pose.inverse() * o.at(t));
    seen.clear();
    for (std::size_t i = 0; i < objects.size(); ++i) {
      if (!view.sees(in_camera[i])) continue;
      bool hidden = false;
      for (std::size_t j = 0; j < objects.size(); ++j) {
        const Eigen::Vector3d a = in_camera[i].normalized(), b = in_camera[j].normalized();
        if (j != i && in_camera[j].norm() < in_camera[i].norm() && std::acos(std::min(1.0, a.dot(b))) * in_camera[j].norm() < 0.3) {
          hidden = true;
        }
      }
      if (hidden) continue;
      Observation o;
      o.colour = objects[i].colour;
      o.shape = ShapeKind::kSphere;
      o.size_m = Eigen::Vector3d::Constant(0.25);
      const Eigen::LLT<Eigen::Matrix3d> llt(tracker.measurementCovariance(in_camera[i]));
      Eigen::Vector3d noise(gauss(rng), gauss(rng), gauss(rng));
      o.position_m = in_camera[i] + llt.matrixL() * noise;
      f.observations.push_back(o);
      seen.push_back(i);
    }
    return f;
  }

  TrackingUpdate step(double t, const Eigen::Isometry3d& pose) {
    const TrackingFrame f = frame(t, pose);
    TrackingUpdate u = tracker.update(f);
    for (std::size_t k = 0; k < seen.size(); ++k) {
      if (u.track_ids[k] != 0) ++assignments[seen[k]][u.track_ids[k]];
    }
    return u;
  }

  /// IDF1-style: per object the frames carrying its most frequent track id, over all its tracked frames.
  double idAgreement() const {
    double best = 0, all = 0;
    for (const auto& [object, ids] : assignments) {
      int top = 0;
      for (const auto& [id, count] : ids) {
        all += count;
        top = std::max(top, count);
      }
      best += top;
    }
    return all > 0 ? best / all : 0.0;
  }

  std::vector<TrueObject> objects;
  TrackingConfig config;
  Tracker tracker;
  CameraView view;
  std::mt19937 rng;
  unsigned seed;
  std::normal_distribution<double> gauss{0.0, 1.0};
  std::vector<std::size_t> seen;
  std::map<std::size_t, std::map<std::uint32_t, int>> assignments;
};

Observation observation(const std::string& colour, const Eigen::Vector3d& position) {
  Observation o;
  o.colour = colour;
  o.position_m = position;
  return o;
}

const Track* nearest(const Tracker& tracker, const Eigen::Vector3d& p) {
  const Track* best = nullptr;
  for (const Track& t : tracker.tracks()) {
    if (!best || (t.filter.position() - p).norm() < (best->filter.position() - p).norm()) best = &t;
  }
  return best;
}

}  // namespace

TEST(Tracker, ThreeBuoysKeepTheirIdsWhenTheCameraLooksAwayAndBack) {
  Scenario s({{"red", "red", {-0.8, 0.2, 3.0}}, {"green", "green", {0.0, 0.0, 3.5}}, {"red2", "red", {0.8, 0.3, 3.2}}},
             7);
  // 0-5 s look at them while moving sideways; 5-8 s yaw to 120 deg; 8-14 s look away; 14-17 s back; 17-22 s look.
  auto yaw = [](double t) {
    if (t < 5) return 0.0;
    if (t < 8) return 40.0 * (t - 5);
    if (t < 14) return 120.0;
    if (t < 17) return 120.0 - 40.0 * (t - 14);
    return 0.0;
  };
  std::map<std::size_t, std::uint32_t> id_before;
  for (int k = 0; k < 22 * 15; ++k) {
    const double t = k / 15.0;
    const TrackingUpdate u = s.step(t, cameraPose({0.02 * t, 0, 0}, yaw(t)));
    EXPECT_EQ(u.outcome, FrameOutcome::kTracked) << "seed " << s.seed;
    EXPECT_TRUE(u.dropped.empty()) << "t=" << t << " seed " << s.seed;
    if (k == 4 * 15) {
      for (std::size_t i = 0; i < 3; ++i) {
        const Track* t3 = nearest(s.tracker, s.objects[i].position);
        ASSERT_NE(t3, nullptr);
        EXPECT_EQ(t3->status, TrackStatus::kConfirmed);
        id_before[i] = t3->id;
      }
    }
    if (k == 11 * 15) {  // looking away: all three kept as landmarks, none in view
      ASSERT_EQ(s.tracker.tracks().size(), 3U);
      for (const Track& t3 : s.tracker.tracks()) EXPECT_FALSE(t3.in_view);
    }
  }
  ASSERT_EQ(s.tracker.tracks().size(), 3U);
  for (std::size_t i = 0; i < 3; ++i) {
    const Track* t3 = nearest(s.tracker, s.objects[i].position);
    EXPECT_EQ(t3->id, id_before[i]) << s.objects[i].name << " seed " << s.seed;
    const double range = (s.objects[i].position - Eigen::Vector3d(0.02 * 22, 0, 0)).norm();
    EXPECT_LT((t3->filter.position() - s.objects[i].position).norm(), 0.01 * range) << s.objects[i].name;
  }
  EXPECT_DOUBLE_EQ(s.idAgreement(), 1.0);
}

TEST(Tracker, SameColourBuoysWhoseImagesCrossKeepTheirIds) {
  // A near buoy moving right and a far one moving left: their images cross at t = 5 s; the near one hides
  // the far one for a moment.
  Scenario s({{"near", "red", {-1.0, 0.0, 2.0}, {0.2, 0, 0}}, {"far", "red", {1.75, 0.0, 3.5}, {-0.35, 0, 0}}}, 11);
  for (int k = 0; k < 10 * 15; ++k) s.step(k / 15.0, Eigen::Isometry3d::Identity());
  EXPECT_DOUBLE_EQ(s.idAgreement(), 1.0) << "seed " << s.seed;
  EXPECT_EQ(s.assignments.size(), 2U);
  for (const auto& [object, ids] : s.assignments) EXPECT_EQ(ids.size(), 1U) << s.objects[object].name;
}

TEST(Tracker, MovingObjectVelocityWithin5cmPerSecond) {
  const Eigen::Vector3d velocity(0.15, -0.05, 0.1);
  Scenario s({{"ball", "yellow", {-0.6, 0.2, 2.0}, velocity}}, 3);
  for (int k = 0; k < 8 * 15; ++k) s.step(k / 15.0, cameraPose({0.05 * k / 15.0, 0, 0}, 0));
  ASSERT_EQ(s.tracker.tracks().size(), 1U);
  const Track& t = s.tracker.tracks()[0];
  EXPECT_LT((t.filter.velocity() - velocity).norm(), 0.05) << t.filter.velocity().transpose() << " seed " << s.seed;
  EXPECT_GE(t.observations, 8U * 15U - 3U) << "a 99.9 % gate";
}

TEST(Tracker, ConfirmsAfterNHitsAndDropsAfterMMissesInView) {
  TrackingConfig config;
  config.confirm_hits = 3;
  config.max_misses = 4;
  Tracker tracker(config);
  TrackingFrame f;
  f.in_view = [](const Eigen::Vector3d&) { return true; };
  const Observation o = observation("red", {0, 0, 2});
  f.observations = {o};
  std::uint32_t id = 0;
  for (int k = 0; k < 3; ++k) {
    f.stamp_s = k * 0.1;
    id = tracker.update(f).track_ids[0];
    EXPECT_EQ(tracker.tracks()[0].status, k < 2 ? TrackStatus::kTentative : TrackStatus::kConfirmed);
  }
  f.observations.clear();
  for (int k = 3; k < 6; ++k) {
    f.stamp_s = k * 0.1;
    EXPECT_TRUE(tracker.update(f).dropped.empty());
  }
  f.stamp_s = 0.6;
  EXPECT_EQ(tracker.update(f).dropped, std::vector<std::uint32_t>{id});
  EXPECT_TRUE(tracker.tracks().empty());
  // Out of view a track is never missed: a landmark.
  f.observations = {o};
  for (int k = 0; k < 3; ++k) {
    f.stamp_s = 1.0 + k * 0.1;
    EXPECT_GT(tracker.update(f).track_ids[0], id) << "ids are never reused";
  }
  f.observations.clear();
  f.in_view = [](const Eigen::Vector3d&) { return false; };
  for (int k = 0; k < 100; ++k) {
    f.stamp_s = 2.0 + k * 0.1;
    tracker.update(f);
  }
  ASSERT_EQ(tracker.tracks().size(), 1U);
  EXPECT_EQ(tracker.tracks()[0].observations, 3U);
  EXPECT_NE(tracker.findConfirmed(""), nullptr);
}

TEST(Tracker, TentativeTracksOfOneGlimpseAreDropped) {
  Tracker tracker(TrackingConfig{});
  TrackingFrame f;
  const Observation o = observation("green", {0.3, 0, 3});
  f.observations = {o};
  tracker.update(f);
  f.observations.clear();
  f.in_view = [](const Eigen::Vector3d&) { return false; };  // even out of view
  f.stamp_s = 0.1;
  EXPECT_TRUE(tracker.update(f).dropped.empty());
  f.stamp_s = 0.2;
  EXPECT_EQ(tracker.update(f).dropped.size(), 1U);
}

TEST(Tracker, AnObjectCutByTheImageBorderUpdatesATrackButStartsNone) {
  Tracker tracker(TrackingConfig{});
  TrackingFrame f;
  Observation cut = observation("green", {1.5, 0, 3});
  cut.cut_by_border = true;
  f.observations = {cut};
  EXPECT_EQ(tracker.update(f).track_ids[0], 0U) << "a partly seen object starts no track";
  Observation whole = cut;
  whole.cut_by_border = false;
  whole.position_m = {1.4, 0, 3};
  f.stamp_s = 0.1;
  f.observations = {whole};
  const std::uint32_t id = tracker.update(f).track_ids[0];
  EXPECT_NE(id, 0U);
  f.stamp_s = 0.2;
  f.observations = {cut};
  EXPECT_EQ(tracker.update(f).track_ids[0], id) << "leaving the view, it still updates its track";
}

// A detection the border cuts has its centre partly guessed: it pulls a track far less than a whole one.
TEST(Tracker, ADetectionCutByTheBorderPullsATrackLessThanAWholeOne) {
  const TrackingConfig config;
  const Eigen::Vector3d truth(0.5, 0, 3), off = truth + Eigen::Vector3d(0, 0, 0.1);
  double moved[2] = {0, 0};
  for (const bool cut : {false, true}) {
    Tracker tracker(config);
    TrackingFrame f;
    f.observations = {observation("green", truth)};
    for (int k = 0; k < 10; ++k, f.stamp_s += 0.1) tracker.update(f);
    Observation o = observation("green", off);
    o.cut_by_border = cut;
    f.observations = {o};
    ASSERT_NE(tracker.update(f).track_ids[0], 0U) << "cut " << cut << ": it updates the track";
    moved[cut] = (tracker.tracks().at(0).filter.position() - truth).norm();
  }
  EXPECT_GT(moved[0], 0.02) << "a whole detection 10 cm off moves the track";
  EXPECT_LT(moved[1], moved[0] / 10) << "a cut one " << config.cut_by_border_sigma_scale << " times as uncertain";
  const Tracker tracker(config);
  EXPECT_TRUE(tracker.measurementCovariance(off, true).isApprox(
      std::pow(config.cut_by_border_sigma_scale, 2) * tracker.measurementCovariance(off, false)));
}

TEST(Tracker, IncompatibleDetectionsNeverJoinATrack) {
  TrackingConfig config;
  config.targets = {{"red_buoy", "red", ShapeKind::kSphere, 0.25, 0.3}};
  config.confirm_hits = 1;  // a confirmed track survives the pairs without it
  Tracker tracker(config);
  TrackingFrame f;
  Observation red = observation("red", {0, 0, 2});
  red.shape = ShapeKind::kSphere;
  red.target = 0;
  f.observations = {red};
  const std::uint32_t id = tracker.update(f).track_ids[0];
  Observation orange = red, box = red, untargeted = red, unknown = red;
  orange.colour = "orange";
  box.shape = ShapeKind::kBox;
  untargeted.target = -1;
  unknown.shape = ShapeKind::kUnknown;
  for (const Observation& o : {orange, box, untargeted}) {
    f.stamp_s += 0.1;
    f.observations = {o};
    EXPECT_NE(tracker.update(f).track_ids[0], id);
  }
  f.stamp_s += 0.1;
  f.observations = {unknown};
  EXPECT_EQ(tracker.update(f).track_ids[0], id) << "an unknown shape fits any";
  EXPECT_EQ(tracker.find(id)->label, "red_buoy");
  EXPECT_EQ(tracker.find(id)->shape, ShapeKind::kSphere);
}

TEST(Tracker, NanDetectionIsReportedAndNotTracked) {
  Tracker tracker(TrackingConfig{});
  TrackingFrame f;
  const Observation good = observation("red", {0, 0, 2}), bad = observation("red", {std::nan(""), 0, 2});
  f.observations = {bad, good};
  const TrackingUpdate u = tracker.update(f);
  EXPECT_EQ(u.outcome, FrameOutcome::kTracked);
  EXPECT_EQ(u.track_ids[0], 0U);
  EXPECT_NE(u.track_ids[1], 0U);
  ASSERT_EQ(u.problems.size(), 1U);
  EXPECT_NE(u.problems[0].find("observation 0"), std::string::npos) << u.problems[0];
  EXPECT_EQ(tracker.tracks().size(), 1U);
  EXPECT_TRUE(tracker.tracks()[0].filter.position().allFinite());
  f.stamp_s = std::nan("");
  EXPECT_EQ(tracker.update(f).outcome, FrameOutcome::kInvalid);
  EXPECT_EQ(tracker.tracks().size(), 1U);
}

TEST(Tracker, StampGoingBackwardsIsIgnoredOrResets) {
  Tracker tracker(TrackingConfig{});
  TrackingFrame f;
  const Observation o = observation("red", {0, 0, 2});
  f.observations = {o};
  for (int k = 0; k < 5; ++k) {
    f.stamp_s = 10.0 + k * 0.1;
    tracker.update(f);
  }
  const std::uint32_t id = tracker.tracks()[0].id;
  const std::uint32_t observations = tracker.tracks()[0].observations;
  f.stamp_s = 10.2;  // a late pair
  TrackingUpdate u = tracker.update(f);
  EXPECT_EQ(u.outcome, FrameOutcome::kStampBackwards);
  EXPECT_EQ(u.track_ids[0], 0U);
  EXPECT_EQ(tracker.tracks()[0].observations, observations);
  EXPECT_FALSE(u.problems.empty());
  f.stamp_s = 2.0;  // a restarted bag
  u = tracker.update(f);
  EXPECT_EQ(u.outcome, FrameOutcome::kClockRestarted);
  EXPECT_EQ(u.dropped, std::vector<std::uint32_t>{id});
  ASSERT_EQ(tracker.tracks().size(), 1U);
  EXPECT_GT(tracker.tracks()[0].id, id);
}

TEST(Tracker, CameraTeleportResetsTracks) {
  Tracker tracker(TrackingConfig{});
  TrackingFrame f;
  const Observation o = observation("red", {0, 0, 2});
  f.observations = {o};
  for (int k = 0; k < 5; ++k) {
    f.stamp_s = k * 0.1;
    f.camera_pose = cameraPose({0.1 * k * 0.1, 0, 0}, 2.0 * k * 0.1);  // 0.1 m/s, 2 deg/s: fine
    EXPECT_EQ(tracker.update(f).outcome, FrameOutcome::kTracked);
  }
  f.stamp_s = 0.5;
  f.camera_pose = cameraPose({5.0, 0, 0}, 1.0);
  const TrackingUpdate u = tracker.update(f);
  EXPECT_EQ(u.outcome, FrameOutcome::kCameraJumped);
  EXPECT_EQ(u.dropped.size(), 1U);
  ASSERT_FALSE(u.problems.empty());
  EXPECT_NE(u.problems[0].find("m/s"), std::string::npos);
  EXPECT_EQ(tracker.tracks().size(), 1U);
  f.stamp_s = 0.6;
  f.camera_pose = cameraPose({5.0, 0, 0}, 91.0);  // 90 deg in 0.1 s
  EXPECT_EQ(tracker.update(f).outcome, FrameOutcome::kCameraJumped);
}

TEST(Tracker, FindConfirmedTakesTheLatestOfALabel) {
  TrackingConfig config;
  config.targets = {{"buoy", "red", ShapeKind::kUnknown, 0.25, 0.3}};
  config.confirm_hits = 1;
  Tracker tracker(config);
  TrackingFrame f;
  Observation a = observation("red", {-1, 0, 2}), b = observation("red", {1, 0, 2});
  a.target = b.target = 0;
  f.observations = {a, b};
  tracker.update(f);
  f.stamp_s = 1.0;
  f.observations = {b};
  f.in_view = [](const Eigen::Vector3d&) { return false; };
  const std::uint32_t id_b = tracker.update(f).track_ids[0];
  ASSERT_NE(tracker.findConfirmed("buoy"), nullptr);
  EXPECT_EQ(tracker.findConfirmed("buoy")->id, id_b);
  EXPECT_EQ(tracker.findConfirmed("nothing"), nullptr);
  EXPECT_EQ(tracker.find(12345), nullptr);
}

TEST(Tracker, RefusesAnInvalidConfiguration) {
  TrackingConfig config;
  config.confirm_hits = 0;
  EXPECT_THROW(Tracker{config}, std::invalid_argument);
}

TEST(Tracker, ADetectionOverTwoTracksIsTheirMergedImage) {
  TrackingConfig config;
  config.confirm_hits = 2;
  config.max_misses = 2;
  Tracker tracker(config);
  TrackingFrame f;
  f.in_view = [](const Eigen::Vector3d&) { return true; };
  Observation near = observation("red", {-0.3, 0, 2.0}), far = observation("red", {0.5, 0, 3.5});
  near.size_m = far.size_m = Eigen::Vector3d::Constant(0.25);
  f.observations = {near, far};
  std::vector<std::uint32_t> ids;
  for (int k = 0; k < 3; ++k) {
    f.stamp_s = 0.1 * k;
    ids = tracker.update(f).track_ids;
  }
  Observation blob = near;  // the detector saw one red region at a depth between them
  blob.position_m = {0.0, 0, 2.6};
  blob.size_m = Eigen::Vector3d::Constant(0.9);
  f.observations = {blob};
  for (int k = 3; k < 8; ++k) {
    f.stamp_s = 0.1 * k;
    const TrackingUpdate u = tracker.update(f);
    EXPECT_EQ(u.track_ids[0], 0U) << "a merged image starts no track";
    EXPECT_TRUE(u.dropped.empty()) << "hidden in the merged image, not missed";
  }
  ASSERT_EQ(tracker.tracks().size(), 2U);
  EXPECT_TRUE(tracker.tracks()[0].hidden);
  f.observations = {near, far};
  f.stamp_s = 0.8;
  EXPECT_EQ(tracker.update(f).track_ids, ids);
}

// 0.05 m apart in the image at 2 m: the far one is partly hidden in the right camera, and its depth wrong. Of two of
// one colour that close, the near one's depth may be wrong too (the two may make one silhouette in the right camera).
TEST(Tracker, ADetectionNextToANearerOneIsNotUsedNorTheNearerOfTwoOfOneColour) {
  for (const std::string far_colour : {"green", "red"}) {
    Tracker tracker(TrackingConfig{});
    TrackingFrame f;
    Observation near = observation("red", {-0.05, 0, 2.0}), far = observation(far_colour, {0.2, 0, 3.5});
    near.size_m = far.size_m = Eigen::Vector3d::Constant(0.25);
    f.observations = {near, far};
    TrackingUpdate u = tracker.update(f);
    EXPECT_EQ(u.track_ids[0] != 0U, far_colour != "red") << far_colour;
    EXPECT_EQ(u.track_ids[1], 0U) << far_colour;
    f.observations[1].position_m.x() = 0.6;  // well apart
    f.stamp_s = 0.1;
    u = tracker.update(f);
    EXPECT_NE(u.track_ids[0], 0U) << far_colour;
    EXPECT_NE(u.track_ids[1], 0U) << far_colour;
  }
}
