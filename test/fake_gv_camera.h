// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Aravis' fake GigE Vision camera, run inside the test process (real GVCP/GVSP over UDP).
#include <arv.h>

#include <cstdint>
#include <cstdlib>
#include <stdexcept>
#include <string>

namespace underwater_stereo {
namespace test {

/// A wait of the fake-camera tests, in ms, times UWS_TEST_TIME_SCALE (a number >= 1, default 1). Under
/// emulation (scripts/check-arm64 sets 10) the in-process fake camera and the receiver deliver a few complete
/// frames a second instead of the configured rate.
inline int scaledMs(int ms) {
  const char* text = std::getenv("UWS_TEST_TIME_SCALE");
  if (!text || !*text) return ms;
  char* end = nullptr;
  const double scale = std::strtod(text, &end);
  if (*end != '\0' || !(scale >= 1 && scale <= 1000)) {
    throw std::invalid_argument(std::string("UWS_TEST_TIME_SCALE must be a number in 1..1000, not '") + text + "'");
  }
  return static_cast<int>(ms * scale);
}

class FakeGvCamera {
 public:
  FakeGvCamera(const char* address, const char* serial) : fake_(arv_gv_fake_camera_new(address, serial)) {}
  ~FakeGvCamera() { g_object_unref(fake_); }
  FakeGvCamera(const FakeGvCamera&) = delete;
  FakeGvCamera& operator=(const FakeGvCamera&) = delete;
  bool running() const { return arv_gv_fake_camera_is_running(fake_); }
  /// Share (0-1) of stream packets the camera drops.
  void loseGvspPackets(double ratio) { g_object_set(fake_, "gvsp-lost-ratio", ratio, nullptr); }
  /// The camera's own register, e.g. ARV_FAKE_CAMERA_REGISTER_EXPOSURE_TIME_US, as the host set it.
  std::uint32_t readRegister(std::uint32_t address) const {
    guint32 value = 0;
    arv_fake_camera_read_register(arv_gv_fake_camera_get_fake_camera(fake_), address, &value);
    return value;
  }

 private:
  ArvGvFakeCamera* fake_;
};

}  // namespace test
}  // namespace underwater_stereo
