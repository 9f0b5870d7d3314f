// SPDX-License-Identifier: BSD-3-Clause
// Why a labelled object was missed: each stage of the learned search named from proposals, verdicts and
// detections built by hand.
#include <gtest/gtest.h>

#include "underwater_stereo/detection/miss_causes.h"

using namespace underwater_stereo;

namespace {

const cv::Rect kLabel(100, 100, 40, 40);
const std::vector<double> kThresholds{0.5, 0.4};  // colour 0 (red), colour 1 (green)
constexpr int kGreen = 1;

MissCause causeOf(const std::vector<cv::Rect>& proposals, const std::vector<ColourVerdict>& verdicts,
                  const std::vector<KeptRegion>& detections = {}) {
  return explainMiss(kLabel, kGreen, proposals, verdicts, detections, kThresholds, 0.5).cause;
}

}  // namespace

TEST(MissCauses, NoCoveringProposal) {
  // Far away, or a sliver of the label (IoU under kMatchIou): not a view of it.
  EXPECT_EQ(causeOf({}, {}), MissCause::kNoProposal);
  EXPECT_EQ(causeOf({cv::Rect(300, 300, 40, 40), cv::Rect(100, 100, 10, 10)}, {{kGreen, 0.9, {}}, {kGreen, 0.9, {}}}),
            MissCause::kNoProposal);
}

TEST(MissCauses, VotesUnderItsThresholdWithTheBestReported) {
  const MissExplanation e = explainMiss(kLabel, kGreen, {cv::Rect(102, 102, 36, 36), cv::Rect(95, 95, 50, 50)},
                                        {{kGreen, 0.3, {}}, {-1, 0.0, {}}}, {}, kThresholds, 0.5);
  EXPECT_EQ(e.cause, MissCause::kUnderThreshold);
  EXPECT_DOUBLE_EQ(e.best_confidence, 0.3);
  // Another colour under its own threshold is not a wrong name.
  EXPECT_EQ(causeOf({cv::Rect(102, 102, 36, 36)}, {{0, 0.45, {}}}), MissCause::kUnderThreshold);
}

TEST(MissCauses, NamedAnotherColour) {
  EXPECT_EQ(causeOf({cv::Rect(102, 102, 36, 36)}, {{0, 0.55, {}}}), MissCause::kWrongColour);
  // Also when its own colour passed but a detection of another colour sits on the label.
  EXPECT_EQ(causeOf({cv::Rect(102, 102, 36, 36)}, {{kGreen, 0.6, {}}}, {{cv::Rect(98, 98, 44, 44), 0}}),
            MissCause::kWrongColour);
}

TEST(MissCauses, TakenByAnOverlappingRegionOrDetectedOffTheLabel) {
  // Passed as green, but a larger green region centred below the label (the buoy with its stem) was kept.
  EXPECT_EQ(causeOf({cv::Rect(102, 102, 36, 36)}, {{kGreen, 0.6, {}}}, {{cv::Rect(95, 100, 50, 120), kGreen}}),
            MissCause::kOverlapped);
  // Passed and nothing overlapped it: its own detection was cut off the label.
  EXPECT_EQ(causeOf({cv::Rect(102, 102, 36, 36)}, {{kGreen, 0.6, {}}}), MissCause::kOffLabel);
}

TEST(MissCauses, MismatchedInputsAreErrors) {
  EXPECT_THROW(causeOf({cv::Rect(102, 102, 36, 36)}, {}), std::invalid_argument);
  EXPECT_THROW(explainMiss(kLabel, 2, {}, {}, {}, kThresholds, 0.5), std::invalid_argument);
}
