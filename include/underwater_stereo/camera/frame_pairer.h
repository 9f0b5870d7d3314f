// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Left and right frames -> stereo pairs, by capture time.

#include <cstdint>
#include <deque>
#include <optional>
#include <utility>

namespace underwater_stereo {

/// Pairs frames of two cameras whose capture times (host clock, from ClockMapper) lie within a maximum skew:
/// a few microseconds under a hardware trigger, about a millisecond with software triggers sent one after
/// the other, up to half a frame period in free run. A frame that can no longer find a partner (its partner
/// was lost, or came too late) is dropped and counted. Not thread-safe.
template <typename Frame>
class FramePairer {
 public:
  enum Side { kLeft = 0, kRight = 1 };

  /// `max_skew_ns`: largest capture-time difference within a pair; `max_waiting`: frames kept per side.
  explicit FramePairer(std::int64_t max_skew_ns, std::size_t max_waiting = 8)
      : max_skew_ns_(max_skew_ns), max_waiting_(max_waiting) {}

  /// Adds a frame captured at `time_ns`; returns the pair (left, right) it completes, if any.
  std::optional<std::pair<Frame, Frame>> add(Side side, std::int64_t time_ns, Frame frame) {
    auto& others = waiting_[1 - side];
    // The closest waiting frame of the other side within the skew.
    auto best = others.end();
    for (auto it = others.begin(); it != others.end(); ++it) {
      const std::int64_t d = std::abs(it->first - time_ns);
      if (d <= max_skew_ns_ && (best == others.end() || d < std::abs(best->first - time_ns))) best = it;
    }
    if (best != others.end()) {
      // Frames of the other side older than the partner will never pair: drop them.
      dropped_ += static_cast<std::uint64_t>(best - others.begin());
      Frame partner = std::move(best->second);
      others.erase(others.begin(), best + 1);
      dropOlderThan(waiting_[side], time_ns);
      ++pairs_;
      if (side == kLeft) return std::make_pair(std::move(frame), std::move(partner));
      return std::make_pair(std::move(partner), std::move(frame));
    }
    waiting_[side].emplace_back(time_ns, std::move(frame));
    // The other side's frames too old to pair with this or any later frame of this side.
    dropOlderThan(others, time_ns - max_skew_ns_);
    while (waiting_[side].size() > max_waiting_) {
      waiting_[side].pop_front();
      ++dropped_;
    }
    return std::nullopt;
  }

  /// Frames dropped without a partner, both sides.
  std::uint64_t dropped() const { return dropped_; }
  std::uint64_t pairs() const { return pairs_; }
  std::size_t waiting(Side side) const { return waiting_[side].size(); }
  /// A new tolerance (the frame rate changed); counters and waiting frames stay.
  void setMaxSkewNs(std::int64_t max_skew_ns) { max_skew_ns_ = max_skew_ns; }
  /// Drops everything waiting (a camera was reopened); not counted.
  void clear() {
    waiting_[0].clear();
    waiting_[1].clear();
  }

 private:
  void dropOlderThan(std::deque<std::pair<std::int64_t, Frame>>& q, std::int64_t time_ns) {
    while (!q.empty() && q.front().first < time_ns) {
      q.pop_front();
      ++dropped_;
    }
  }

  std::int64_t max_skew_ns_;
  std::size_t max_waiting_;
  std::deque<std::pair<std::int64_t, Frame>> waiting_[2];
  std::uint64_t dropped_ = 0, pairs_ = 0;
};

}  // namespace underwater_stereo
