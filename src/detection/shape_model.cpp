// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/detection/shape_model.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

#include "underwater_stereo/detection/shape_features.h"

namespace underwater_stereo {
namespace {

/// The shapes a model tells apart; the forest's label of kShapes[i] is i.
constexpr std::array<ShapeKind, 4> kShapes{ShapeKind::kSphere, ShapeKind::kCylinder, ShapeKind::kBox, ShapeKind::kPlane};

int labelOf(ShapeKind shape) {
  const auto it = std::find(kShapes.begin(), kShapes.end(), shape);
  return it == kShapes.end() ? -1 : static_cast<int>(it - kShapes.begin());
}

}  // namespace

ShapeModel ShapeModel::train(const cv::Mat& samples, const std::vector<ShapeKind>& labels,
                             const ShapeModelTraining& options) {
  const auto problems = options.validate();
  if (!problems.empty()) throw std::invalid_argument("ShapeModel::train: " + problems.front());
  if (samples.type() != CV_32FC1 || samples.cols != kShapeFeatureCount || samples.rows != static_cast<int>(labels.size())) {
    throw std::invalid_argument("ShapeModel::train: need one CV_32F row of " + std::to_string(kShapeFeatureCount) +
                                " features per label");
  }
  std::array<int, kShapes.size()> counts{};
  cv::Mat responses(samples.rows, 1, CV_32SC1);
  for (int i = 0; i < samples.rows; ++i) {
    const int l = labelOf(labels[i]);
    if (l < 0) throw std::invalid_argument(std::string("ShapeModel::train: cannot learn shape '") + shapeName(labels[i]) + "'");
    responses.at<int>(i) = l;
    ++counts[l];
  }
  for (std::size_t k = 0; k < kShapes.size(); ++k) {
    if (counts[k] == 0) throw std::invalid_argument(std::string("ShapeModel::train: no samples of ") + shapeName(kShapes[k]));
  }
  const int most = *std::max_element(counts.begin(), counts.end());
  cv::Mat priors(1, static_cast<int>(kShapes.size()), CV_32F);
  for (std::size_t k = 0; k < kShapes.size(); ++k) {
    priors.at<float>(static_cast<int>(k)) = static_cast<float>(std::pow(double(most) / counts[k], options.balance));
  }
  ShapeModel m;
  m.forest_ = trainForest(samples, responses, priors, options);
  m.votes_ = ForestVotes(*m.forest_, kShapeFeatureCount);
  return m;
}

ShapeModel ShapeModel::load(const std::string& path) {
  const std::string what = "shape model " + path + ": ";
  const cv::FileStorage fs = openModelFile(path, "shape model " + path);
  ShapeModel m;
  try {
    std::vector<std::string> features, shapes;
    fs["features"] >> features;
    fs["shapes"] >> shapes;
    if (features != shapeFeatureNames()) {
      throw std::invalid_argument(what + "made for other features (" + std::to_string(features.size()) +
                                  " named; this build computes " + std::to_string(kShapeFeatureCount) + "): learn it again");
    }
    std::vector<std::string> expected;
    for (ShapeKind s : kShapes) expected.emplace_back(shapeName(s));
    if (shapes != expected) throw std::invalid_argument(what + "names other shapes than sphere, cylinder, box, plane");
    m.forest_ = readStoredForest(fs["forest"], kShapeFeatureCount, what);
  } catch (const cv::Exception& e) {
    throw std::invalid_argument(what + "unreadable (" + e.msg + ")");
  }
  try {  // also refuses a forest that is no trained classifier of kShapeFeatureCount features
    m.votes_ = ForestVotes(*m.forest_, kShapeFeatureCount);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(what + e.what());
  }
  return m;
}

void ShapeModel::save(const std::string& path) const {
  if (empty()) throw std::runtime_error("ShapeModel::save: empty model");
  cv::FileStorage fs = createModelFile(path, "shape model " + path);
  std::vector<std::string> shapes;
  for (ShapeKind s : kShapes) shapes.emplace_back(shapeName(s));
  fs << "features" << shapeFeatureNames();
  fs << "shapes" << shapes;
  fs << "forest" << "{";
  forest_->write(fs);
  fs << "}";
}

ShapeVerdict ShapeModel::classify(const std::vector<float>& features) const {
  if (empty()) throw std::invalid_argument("ShapeModel::classify: empty model");
  if (static_cast<int>(features.size()) != kShapeFeatureCount) {
    throw std::invalid_argument("ShapeModel::classify: need " + std::to_string(kShapeFeatureCount) + " features, got " +
                                std::to_string(features.size()));
  }
  std::vector<int> counts(votes_.labels().size());
  votes_.vote(features.data(), counts.data());
  const auto [label, share] =
      votes_.best(counts.data(), [](int l) { return l >= 0 && l < static_cast<int>(kShapes.size()); });
  ShapeVerdict v;
  if (label >= 0) v.shape = kShapes[label];
  v.confidence = share;
  return v;
}

}  // namespace underwater_stereo
