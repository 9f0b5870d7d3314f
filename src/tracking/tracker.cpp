// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/tracking/tracker.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <tuple>

#include "underwater_stereo/config/yaml_fields.h"

namespace underwater_stereo {
namespace {

constexpr double kMinJumpDtS = 1e-3;  ///< [s] pose changes between pairs closer than this are rated over this
/// An unseen track moves on only when its velocity is this significant (chi-square, 3 dof, 95 %).
constexpr double kMovingChi2 = 7.81;

std::string number(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.3g", v);
  return buffer;
}

}  // namespace

std::string frameOutcomeName(FrameOutcome outcome) {
  switch (outcome) {
    case FrameOutcome::kTracked:
      return "tracked";
    case FrameOutcome::kInvalid:
      return "invalid frame ignored";
    case FrameOutcome::kStampBackwards:
      return "stamp went backwards, pair ignored";
    case FrameOutcome::kClockRestarted:
      return "clock restarted, tracks reset";
    case FrameOutcome::kCameraJumped:
      return "camera pose jumped, tracks reset";
  }
  return "unknown";
}

Tracker::Tracker(const TrackingConfig& config)
    : config_(config), last_stamp_s_(std::numeric_limits<double>::quiet_NaN()) {
  const auto problems = config_.validate();
  if (!problems.empty()) throw std::invalid_argument(joinProblems("invalid tracking configuration", problems));
}

void Tracker::reset() {
  tracks_.clear();
  last_stamp_s_ = std::numeric_limits<double>::quiet_NaN();
}

const Track* Tracker::find(std::uint32_t id) const {
  for (const Track& t : tracks_) {
    if (t.id == id) return &t;
  }
  return nullptr;
}

const Track* Tracker::findConfirmed(const std::string& label) const {
  const Track* best = nullptr;
  for (const Track& t : tracks_) {
    if (t.status != TrackStatus::kConfirmed || t.label != label) continue;
    if (!best || std::tie(t.last_seen_s, t.observations) > std::tie(best->last_seen_s, best->observations)) best = &t;
  }
  return best;
}

Eigen::Matrix3d Tracker::measurementCovariance(const Eigen::Vector3d& p, bool cut_by_border) const {
  const double range = p.norm();
  const Eigen::Vector3d ray = range > 0 ? Eigen::Vector3d(p / range) : Eigen::Vector3d::UnitZ();
  const double scale = cut_by_border ? config_.cut_by_border_sigma_scale : 1.0;
  const double along = scale * (config_.min_sigma_m + config_.range_sigma_fraction * range);
  const double across = scale * (config_.min_sigma_m + config_.lateral_sigma_fraction * range);
  return Eigen::Matrix3d::Identity() * (across * across) + ray * ray.transpose() * (along * along - across * across);
}

bool Tracker::compatible(const Track& t, const Observation& o) const {
  if (t.colour != o.colour || t.target != o.target) return false;
  return !config_.match_shape || shapesAgree(t.shape, o.shape);
}

FrameOutcome Tracker::checkFrame(const TrackingFrame& frame, TrackingUpdate& out) {
  if (!std::isfinite(frame.stamp_s) || !frame.camera_pose.matrix().allFinite()) {
    out.problems.push_back("stamp or camera pose is not finite");
    return FrameOutcome::kInvalid;
  }
  if (std::isnan(last_stamp_s_)) return FrameOutcome::kTracked;
  const double dt = frame.stamp_s - last_stamp_s_;
  if (dt < 0) {
    out.problems.push_back("stamp " + number(-dt) + " s earlier than the previous pair's");
    return -dt > config_.max_backwards_s ? FrameOutcome::kClockRestarted : FrameOutcome::kStampBackwards;
  }
  const double rated_dt = std::max(dt, kMinJumpDtS);
  const double speed = (frame.camera_pose.translation() - last_pose_.translation()).norm() / rated_dt;
  const double turn_dps =
      Eigen::AngleAxisd(last_pose_.linear().transpose() * frame.camera_pose.linear()).angle() * 180.0 / M_PI / rated_dt;
  if (speed > config_.max_camera_speed_mps || turn_dps > config_.max_camera_turn_rate_dps) {
    out.problems.push_back("camera moved at " + number(speed) + " m/s, turned at " + number(turn_dps) +
                           " deg/s since the previous pair");
    return FrameOutcome::kCameraJumped;
  }
  return FrameOutcome::kTracked;
}

TrackingUpdate Tracker::update(const TrackingFrame& frame) {
  TrackingUpdate out;
  out.track_ids.assign(frame.observations.size(), 0);
  out.outcome = checkFrame(frame, out);
  if (out.outcome == FrameOutcome::kInvalid || out.outcome == FrameOutcome::kStampBackwards) return out;
  if (out.outcome != FrameOutcome::kTracked) {
    for (const Track& t : tracks_) out.dropped.push_back(t.id);
    tracks_.clear();
  }
  const double dt = std::isnan(last_stamp_s_) ? 0.0 : std::max(0.0, frame.stamp_s - last_stamp_s_);
  // A track out of view whose velocity is not significantly non-zero stays where it is: a moored buoy's velocity
  // noise must not carry it away while the camera looks elsewhere.
  for (Track& t : tracks_) {
    if (!t.in_view && t.filter.velocitySignificance() < kMovingChi2) {
      t.filter.hold(dt, config_.acceleration_sigma_mps2);
    } else {
      t.filter.predict(dt, config_.acceleration_sigma_mps2);
    }
  }
  last_stamp_s_ = frame.stamp_s;
  last_pose_ = frame.camera_pose;

  // Observations in the tracking frame.
  const std::size_t n = frame.observations.size();
  std::vector<Eigen::Vector3d> z(n);
  std::vector<Eigen::Matrix3d> r(n);
  std::vector<bool> valid(n, false);
  const Eigen::Matrix3d rotation = frame.camera_pose.linear();
  for (std::size_t i = 0; i < n; ++i) {
    const Observation& o = frame.observations[i];
    if (!o.position_m.allFinite() || !o.size_m.allFinite() || o.position_m.norm() <= 0.0) {
      out.problems.push_back("observation " + std::to_string(i) + " (" + o.colour +
                             "): position or size not finite (or zero), not tracked");
      continue;
    }
    valid[i] = true;
    z[i] = frame.camera_pose * o.position_m;
    r[i] = rotation * measurementCovariance(o.position_m, o.cut_by_border) * rotation.transpose();
  }

  // Where the tracks should be in the image. Detections whose depth cannot be trusted update no track and start
  // none (the tracks under them count as hidden): one whose disc holds the centres of two or more confirmed
  // tracks of its colour (the detector may join touching objects of one colour where stereo cannot tell them
  // apart), one next to a nearer detection (within occlusion_margin_m: in one of the two cameras the nearer object
  // hides part of it), and the nearer of two of one colour that close (in the right camera the two may make one
  // silhouette, which puts the nearer one a few per cent near or far: config/scenes/crossing.yaml's near buoy
  // 1.90-2.11 m for 2.0).
  const Eigen::Isometry3d world_to_camera = frame.camera_pose.inverse();
  std::vector<Eigen::Vector3d> in_camera(tracks_.size());
  std::vector<bool> visible(tracks_.size());
  for (std::size_t k = 0; k < tracks_.size(); ++k) {
    in_camera[k] = world_to_camera * tracks_[k].filter.position();
    visible[k] = !frame.in_view || frame.in_view(in_camera[k]);
  }
  const auto angle = [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0));
  };
  /// [m] at the detection's range, how far apart in the image detection i and a point at `p` of size `size` are.
  const auto gap = [&](std::size_t i, const Eigen::Vector3d& p, double size) {
    const Observation& o = frame.observations[i];
    const double range = o.position_m.norm();
    return angle(o.position_m, p) * range - (o.size_m.maxCoeff() + size * range / p.norm()) / 2;
  };
  const auto covers = [&](std::size_t i, std::size_t k) { return gap(i, in_camera[k], tracks_[k].size_m.maxCoeff()) < 0; };
  std::vector<bool> usable = valid;
  for (std::size_t i = 0; i < n; ++i) {
    if (!valid[i]) continue;
    const Observation& o = frame.observations[i];
    int under = 0;
    for (std::size_t k = 0; k < tracks_.size(); ++k) {
      under += tracks_[k].status == TrackStatus::kConfirmed && visible[k] && tracks_[k].colour == o.colour &&
               angle(o.position_m, in_camera[k]) * o.position_m.norm() < o.size_m.maxCoeff() / 2;
    }
    if (under >= 2) usable[i] = false;
    // Too close to a nearer detection j: not used, nor j when it is of i's colour.
    for (std::size_t j = 0; j < n; ++j) {
      const Observation& front = frame.observations[j];
      if (j != i && valid[j] && front.position_m.norm() < o.position_m.norm() &&
          gap(j, o.position_m, o.size_m.maxCoeff()) < config_.occlusion_margin_m) {
        usable[i] = false;
        if (front.colour == o.colour) usable[j] = false;
      }
    }
  }

  // Gated candidate pairs, then greedy: confirmed tracks first, then by distance.
  struct Candidate {
    bool tentative;
    double distance2;
    std::size_t observation, track;
  };
  std::vector<Candidate> candidates;
  for (std::size_t i = 0; i < n; ++i) {
    if (!usable[i]) continue;
    for (std::size_t k = 0; k < tracks_.size(); ++k) {
      if (!compatible(tracks_[k], frame.observations[i])) continue;
      const double d2 = tracks_[k].filter.mahalanobis2(z[i], r[i]);
      if (d2 <= config_.gate_chi2) {
        candidates.push_back({tracks_[k].status == TrackStatus::kTentative, d2, i, k});
      }
    }
  }
  std::sort(candidates.begin(), candidates.end(), [](const Candidate& a, const Candidate& b) {
    return std::tie(a.tentative, a.distance2, a.observation, a.track) <
           std::tie(b.tentative, b.distance2, b.observation, b.track);
  });
  std::vector<bool> track_taken(tracks_.size(), false), observation_taken(n, false);
  for (const Candidate& c : candidates) {
    if (track_taken[c.track] || observation_taken[c.observation]) continue;
    track_taken[c.track] = observation_taken[c.observation] = true;
    Track& t = tracks_[c.track];
    const Observation& o = frame.observations[c.observation];
    t.filter.update(z[c.observation], r[c.observation]);
    ++t.observations;
    t.size_m += (o.size_m - t.size_m) / t.observations;
    if (o.shape != ShapeKind::kUnknown) t.shape = o.shape;
    t.misses = 0;
    t.in_view = true;
    t.hidden = false;
    t.last_seen_s = frame.stamp_s;
    if (t.status == TrackStatus::kTentative && static_cast<int>(t.observations) >= config_.confirm_hits) {
      t.status = TrackStatus::kConfirmed;
    }
    out.track_ids[c.observation] = t.id;
  }

  // Tracks not found: missed when they should have been seen (in view, and their image not within a detection's:
  // occluded, or merged with it by the detector; tentative ones always); dropped after too many.
  for (std::size_t k = 0; k < tracks_.size(); ++k) {
    Track& t = tracks_[k];
    if (track_taken[k]) continue;
    t.in_view = visible[k];
    t.hidden = false;
    for (std::size_t i = 0; i < n && t.in_view; ++i) t.hidden = t.hidden || (valid[i] && covers(i, k));
  }
  std::vector<Track> kept;
  kept.reserve(tracks_.size() + n);
  for (std::size_t k = 0; k < tracks_.size(); ++k) {
    Track& t = tracks_[k];
    if (!track_taken[k]) {
      const bool tentative = t.status == TrackStatus::kTentative;
      if ((t.in_view && !t.hidden) || tentative) ++t.misses;
      if (t.misses >= (tentative ? config_.tentative_max_misses : config_.max_misses)) {
        out.dropped.push_back(t.id);
        continue;
      }
    }
    kept.push_back(std::move(t));
  }
  tracks_ = std::move(kept);

  // Observations no track took start tentative tracks (unless cut by the image's border).
  for (std::size_t i = 0; i < n; ++i) {
    const Observation& o = frame.observations[i];
    if (!usable[i] || observation_taken[i] || o.cut_by_border) continue;
    Track t;
    t.id = next_id_++;
    t.colour = o.colour;
    t.shape = o.shape;
    t.target = o.target;
    t.label = o.target >= 0 && o.target < static_cast<int>(config_.targets.size())
                  ? config_.targets[static_cast<std::size_t>(o.target)].name
                  : std::string();
    t.size_m = o.size_m;
    t.filter = ConstantVelocityFilter(z[i], r[i], config_.initial_speed_sigma_mps);
    t.observations = 1;
    t.in_view = true;
    t.first_seen_s = t.last_seen_s = frame.stamp_s;
    if (config_.confirm_hits <= 1) t.status = TrackStatus::kConfirmed;
    out.track_ids[i] = t.id;
    tracks_.push_back(std::move(t));
  }
  return out;
}

}  // namespace underwater_stereo
