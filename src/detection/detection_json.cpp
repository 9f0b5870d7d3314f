// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/detection/detection_json.h"

#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <sstream>

namespace underwater_stereo {
namespace {

std::string quoted(const std::string& s) {
  std::string out = "\"";
  for (const char c : s) {
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
