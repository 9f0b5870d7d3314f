// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/detection/image_file.h"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <string>
#include <stdexcept>
#include <vector>

extern "C" {
#include <jpeglib.h>
}

#include "underwater_stereo/common/whole_file.h"
#include "underwater_stereo/detection/image_checks.h"

namespace underwater_stereo {
namespace {

/// libjpeg's error manager, made strict: an error jumps back, a warning (corrupt or missing data, which
/// libjpeg would fill with grey) is kept and fails the check.
struct StrictJpegErrors {
  jpeg_error_mgr mgr;
  std::jmp_buf jump;
  char message[JMSG_LENGTH_MAX];
  int width, height;
  std::vector<JSAMPLE> row;  ///< one decoded row (lives outside the function that may jump)
};

void onJpegError(j_common_ptr cinfo) {
  auto* e = reinterpret_cast<StrictJpegErrors*>(cinfo->err);
  (*cinfo->err->format_message)(cinfo, e->message);
  std::longjmp(e->jump, 1);
}

void onJpegMessage(j_common_ptr cinfo) {
  auto* e = reinterpret_cast<StrictJpegErrors*>(cinfo->err);
  if (e->message[0] == '\0') (*cinfo->err->format_message)(cinfo, e->message);  // the first warning
}

/// Decodes the whole JPEG `data` (no local with a destructor: longjmp skips none); "" when it is intact,
/// else libjpeg's message. The header's size is checked before decoding.
std::string jpegProblem(const unsigned char* data, std::size_t size, StrictJpegErrors& errors) {
  jpeg_decompress_struct cinfo;
  cinfo.err = jpeg_std_error(&errors.mgr);
  errors.mgr.error_exit = onJpegError;
  errors.mgr.output_message = onJpegMessage;
  errors.message[0] = '\0';
  errors.width = errors.height = 0;
  if (setjmp(errors.jump) != 0) {
    jpeg_destroy_decompress(&cinfo);
    return errors.message;
  }
  jpeg_create_decompress(&cinfo);
  jpeg_mem_src(&cinfo, data, static_cast<unsigned long>(size));
  jpeg_read_header(&cinfo, TRUE);
  errors.width = static_cast<int>(cinfo.image_width);
  errors.height = static_cast<int>(cinfo.image_height);
  if (!imageSizeProblem(errors.width, errors.height).empty()) {
    jpeg_destroy_decompress(&cinfo);
    return "";  // the caller reports the size
  }
  // Only the data's integrity matters here: the cheapest output libjpeg converts to (grey; a CMYK or YCCK file only
  // decodes to CMYK).
  const bool cmyk = cinfo.jpeg_color_space == JCS_CMYK || cinfo.jpeg_color_space == JCS_YCCK;
  cinfo.out_color_space = cmyk ? JCS_CMYK : JCS_GRAYSCALE;
  jpeg_start_decompress(&cinfo);
  errors.row.resize(static_cast<std::size_t>(cinfo.output_width) * cinfo.output_components);
  while (cinfo.output_scanline < cinfo.output_height) {
    JSAMPLE* row = errors.row.data();
    jpeg_read_scanlines(&cinfo, &row, 1);
  }
  jpeg_finish_decompress(&cinfo);
  jpeg_destroy_decompress(&cinfo);
  return errors.message;  // a warning's message, or ""
}

std::uint32_t bigEndian32(const unsigned char* p) {
  return (std::uint32_t(p[0]) << 24) | (std::uint32_t(p[1]) << 16) | (std::uint32_t(p[2]) << 8) | p[3];
}

/// The median of all of `image`'s values (every channel; CV_32F).
float medianValue(const cv::Mat& image) {
  std::vector<float> v;
  (image.isContinuous() ? image : image.clone()).reshape(1, 1).copyTo(v);
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

/// What OpenCV's `depth` holds, for a message naming a depth that is not read.
std::string depthName(int depth) {
  switch (depth) {
    case CV_8S: return "8-bit signed integers";
    case CV_16S: return "16-bit signed integers";
    case CV_32S: return "32-bit signed integers";
    case CV_16F: return "16-bit floating point";
    default: return "OpenCV depth " + std::to_string(depth);
  }
}

/// `image` (as decoded: any depth, 1, 3 or 4 channels) as 8-bit BGR: grey repeated in three channels, alpha dropped,
/// 16-bit scaled by 1/257 (65535 -> 255), floating point read as brightness 0..1 (clipped: a high-dynamic-range
/// frame's highlights are white, as a camera sees them; one whose median pixel exceeds 1 was scaled otherwise and is
/// refused); anything else is refused naming `path`.
cv::Mat asBgr8(const cv::Mat& decoded, const std::string& path) {
  const int depth = decoded.depth();
  if (depth != CV_8U && depth != CV_16U && depth != CV_32F && depth != CV_64F) {
    throw std::invalid_argument(path + ": pixels of " + depthName(depth) +
                                ": only 8- or 16-bit unsigned or 32- or 64-bit floating-point images are read");
  }
  cv::Mat image = decoded;
  if (depth == CV_64F) {  // cvtColor takes no 64-bit pixels; 8 bits come out anyway
    if (!cv::checkRange(decoded)) throw std::invalid_argument(path + ": a floating-point image with NaN or infinite pixels");
    // Clamped well inside 32-bit floats (OpenCV's checkRange takes FLT_MAX itself for infinite): far over 1 either way,
    // so such an image is refused for its median below, not said to hold infinite pixels.
    constexpr double kMost = 1e30;
    cv::Mat(cv::max(cv::min(decoded, kMost), -kMost)).convertTo(image, CV_32F);
  }
  cv::Mat bgr;
  switch (image.channels()) {
    case 1: cv::cvtColor(image, bgr, cv::COLOR_GRAY2BGR); break;
    case 3: bgr = image; break;
    case 4: cv::cvtColor(image, bgr, cv::COLOR_BGRA2BGR); break;
    default: throw std::invalid_argument(path + ": " + std::to_string(image.channels()) + " channels (1, 3 or 4 are read)");
  }
  cv::Mat out;
  switch (bgr.depth()) {
    case CV_8U: return bgr;
    case CV_16U: bgr.convertTo(out, CV_8U, 1.0 / 257.0); return out;
    case CV_32F:
      if (!cv::checkRange(bgr)) throw std::invalid_argument(path + ": a floating-point image with NaN or infinite pixels");
      if (const float median = medianValue(bgr); median > 1.0) {
        throw std::invalid_argument(path + ": a floating-point image whose median pixel is " + std::to_string(median) +
                                    ": read as brightness 0..1, so it would be nearly all white (scaled 0..255 or "
                                    "0..65535? divide it by its white level)");
      }
      bgr.convertTo(out, CV_8U, 255.0);  // saturating
      return out;
    default:  // refused above
      throw std::logic_error("asBgr8: depth " + std::to_string(bgr.depth()));
  }
}

}  // namespace

bool isGreyImage(const cv::Mat& bgr) {
  if (bgr.empty() || bgr.channels() != 3) return false;
  cv::Mat channels[3];
  cv::split(bgr, channels);
  return cv::norm(channels[0], channels[1], cv::NORM_INF) == 0 && cv::norm(channels[1], channels[2], cv::NORM_INF) == 0;
}

cv::Mat readImageFile(const std::string& path) {
  const auto too_large = [&](std::uintmax_t bytes) {  // OpenCV decodes from an int-sized buffer
    if (bytes <= static_cast<std::uintmax_t>(std::numeric_limits<int>::max())) return;
    throw std::invalid_argument(path + ": " + std::to_string(bytes) + " bytes: larger than an image file OpenCV decodes (2 GiB)");
  };
  std::error_code error;
  if (const std::uintmax_t bytes = std::filesystem::file_size(path, error); !error) too_large(bytes);  // before reading
  const std::string file = readWholeFile(path);
  if (file.empty()) throw std::invalid_argument(path + ": empty file");
  too_large(file.size());  // grown since
  const auto* bytes = reinterpret_cast<const unsigned char*>(file.data());
  const std::size_t size = file.size();
  long long width = -1, height = -1;  // as the header declares them, where known before decoding
  static const unsigned char kPngSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  static const unsigned char kPngEnd[8] = {'I', 'E', 'N', 'D', 0xae, 0x42, 0x60, 0x82};
  if (size >= 3 && bytes[0] == 0xff && bytes[1] == 0xd8 && bytes[2] == 0xff) {
    StrictJpegErrors errors;
    const std::string problem = jpegProblem(bytes, size, errors);
    if (!problem.empty()) throw std::invalid_argument(path + ": corrupt or truncated JPEG (" + problem + ")");
    width = errors.width;
    height = errors.height;
  } else if (size >= 8 && std::memcmp(bytes, kPngSignature, 8) == 0) {
    if (size < 33) throw std::invalid_argument(path + ": truncated PNG (" + std::to_string(size) + " bytes)");
    width = bigEndian32(&bytes[16]);
    height = bigEndian32(&bytes[20]);
    if (std::memcmp(&bytes[size - 8], kPngEnd, 8) != 0) {
      throw std::invalid_argument(path + ": truncated PNG (the file does not end with its IEND chunk)");
    }
  }
  if (width >= 0) {
    const std::string size_problem = imageSizeProblem(width, height);
    if (!size_problem.empty()) throw std::invalid_argument(path + ": " + size_problem);
  }
  cv::Mat image;
  try {
    const cv::Mat encoded(1, static_cast<int>(size), CV_8U, const_cast<unsigned char*>(bytes));  // read only
    image = cv::imdecode(encoded, cv::IMREAD_ANYCOLOR | cv::IMREAD_ANYDEPTH | cv::IMREAD_IGNORE_ORIENTATION);
  } catch (const cv::Exception& e) {
    throw std::invalid_argument(path + ": cannot decode the image (" + e.err + ")");
  }
  if (image.empty()) throw std::invalid_argument(path + ": not an image OpenCV can read, or corrupt");
  const std::string size_problem = imageSizeProblem(image.cols, image.rows);
  if (!size_problem.empty()) throw std::invalid_argument(path + ": " + size_problem);
  return asBgr8(image, path);
}

}  // namespace underwater_stereo
