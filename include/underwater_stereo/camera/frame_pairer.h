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

  /// A frame dropped without a partner: its side, its capture time and how far the nearest frame of the other
  /// side seen when it was dropped lay from it (other - this; 0 with `other_seen` false when none was there).
  struct Miss {
    Side side = kLeft;
    std::int64_t time_ns = 0;
    std::int64_t other_minus_this_ns = 0;
    bool other_seen = false;
  };

  /// Adds a frame captured at `time_ns`; returns the pair (left, right) it completes, if any.
  std::optional<std::pair<Frame, Frame>> add(Side side, std::int64_t time_ns, Frame frame) {
    auto& others = waiting_[1 - side];
    const Side other_side = side == kLeft ? kRight : kLeft;
    // The closest waiting frame of the other side within the skew.
    auto best = others.end();
    for (auto it = others.begin(); it != others.end(); ++it) {
      const std::int64_t d = std::abs(it->first - time_ns);
      if (d <= max_skew_ns_ && (best == others.end() || d < std::abs(best->first - time_ns))) best = it;
    }
    if (best != others.end()) {
      // Frames of the other side older than the partner will never pair: drop them.
      // (A deque's pop_front leaves iterators to the other elements valid.)
      while (others.begin() != best) drop(others, other_side, time_ns);
      const std::int64_t partner_ns = best->first;
      Frame partner = std::move(best->second);
      others.pop_front();
      dropOlderThan(waiting_[side], side, time_ns, partner_ns);
      ++pairs_;
      if (side == kLeft) return std::make_pair(std::move(frame), std::move(partner));
      return std::make_pair(std::move(partner), std::move(frame));
    }
    waiting_[side].emplace_back(time_ns, std::move(frame));
    // The other side's frames too old to pair with this or any later frame of this side.
    dropOlderThan(others, other_side, time_ns - max_skew_ns_, time_ns);
    while (waiting_[side].size() > max_waiting_) {
      if (others.empty()) {
        record(side, waiting_[side].front().first, std::nullopt);
        waiting_[side].pop_front();
      } else {
        drop(waiting_[side], side, others.back().first);
      }
    }
    return std::nullopt;
  }

  std::uint64_t dropped() const { return dropped_; }
  std::uint64_t pairs() const { return pairs_; }
  /// The last frame dropped without a partner, if any.
  const std::optional<Miss>& lastMiss() const { return last_miss_; }
  std::size_t waiting(Side side) const { return waiting_[side].size(); }
  void setMaxSkewNs(std::int64_t max_skew_ns) { max_skew_ns_ = max_skew_ns; }
  std::int64_t maxSkewNs() const { return max_skew_ns_; }
  void clear() {
    waiting_[0].clear();
    waiting_[1].clear();
  }

 private:
  using Queue = std::deque<std::pair<std::int64_t, Frame>>;

  void record(Side side, std::int64_t time_ns, std::optional<std::int64_t> other_ns) {
    ++dropped_;
    last_miss_ = Miss{side, time_ns, other_ns ? *other_ns - time_ns : 0, other_ns.has_value()};
  }
  /// Drops the oldest frame of `q` (of `side`); `other_ns` is the other side's frame that made it hopeless.
  void drop(Queue& q, Side side, std::int64_t other_ns) {
    record(side, q.front().first, other_ns);
    q.pop_front();
  }
  void dropOlderThan(Queue& q, Side side, std::int64_t time_ns, std::int64_t other_ns) {
    while (!q.empty() && q.front().first < time_ns) drop(q, side, other_ns);
  }

  std::int64_t max_skew_ns_;
  std::size_t max_waiting_;
  Queue waiting_[2];
  std::uint64_t dropped_ = 0, pairs_ = 0;
  std::optional<Miss> last_miss_;
};

}  // namespace underwater_stereo
