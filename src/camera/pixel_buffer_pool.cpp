// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/camera/pixel_buffer_pool.h"

#include <deque>
#include <mutex>
#include <stdexcept>

namespace underwater_stereo {

struct PixelBufferPool::State {
  std::mutex mutex;
  std::size_t max_free = 0;
  bool open = true;  ///< false once the pool is destroyed: buffers released after that are freed
  std::deque<std::unique_ptr<std::vector<std::uint8_t>>> free;  ///< released longest ago first
  std::uint64_t allocations = 0;

  void release(std::vector<std::uint8_t>* raw, std::size_t bytes) {
    std::unique_ptr<std::vector<std::uint8_t>> buffer(raw);
    std::unique_ptr<std::vector<std::uint8_t>> evicted;  // freed outside the lock
    std::lock_guard<std::mutex> lock(mutex);
    if (!open || buffer->size() != bytes) return;
    free.push_back(std::move(buffer));
    if (free.size() > max_free) {
      evicted = std::move(free.front());
      free.pop_front();
    }
  }
};

PixelBufferPool::PixelBufferPool(std::size_t max_free) : state_(std::make_shared<State>()) {
  if (max_free == 0) throw std::invalid_argument("PixelBufferPool: max_free must be at least 1");
  state_->max_free = max_free;
}

PixelBufferPool::~PixelBufferPool() {
  std::deque<std::unique_ptr<std::vector<std::uint8_t>>> free;
  std::lock_guard<std::mutex> lock(state_->mutex);
  state_->open = false;
  free.swap(state_->free);
}

PixelBufferPool& PixelBufferPool::frames() {
  static PixelBufferPool pool(48);
  return pool;
}

PixelBufferPool::Buffer PixelBufferPool::acquire(std::size_t bytes) {
  std::unique_ptr<std::vector<std::uint8_t>> buffer;
  {
    std::lock_guard<std::mutex> lock(state_->mutex);
    for (auto it = state_->free.rbegin(); it != state_->free.rend(); ++it) {  // the most recently released first
      if ((*it)->size() == bytes) {
        buffer = std::move(*it);
        state_->free.erase(std::next(it).base());
        break;
      }
    }
    if (!buffer) ++state_->allocations;
  }
  if (!buffer) buffer = std::make_unique<std::vector<std::uint8_t>>(bytes);
  std::weak_ptr<State> state = state_;
  return Buffer(buffer.release(), [state, bytes](std::vector<std::uint8_t>* raw) {
    if (const auto s = state.lock()) {
      s->release(raw, bytes);
    } else {
      delete raw;
    }
  });
}

std::size_t PixelBufferPool::freeBuffers() const {
  std::lock_guard<std::mutex> lock(state_->mutex);
  return state_->free.size();
}

std::uint64_t PixelBufferPool::allocations() const {
  std::lock_guard<std::mutex> lock(state_->mutex);
  return state_->allocations;
}

}  // namespace underwater_stereo
