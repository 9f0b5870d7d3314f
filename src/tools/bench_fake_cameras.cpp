// SPDX-License-Identifier: BSD-3-Clause
// bench_fake_cameras: two of Aravis' fake GigE Vision cameras (real GVCP/GVSP over UDP) that stream a rendered
// stereo pair as BayerRG8 instead of the fake's ramp, for scripts/bench's whole-pipeline figures: the camera
// nodelet and the detector get real packets and a scene with objects. Runs until SIGINT/SIGTERM.
// (Like test/fake_gv_camera.h, a stand-in for camera hardware: it drives Aravis' fake directly.)
#include <arv.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <string>
#include <thread>

namespace {

std::atomic<bool> stop{false};

/// Aravis' fake serves a trigger only at the next tick of its own grid of 1 / trigger_frequency on the monotonic
/// clock (25 Hz by default: two triggers that arrive 1 ms apart around a tick come out 40 ms apart, an unpaired
/// pair; a real camera exposes within microseconds of its trigger). The nodelet sends its software triggers half
/// a period after the multiples of 1 / rate on the same clock: with the fakes' grid at that rate (--trigger-hz,
/// default 15) both triggers of a pair arrive mid-period and are served at the fakes' next tick, unless one is
/// sent half a period late. (A 60 Hz grid lay 0.7 ms after the nodelet's ticks and split 4 % of pairs; a 1 kHz
/// one cost the fakes a whole core; with the nodelet's ticks on the grid's own multiples, a fake that woke late
/// served a trigger a period early: 197 of 3190 frames unpaired at load 7.)
constexpr double kDefaultTriggerHz = 15.0;

/// BGR -> Bayer RGGB mosaic (R at even row/even column, B at odd/odd).
cv::Mat toBayerRggb(const cv::Mat& bgr) {
  cv::Mat out(bgr.size(), CV_8UC1);
  for (int y = 0; y < bgr.rows; ++y) {
    const cv::Vec3b* in = bgr.ptr<cv::Vec3b>(y);
    std::uint8_t* o = out.ptr<std::uint8_t>(y);
    for (int x = 0; x < bgr.cols; ++x) o[x] = in[x][(y % 2 == 0) ? (x % 2 == 0 ? 2 : 1) : (x % 2 == 0 ? 1 : 0)];
  }
  return out;
}

struct Pattern {
  cv::Mat mosaic;
  ArvFakeCamera* camera = nullptr;
};

/// The fake's fill pattern: the mosaic, cropped to (or placed in the corner of) the region the host set (read
/// from the fake's registers: the buffer's own size is set after the pattern ran).
void fillWithImage(ArvBuffer* buffer, void* data, guint32, guint32, ArvPixelFormat) {
  const Pattern& p = *static_cast<const Pattern*>(data);
  guint32 width = 0, height = 0;
  arv_fake_camera_read_register(p.camera, ARV_FAKE_CAMERA_REGISTER_WIDTH, &width);
  arv_fake_camera_read_register(p.camera, ARV_FAKE_CAMERA_REGISTER_HEIGHT, &height);
  // The fake checked the buffer holds width x height before calling (get_data's size is what was received).
  auto* pixels = static_cast<std::uint8_t*>(const_cast<void*>(arv_buffer_get_data(buffer, nullptr)));
  if (!pixels || width == 0 || height == 0) return;
  const int w = std::min(static_cast<int>(width), p.mosaic.cols), h = std::min(static_cast<int>(height), p.mosaic.rows);
  for (int y = 0; y < h; ++y) std::memcpy(pixels + static_cast<size_t>(y) * width, p.mosaic.ptr(y), w);
}

int usage() {
  std::cerr << "usage: bench_fake_cameras [--trigger-hz HZ] LEFT.png RIGHT.png [LEFT_ADDRESS RIGHT_ADDRESS]\n"
               "  two fake GigE cameras (default 127.0.0.1 and 127.0.0.2, which must be on lo) streaming the two\n"
               "  images as BayerRG8 (set the nodelet's ROI to the images' size; the fake's sensor is 2048x2048);\n"
               "  in software trigger mode they serve triggers on ticks of HZ (default 15: the nodelet's rate)\n";
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  double trigger_hz = kDefaultTriggerHz;
  if (argc > 2 && std::string(argv[1]) == "--trigger-hz") {
    char* end = nullptr;
    trigger_hz = std::strtod(argv[2], &end);
    if (end == argv[2] || *end != '\0' || !(trigger_hz >= 1 && trigger_hz <= 1000)) {
      std::cerr << "bench_fake_cameras: --trigger-hz must be a number in [1, 1000], got '" << argv[2] << "'\n";
      return 2;
    }
    argc -= 2;
    argv += 2;
  }
  if (argc != 3 && argc != 5) return usage();
  Pattern pattern[2];
  for (int s = 0; s < 2; ++s) {
    const cv::Mat bgr = cv::imread(argv[1 + s], cv::IMREAD_COLOR);
    if (bgr.empty()) {
      std::cerr << "bench_fake_cameras: cannot read the image '" << argv[1 + s] << "'\n";
      return 1;
    }
    pattern[s].mosaic = toBayerRggb(bgr);
  }
  const char* address[2] = {argc == 5 ? argv[3] : "127.0.0.1", argc == 5 ? argv[4] : "127.0.0.2"};
  ArvGvFakeCamera* fake[2] = {nullptr, nullptr};
  for (int s = 0; s < 2; ++s) {
    fake[s] = arv_gv_fake_camera_new(address[s], s == 0 ? "BENCH-LEFT" : "BENCH-RIGHT");
    if (!fake[s] || !arv_gv_fake_camera_is_running(fake[s])) {
      std::cerr << "bench_fake_cameras: cannot start a fake camera on " << address[s] << "\n";
      return 1;
    }
    pattern[s].camera = arv_gv_fake_camera_get_fake_camera(fake[s]);
    arv_fake_camera_set_fill_pattern(pattern[s].camera, fillWithImage, &pattern[s]);
    arv_fake_camera_set_trigger_frequency(pattern[s].camera, trigger_hz);
  }
  std::signal(SIGINT, [](int) { stop = true; });
  std::signal(SIGTERM, [](int) { stop = true; });
  std::cout << "bench_fake_cameras: " << pattern[0].mosaic.cols << "x" << pattern[0].mosaic.rows << " BayerRG8 on " << address[0]
            << " and " << address[1] << std::endl;
  while (!stop) std::this_thread::sleep_for(std::chrono::milliseconds(100));
  for (ArvGvFakeCamera* f : fake) g_object_unref(f);
  return 0;
}
