// SPDX-License-Identifier: BSD-3-Clause
#include <gtest/gtest.h>

#include <limits>

#include "underwater_stereo/detection/detection_json.h"

using namespace underwater_stereo;

TEST(DetectionJson, WritesTheMessageFieldNamesEscapesStringsAndNullsNonFiniteNumbers) {
  Detection d;
  d.colour = "red \"buoy\"";
  d.shape = ShapeKind::kSphere;
  d.outline = OutlineKind::kCircle;
  d.measured_bgr = cv::Scalar(0, 51, 255);
  d.size_m = Eigen::Vector3d(0.25, 0.25, 0.25);
  d.position_m = Eigen::Vector3d(-0.5, 0.1, std::numeric_limits<double>::quiet_NaN());
  d.range_m = 2.5;
  d.roi = cv::Rect(10, 20, 30, 40);
  d.confidence = 0.9;
  d.cut_by_border = true;
  QualityReport q;
  q.mean_brightness = 97.5;
  const std::string line = detectionJson("a\\b.png", 3, d, q, true);
  EXPECT_EQ(line.find('\n'), std::string::npos);
  for (const char* expected :
       {"\"file\": \"a\\\\b.png\"", "\"id\": 3", "\"colour\": \"red \\\"buoy\\\"\"", "\"measured_colour\": [1, 0.2, 0]",
        "\"shape\": \"sphere\"", "\"outline\": \"circle\"", "\"size\": [0.25, 0.25, 0.25]", "\"range\": 2.5",
        "\"position\": [-0.5, 0.1, null]", "\"orientation\": [0, 0, 0, 1]", "\"roi\": [10, 20, 30, 40]",
        "\"confidence\": 0.9", "\"cut_by_border\": true", "\"quality\": {\"status\": \"OK\", \"mean_brightness\": 97.5"}) {
    EXPECT_NE(line.find(expected), std::string::npos) << expected << " in " << line;
  }
  const std::string flat = detectionJson("x.jpg", 0, d, q, false);
  EXPECT_EQ(flat.find("\"range\""), std::string::npos);
  EXPECT_EQ(flat.find("\"shape\""), std::string::npos);
  EXPECT_NE(emptyFrameJson("x.jpg", q).find("\"id\": null"), std::string::npos);
  // A file name in another encoding than UTF-8: each stray byte becomes U+FFFD, UTF-8 is kept as it is.
  EXPECT_NE(emptyFrameJson("b\xe4r_\xc3\xa4_\xed\xa0\x80_\xf0\x9f\x90\x9f.jpg", q)
                .find("\"file\": \"b\\ufffdr_\xc3\xa4_\\ufffd\\ufffd\\ufffd_\xf0\x9f\x90\x9f.jpg\""),
            std::string::npos)
      << emptyFrameJson("b\xe4r_\xc3\xa4_\xed\xa0\x80_\xf0\x9f\x90\x9f.jpg", q);
}
