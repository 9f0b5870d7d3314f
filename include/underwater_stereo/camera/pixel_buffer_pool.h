// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Pixel buffers that are recycled instead of freed: a camera frame's one copy (and a GigE camera's stream
/// buffers) come from a pool and go back to it when the last holder lets go. ROS-free.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

namespace underwater_stereo {

/// A bounded pool of pixel buffers. acquire() hands out a buffer of the asked size; when its last owner
/// releases it, it goes back to the pool (if the pool still exists and is not full), keeping its bytes, and a
/// later acquire() of the same size takes it again instead of allocating. Thread-safe.
///
/// Why: an image-sized buffer (2.3 MB for 1920x1200 Bayer) is below the 32 MB mmap threshold the launch files
/// set, so glibc takes it from the allocating thread's heap arena and, freed, keeps its pages there. Allocated
/// and freed per frame by threads that come and go with each camera load, such buffers left each arena at its
/// own high-water mark and moved the manager's RSS at every camera restart; recycled, the same few buffers
/// carry every frame of every load.
class PixelBufferPool {
 public:
  /// A buffer of pixels; its deleter returns it to the pool it came from.
  using Buffer = std::shared_ptr<std::vector<std::uint8_t>>;

  /// @param max_free the most released buffers kept for reuse (all sizes together); a buffer released into a
  ///   full pool replaces the one released longest ago, which is freed.
  /// @throw std::invalid_argument when max_free is 0.
  explicit PixelBufferPool(std::size_t max_free);
  ~PixelBufferPool();
  PixelBufferPool(const PixelBufferPool&) = delete;
  PixelBufferPool& operator=(const PixelBufferPool&) = delete;

  /// The process's pool of camera frames: it outlives every camera source, so a camera unloaded and loaded
  /// again streams into the buffers of the load before. Keeps at most 48 released buffers (the stream buffers
  /// of two cameras and the frames in flight).
  static PixelBufferPool& frames();

  /// A buffer of exactly `bytes` bytes: a released one of that size if the pool holds one (its contents are the
  /// old frame's, to be overwritten), else a new one. It is never handed out again while anyone holds it.
  /// A buffer that comes back with another size (its vector resized or moved from) is freed, not kept.
  Buffer acquire(std::size_t bytes);

  /// Released buffers held for reuse.
  std::size_t freeBuffers() const;
  /// Buffers allocated so far (acquire() calls that found no released buffer of their size).
  std::uint64_t allocations() const;

 private:
  struct State;
  std::shared_ptr<State> state_;  ///< shared with the buffers' deleters, which may outlive the pool
};

}  // namespace underwater_stereo
