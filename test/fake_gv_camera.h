// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Aravis' fake GigE Vision camera, run inside the test process (real GVCP/GVSP over UDP).
#include <arv.h>

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

 private:
  ArvGvFakeCamera* fake_;
};

}  // namespace test
}  // namespace underwater_stereo
