// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/detection/detection_json.h"

#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <sstream>

namespace underwater_stereo {
namespace {

/// Length of the well-formed UTF-8 sequence at s[i] (1-4), or 0 when the byte there starts none.
std::size_t utf8Length(const std::string& s, std::size_t i) {
  const auto byte = [&](std::size_t k) { return k < s.size() ? static_cast<unsigned char>(s[k]) : 0u; };
  const unsigned c = byte(i);
  if (c < 0x80) return 1;
  // The sequence's length, and its second byte's range: narrower after E0, ED, F0 and F4 (no overlong form, no
  // surrogate, nothing past U+10FFFF).
  std::size_t n = 0;
  unsigned lo = 0x80, hi = 0xbf;
  if (c >= 0xc2 && c <= 0xdf) {
    n = 2;
  } else if (c >= 0xe0 && c <= 0xef) {
    n = 3;
    if (c == 0xe0) lo = 0xa0;
    if (c == 0xed) hi = 0x9f;
  } else if (c >= 0xf0 && c <= 0xf4) {
    n = 4;
    if (c == 0xf0) lo = 0x90;
    if (c == 0xf4) hi = 0x8f;
  } else {
    return 0;
  }
  if (byte(i + 1) < lo || byte(i + 1) > hi) return 0;
  for (std::size_t k = 2; k < n; ++k) {
    if (byte(i + k) < 0x80 || byte(i + k) > 0xbf) return 0;
  }
  return n;
}

/// A JSON string; a byte that is no UTF-8 (a file name in another encoding) becomes U+FFFD, so the line stays JSON.
std::string quoted(const std::string& s) {
  std::string out = "\"";
  for (std::size_t i = 0; i < s.size();) {
    const char c = s[i];
    const std::size_t n = utf8Length(s, i);
    if (n == 0) {
      out += "\\ufffd";
      ++i;
      continue;
    }
    if (n > 1) {
      out.append(s, i, n);
      i += n;
      continue;
    }
    ++i;
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\t': out += "\\t"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          char buf[8];
          std::snprintf(buf, sizeof buf, "\\u%04x", c);
          out += buf;
        } else {
          out += c;
        }
    }
  }
  return out + "\"";
}

std::string number(double v) {
  if (!std::isfinite(v)) return "null";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

std::string array(std::initializer_list<double> values) {
  std::string out = "[";
  for (const double v : values) out += (out.size() > 1 ? ", " : "") + number(v);
  return out + "]";
}

}  // namespace

std::string qualityJson(const QualityReport& q) {
  return "{\"status\": " + quoted(qualityStatusName(q.status)) + ", \"mean_brightness\": " + number(q.mean_brightness) +
         ", \"dark_fraction\": " + number(q.dark_fraction) + ", \"bright_fraction\": " + number(q.bright_fraction) +
         ", \"enhanced\": " + (q.enhanced ? "true" : "false") + "}";
}

std::string detectionJson(const std::string& file, int id, const Detection& d, const QualityReport& quality,
                          bool with_3d) {
  std::ostringstream out;
  out << "{\"file\": " << quoted(file) << ", \"id\": " << id << ", \"colour\": " << quoted(d.colour)
      << ", \"measured_colour\": "
      << array({d.measured_bgr[2] / 255.0, d.measured_bgr[1] / 255.0, d.measured_bgr[0] / 255.0})
      << ", \"outline\": " << quoted(outlineName(d.outline))
      << ", \"roi\": " << array({double(d.roi.x), double(d.roi.y), double(d.roi.width), double(d.roi.height)})
      << ", \"confidence\": " << number(d.confidence) << ", \"cut_by_border\": " << (d.cut_by_border ? "true" : "false");
  if (with_3d) {
    out << ", \"shape\": " << quoted(shapeName(d.shape))
        << ", \"size\": " << array({d.size_m.x(), d.size_m.y(), d.size_m.z()})
        << ", \"range\": " << number(d.range_m)
        << ", \"position\": " << array({d.position_m.x(), d.position_m.y(), d.position_m.z()})
        << ", \"orientation\": "
        << array({d.orientation.x(), d.orientation.y(), d.orientation.z(), d.orientation.w()})
        << ", \"num_points\": " << d.points.size() << ", \"fit_rmse\": " << number(d.fit_rmse_m);
  }
  out << ", \"quality\": " << qualityJson(quality) << "}";
  return out.str();
}

std::string emptyFrameJson(const std::string& file, const QualityReport& quality) {
  return "{\"file\": " + quoted(file) + ", \"id\": null, \"quality\": " + qualityJson(quality) + "}";
}

std::string rejectionJson(const std::string& file, const Rejection& r) {
  return "{\"file\": " + quoted(file) + ", \"rejected\": {\"colour\": " + quoted(r.colour) + ", \"roi\": " +
         array({double(r.roi.x), double(r.roi.y), double(r.roi.width), double(r.roi.height)}) +
         ", \"confidence\": " + number(r.confidence) + ", \"stage\": " + quoted(rejectionStageName(r.stage)) +
         ", \"reason\": " + quoted(r.reason) + "}}";
}

}  // namespace underwater_stereo
