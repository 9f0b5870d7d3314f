// SPDX-License-Identifier: BSD-3-Clause
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include <regex>

#include "underwater_stereo/sim/renderer.h"
#include "underwater_stereo/sim/scene_sampler.h"
#include "underwater_stereo/sim/voc_labels.h"

using namespace underwater_stereo::sim;

namespace {

/// Every tag of `xml` closed in order (a minimal well-formedness check: no attributes, no self-closing tags).
bool tagsBalance(const std::string& xml) {
  std::vector<std::string> open;
  const std::regex tag("<(/?)([a-z_]+)>");
  for (auto it = std::sregex_iterator(xml.begin(), xml.end(), tag); it != std::sregex_iterator(); ++it) {
    if ((*it)[1].length() == 0) {
      open.push_back((*it)[2]);
    } else {
      if (open.empty() || open.back() != (*it)[2]) return false;
      open.pop_back();
    }
  }
  return open.empty();
}

std::vector<int> numbers(const std::string& xml, const std::string& tag) {
  std::vector<int> out;
  const std::regex re("<" + tag + ">(-?[0-9]+)</" + tag + ">");
  for (auto it = std::sregex_iterator(xml.begin(), xml.end(), re); it != std::sregex_iterator(); ++it) {
    out.push_back(std::stoi((*it)[1]));
  }
  return out;
}

}  // namespace

TEST(VocLabels, AnnotationAndMaskDescribeEveryVisibleDesignatedObjectExactly) {
  SceneSamplerConfig config;
  config.width = 320;
  config.height = 200;
  int objects_seen = 0;
  for (std::uint64_t seed = 400; seed < 420; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const SampledScene sampled = sampleScene(seed, config);
    const RenderedPair pair = Renderer(sampled.scene).render(0.0, 0);
    const std::vector<std::size_t> labelled = labelledObjects(pair.ground_truth, config.designated);
    const std::string xml = vocAnnotation("x.png", cv::Size(320, 200), pair.ground_truth, labelled, 400);
    const cv::Mat mask = labelMask(pair.left_labels, labelled);
    EXPECT_TRUE(tagsBalance(xml)) << xml;
    EXPECT_EQ(numbers(xml, "width"), std::vector<int>{320});
    EXPECT_EQ(numbers(xml, "height"), std::vector<int>{200});
    const std::vector<int> xmin = numbers(xml, "xmin"), ymin = numbers(xml, "ymin"), xmax = numbers(xml, "xmax"),
                           ymax = numbers(xml, "ymax");
    ASSERT_EQ(xmin.size(), labelled.size());
    ASSERT_EQ(ymax.size(), labelled.size());
    for (std::size_t k = 0; k < labelled.size(); ++k) {
      const GroundTruthObject& g = pair.ground_truth[labelled[k]];
      // Distractors are never labelled; every labelled object shows.
      EXPECT_TRUE(sampled.designated[labelled[k]]) << g.name;
      // VOC corners are 1-based and inclusive: the box of the mask's pixels of label k + 1.
      const cv::Mat mine = mask == static_cast<int>(k + 1);
      EXPECT_EQ(cv::countNonZero(mine), g.visible_pixels) << g.name;
      const cv::Rect box = cv::boundingRect(mine);
      EXPECT_EQ(xmin[k], box.x + 1);
      EXPECT_EQ(ymin[k], box.y + 1);
      EXPECT_EQ(xmax[k], box.x + box.width);
      EXPECT_EQ(ymax[k], box.y + box.height);
      EXPECT_GE(xmin[k], 1);
      EXPECT_LE(xmax[k], 320);
      ++objects_seen;
    }
    double max_label = 0;
    cv::minMaxLoc(mask, nullptr, &max_label);
    EXPECT_EQ(static_cast<std::size_t>(max_label), labelled.size());
    // <name> is the colour, in object order.
    const std::regex name("<name>([a-z]+)</name>");
    std::size_t k = 0;
    for (auto it = std::sregex_iterator(xml.begin(), xml.end(), name); it != std::sregex_iterator(); ++it, ++k) {
      ASSERT_LT(k, labelled.size());
      EXPECT_EQ((*it)[1], pair.ground_truth[labelled[k]].colour);
    }
  }
  EXPECT_GT(objects_seen, 20);
}

TEST(VocLabels, NamesAreEscapedAndBadInputRefused) {
  GroundTruthObject g;
  g.name = "a";
  g.colour = "red<&>";
  g.visible_pixels = 10;
  g.roi_left = cv::Rect(0, 0, 5, 2);
  const std::string xml = vocAnnotation("a&b.png", cv::Size(10, 10), {g}, {0}, 400);
  EXPECT_NE(xml.find("<name>red&lt;&amp;&gt;</name>"), std::string::npos);
  EXPECT_NE(xml.find("<filename>a&amp;b.png</filename>"), std::string::npos);
  EXPECT_NE(xml.find("<truncated>1</truncated>"), std::string::npos);
  EXPECT_NE(xml.find("<difficult>1</difficult>"), std::string::npos);
  EXPECT_THROW(vocAnnotation("a.png", cv::Size(10, 10), {g}, {1}, 400), std::invalid_argument);
  g.visible_pixels = 0;
  EXPECT_THROW(vocAnnotation("a.png", cv::Size(10, 10), {g}, {0}, 400), std::invalid_argument);
  EXPECT_THROW(labelMask(cv::Mat::zeros(4, 4, CV_8UC1), {}), std::invalid_argument);
}

TEST(VocLabels, ASliverOnePixelWideOrTallIsNotLabelled) {
  GroundTruthObject g;
  g.colour = "red";
  g.visible_pixels = 10;
  std::vector<GroundTruthObject> truth(3, g);
  truth[0].roi_left = cv::Rect(350, 288, 1, 10);  // its VOC corners would be xmin == xmax: an "empty box"
  truth[1].roi_left = cv::Rect(10, 20, 10, 1);
  truth[2].roi_left = cv::Rect(10, 20, 2, 2);
  EXPECT_EQ(labelledObjects(truth, {"red"}), std::vector<std::size_t>{2});
}
