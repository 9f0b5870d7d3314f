// SPDX-License-Identifier: BSD-3-Clause
// bench_fake_cameras: two of Aravis' fake GigE Vision cameras (real GVCP/GVSP over UDP) that stream a rendered
// stereo pair as BayerRG8 instead of the fake's ramp, for scripts/bench's whole-pipeline figures: the camera
// nodelet and the detector get real packets and a scene with objects. Runs until SIGINT/SIGTERM.
// (Like test/fake_gv_camera.h, a stand-in for camera hardware: it drives Aravis' fake directly.)
#include <arpa/inet.h>
#include <arv.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <array>
#include <atomic>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <iostream>
#include <string>

#include "underwater_stereo/common/whole_file.h"
#include "tool_helpers.h"

namespace {

std::atomic<bool> stop{false};

/// Aravis' fake serves a trigger only at the next multiple of its period, 1 / trigger_frequency truncated to whole
/// microseconds, of the wall clock since the epoch (arvfakecamera.c, g_get_real_time; 25 Hz by default, and not
/// settable over GigE): two triggers that arrive 1 ms apart around such a tick come out a period apart, an
/// unpaired pair (a real camera exposes within microseconds of its trigger). The nodelet sends its software
/// triggers half a period after the multiples of its own period, whole microseconds of the same clock
/// (TriggerSchedule). So the fakes' period is set to exactly the nodelet's, llround(1e6 / HZ) us: the triggers of
/// a pair then arrive half a period from the fakes' ticks for as long as the run lasts. (With the fakes at 25 Hz,
/// or a period a fraction of a microsecond off, the phase drifts through the ticks and pairs split.)
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
  std::int64_t period_us = 0;              ///< the fakes' trigger grid
  std::atomic<long> frames{0}, off_tick{0};  ///< frames served; those triggered, more than 1 ms off their tick
};

/// The fake's fill pattern: the mosaic, cropped to (or placed in the corner of) the region the host set (read
/// from the fake's registers: the buffer's own size is set after the pattern ran).
void fillWithImage(ArvBuffer* buffer, void* data, guint32, guint32, ArvPixelFormat) {
  Pattern& p = *static_cast<Pattern*>(data);
  const std::int64_t phase = g_get_real_time() % p.period_us;
  ++p.frames;
  if (arv_fake_camera_is_in_software_trigger_mode(p.camera) && phase > 1000 && phase < p.period_us - 1000) ++p.off_tick;
  guint32 width = 0, height = 0;
  arv_fake_camera_read_register(p.camera, ARV_FAKE_CAMERA_REGISTER_WIDTH, &width);
  arv_fake_camera_read_register(p.camera, ARV_FAKE_CAMERA_REGISTER_HEIGHT, &height);
  // The fake checked the buffer holds width x height before calling (get_data's size is what was received).
  auto* pixels = static_cast<std::uint8_t*>(const_cast<void*>(arv_buffer_get_data(buffer, nullptr)));
  if (!pixels || width == 0 || height == 0) return;
  const int w = std::min(static_cast<int>(width), p.mosaic.cols), h = std::min(static_cast<int>(height), p.mosaic.rows);
  for (int y = 0; y < h; ++y) std::memcpy(pixels + static_cast<size_t>(y) * width, p.mosaic.ptr(y), w);
}

/// Aravis 0.8's fake sometimes oversleeps a tick of its grid: it polls its GVCP socket until the tick with a
/// timeout of (tick - now) computed unsigned, and when `now` passes the tick between its loop's check and that
/// computation, the timeout wraps round to the 100 ms cap. The trigger waiting then is served only when the
/// next GVCP packet wakes it (the nodelet's next trigger, half a period later: a frame off its tick and one
/// trigger lost, ~1 per 1000 frames). A real camera has no such sleep. So each fake gets a read of one of its
/// registers 1.5 ms after every tick: a fake that overslept wakes then and serves its frame 1.5 ms late, well
/// within the nodelet's pairing tolerance (5 ms at 15 Hz). Each frame served more than 1 ms from its tick is
/// counted and reported at exit.
constexpr std::int64_t kNudgeAfterTickUs = 1500;

/// A GVCP READREG command for the device's version register (bootstrap address 0), 12 bytes big-endian.
std::array<std::uint8_t, 12> readRegisterPacket(std::uint16_t id) {
  return {0x42, 0x01, 0x00, 0x80, 0x00, 0x04, static_cast<std::uint8_t>(id >> 8), static_cast<std::uint8_t>(id & 0xff),
          0, 0, 0, 0};
}

/// A UDP socket connected to the fake's GVCP port (3956), non-blocking; -1 on failure.
int gvcpSocket(const char* address) {
  const int fd = socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK, 0);
  if (fd < 0) return -1;
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_port = htons(3956);
  if (inet_pton(AF_INET, address, &to.sin_addr) != 1 || connect(fd, reinterpret_cast<sockaddr*>(&to), sizeof to) != 0) {
    close(fd);
    return -1;
  }
  return fd;
}

/// Until stopped: a register read to each fake kNudgeAfterTickUs after every tick of the wall clock's grid of
/// `period_us` (the acknowledgements are read and dropped).
void nudge(const char* const address[2], std::int64_t period_us) {
  int fd[2] = {gvcpSocket(address[0]), gvcpSocket(address[1])};
  if (fd[0] < 0 || fd[1] < 0) {
    std::cerr << "bench_fake_cameras: no GVCP socket to nudge the fakes; an oversleeping fake loses its frame\n";
  }
  std::uint16_t id = 1;
  std::uint8_t sink[64];
  while (!stop) {
    const std::int64_t now = g_get_real_time();
    const std::int64_t at = (now / period_us + 1) * period_us + kNudgeAfterTickUs;
    timespec wake{static_cast<time_t>(at / 1000000), static_cast<long>(at % 1000000) * 1000};
    clock_nanosleep(CLOCK_REALTIME, TIMER_ABSTIME, &wake, nullptr);
    for (int f : fd) {
      if (f < 0) continue;
      const auto packet = readRegisterPacket(id);
      send(f, packet.data(), packet.size(), 0);
      while (recv(f, sink, sizeof sink, 0) > 0) {
      }
    }
    id = static_cast<std::uint16_t>(id % 65535 + 1);
  }
  for (int f : fd) {
    if (f >= 0) close(f);
  }
}

int usage() {
  std::cerr << "usage: bench_fake_cameras [--trigger-hz HZ] LEFT.png RIGHT.png [LEFT_ADDRESS RIGHT_ADDRESS]\n"
               "  two fake GigE cameras (default 127.0.0.1 and 127.0.0.2, which must be on lo) streaming the two\n"
               "  images as BayerRG8 (set the nodelet's ROI to the images' size; the fake's sensor is 2048x2048);\n"
               "  in software trigger mode they serve triggers on ticks of the period llround(1e6 / HZ) us of the wall clock\n"
               "  (HZ default 15: the nodelet's rate)\n";
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  double trigger_hz = kDefaultTriggerHz;
  if (argc > 2 && std::string(argv[1]) == "--trigger-hz") {
    try {
      trigger_hz = underwater_stereo::tools::numberIn(argv[2], 1, 1000, "--trigger-hz");
    } catch (const std::invalid_argument& e) {
      std::cerr << "bench_fake_cameras: " << e.what() << "\n";
      return 2;
    }
    argc -= 2;
    argv += 2;
  }
  if (argc != 3 && argc != 5) return usage();
  Pattern pattern[2];
  for (int s = 0; s < 2; ++s) {
    try {
      underwater_stereo::checkReadable(argv[1 + s]);  // imread says nothing of why
    } catch (const underwater_stereo::UnreadableFile& e) {
      std::cerr << "bench_fake_cameras: " << e.what() << "\n";
      return 1;
    }
    const cv::Mat bgr = cv::imread(argv[1 + s], cv::IMREAD_COLOR);
    if (bgr.empty()) {
      std::cerr << "bench_fake_cameras: " << argv[1 + s] << ": not an image OpenCV decodes\n";
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
    // The fake truncates 1e6 / frequency to whole microseconds: aim half a microsecond above the period wanted.
    pattern[s].period_us = std::llround(1e6 / trigger_hz);
    arv_fake_camera_set_trigger_frequency(pattern[s].camera, 1e6 / (pattern[s].period_us + 0.5));
    arv_fake_camera_set_fill_pattern(pattern[s].camera, fillWithImage, &pattern[s]);
  }
  std::signal(SIGINT, [](int) { stop = true; });
  std::signal(SIGTERM, [](int) { stop = true; });
  std::cout << "bench_fake_cameras: " << pattern[0].mosaic.cols << "x" << pattern[0].mosaic.rows << " BayerRG8 on " << address[0]
            << " and " << address[1] << std::endl;
  nudge(address, pattern[0].period_us);
  for (ArvGvFakeCamera* f : fake) g_object_unref(f);
  std::cout << "bench_fake_cameras: frames served " << pattern[0].frames << " / " << pattern[1].frames
            << ", triggered ones more than 1 ms from their tick (overslept, woken by the nudge) "
            << pattern[0].off_tick << " / " << pattern[1].off_tick << std::endl;
  return 0;
}
