// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Aravis' fake GigE Vision camera, run inside the test process (real GVCP/GVSP over UDP).
#include <arv.h>

#include <cstdint>

namespace underwater_stereo {
namespace test {

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
