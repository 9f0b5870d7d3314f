// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/detection/forest_votes.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace underwater_stereo {
namespace {

/// Probe samples for the check against getVotes: each feature at one of its own thresholds or just above it,
/// so the probes take both branches at many nodes (0 for a feature no node splits on).
cv::Mat probes(const std::vector<std::vector<float>>& thresholds, int rows) {
  cv::Mat out(rows, static_cast<int>(thresholds.size()), CV_32F);
  cv::RNG rng(12345);
  for (int r = 0; r < rows; ++r) {
    for (int f = 0; f < out.cols; ++f) {
      const std::vector<float>& t = thresholds[f];
      const float at = t.empty() ? 0.f : t[rng.uniform(0, static_cast<int>(t.size()))];
      out.at<float>(r, f) = rng.uniform(0, 2) ? std::nextafter(at, 1e30f) : at;
    }
  }
  return out;
}

}  // namespace

void checkStoredTrees(const cv::FileNode& stored, int feature_count, const std::string& what, const std::string& kind) {
  auto integer = [&](const cv::FileNode& n, const std::string& name) {
    if (!n.isInt()) throw std::invalid_argument(what + kind + ": " + name + " is missing or not an integer");
    return static_cast<int>(n);
  };
  if (!stored.isMap()) throw std::invalid_argument(what + "no " + kind);
  const int var_all = integer(stored["var_all"], "var_all"), var_count = integer(stored["var_count"], "var_count");
  if (var_count != feature_count || var_all != feature_count + 1) {
    throw std::invalid_argument(what + kind + " of " + std::to_string(var_count) + " features and " +
                                std::to_string(var_all - var_count) + " responses, not " +
                                std::to_string(feature_count) + " and 1");
  }
  // Every feature ordered (0), the response a class (1): a categorical split reads a subset OpenCV does not check.
  const cv::FileNode var_idx = stored["var_idx"], var_type = stored["var_type"];
  if (!var_type.isSeq() || static_cast<int>(var_type.size()) != var_all) {
    throw std::invalid_argument(what + kind + ": var_type does not list " + std::to_string(var_all) + " variables");
  }
  for (int i = 0; i < var_all; ++i) {
    const cv::FileNode t = var_type[i];
    if (!t.isInt() || static_cast<int>(t) != (i < var_count ? 0 : 1)) {
      throw std::invalid_argument(what + kind + ": variable " + std::to_string(i) + " is not " +
                                  (i < var_count ? "an ordered feature" : "the class"));
    }
  }
  if (!var_idx.empty()) {
    if (!var_idx.isSeq() || static_cast<int>(var_idx.size()) != var_count) {
      throw std::invalid_argument(what + kind + ": var_idx does not list " + std::to_string(var_count) + " features");
    }
    std::vector<bool> listed(static_cast<std::size_t>(var_count), false);
    for (const cv::FileNode& v : var_idx) {
      const int k = v.isInt() ? static_cast<int>(v) : -1;
      if (k < 0 || k >= var_count || listed[k]) {
        throw std::invalid_argument(what + kind + ": var_idx is not each of the " + std::to_string(var_count) +
                                    " features once");
      }
      listed[k] = true;
    }
  }
  const cv::FileNode trees = stored["trees"];
  if (!trees.isSeq()) throw std::invalid_argument(what + kind + ": no trees");
  int t = 0;
  for (const cv::FileNode& tree : trees) {
    int n = 0;
    for (const cv::FileNode& node : tree["nodes"]) {
      for (const cv::FileNode& split : node["splits"]) {
        const int var = split["var"].isInt() ? static_cast<int>(split["var"]) : -1;
        if (!split["in"].empty() || !split["not_in"].empty()) {
          throw std::invalid_argument(what + kind + ": tree " + std::to_string(t) + " node " + std::to_string(n) +
                                      " splits on a category");
        }
        if (var < 0 || var >= feature_count) {
          throw std::invalid_argument(what + kind + ": tree " + std::to_string(t) + " node " + std::to_string(n) +
                                      " splits on feature " + (split["var"].isInt() ? std::to_string(var) : "(none)") +
                                      ", outside [0, " + std::to_string(feature_count) + ")");
        }
      }
      ++n;
    }
    ++t;
  }
}

cv::Ptr<cv::ml::RTrees> readStoredForest(const cv::FileNode& forest, int feature_count, const std::string& what) {
  checkStoredTrees(forest, feature_count, what, "forest");
  cv::Ptr<cv::ml::RTrees> read = cv::ml::RTrees::create();
  read->read(forest);
  return read;
}

void checkTreeLinks(const cv::ml::DTrees& trees, int feature_count) {
  const std::vector<cv::ml::DTrees::Node>& nodes = trees.getNodes();
  const std::vector<cv::ml::DTrees::Split>& splits = trees.getSplits();
  const int n = static_cast<int>(nodes.size());
  for (int i = 0; i < n; ++i) {
    const cv::ml::DTrees::Node& node = nodes[i];
    if (node.split < 0) continue;
    if (node.split >= static_cast<int>(splits.size()) || node.left < 0 || node.left >= n || node.right < 0 ||
        node.right >= n) {
      throw std::invalid_argument("node " + std::to_string(i) + " links outside the trees");
    }
    const int var = splits[node.split].varIdx;
    if (var < 0 || var >= feature_count) {
      throw std::invalid_argument("node " + std::to_string(i) + " splits on feature " + std::to_string(var));
    }
    // Every walk must end: children come after their parent in OpenCV's node order.
    if (node.left <= i || node.right <= i) throw std::invalid_argument("node " + std::to_string(i) + " links back");
  }
  for (int r : trees.getRoots()) {
    if (r < 0 || r >= n) throw std::invalid_argument("a tree's root lies outside the trees");
  }
}

ForestVotes::ForestVotes(const cv::ml::RTrees& forest, int feature_count) {
  if (!forest.isTrained() || !forest.isClassifier() || forest.getVarCount() != feature_count || feature_count < 1) {
    throw std::invalid_argument("ForestVotes: no trained classifier forest of " + std::to_string(feature_count) + " features");
  }
  try {
    checkTreeLinks(forest, feature_count);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(std::string("ForestVotes: ") + e.what());
  }
  const std::vector<cv::ml::DTrees::Node>& nodes = forest.getNodes();
  const std::vector<cv::ml::DTrees::Split>& splits = forest.getSplits();
  nodes_.resize(nodes.size());
  std::vector<std::vector<float>> thresholds(feature_count);
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    const cv::ml::DTrees::Node& in = nodes[i];
    Node& out = nodes_[i];
    if (in.split < 0) {
      out.label_index = in.classIdx;
      continue;
    }
    const cv::ml::DTrees::Split& s = splits[in.split];
    out.feature = s.varIdx;
    out.threshold = s.c;
    out.left = in.left;
    out.right = in.right;
    thresholds[s.varIdx].push_back(s.c);
  }
  roots_ = forest.getRoots();
  // The links are sound: OpenCV's own walk is safe now, and gives the labels.
  cv::Mat votes;
  forest.getVotes(cv::Mat::zeros(1, feature_count, CV_32F), votes, 0);
  if (votes.rows != 2 || votes.type() != CV_32S) throw std::invalid_argument("ForestVotes: getVotes gave no label row");
  labels_.assign(votes.ptr<int>(0), votes.ptr<int>(0) + votes.cols);
  for (const Node& node : nodes_) {
    if (node.feature < 0 && (node.label_index < 0 || node.label_index >= static_cast<int>(labels_.size()))) {
      throw std::invalid_argument("ForestVotes: a leaf votes for class index " + std::to_string(node.label_index));
    }
  }
  const cv::Mat probe = probes(thresholds, 64);
  forest.getVotes(probe, votes, 0);
  std::vector<int> counts(labels_.size());
  for (int r = 0; r < probe.rows; ++r) {
    vote(probe.ptr<float>(r), counts.data());
    for (std::size_t k = 0; k < counts.size(); ++k) {
      if (counts[k] != votes.at<int>(1 + r, static_cast<int>(k))) {
        throw std::invalid_argument("ForestVotes: the copied forest votes otherwise than OpenCV's");
      }
    }
  }
}

void ForestVotes::vote(const float* sample, int* counts) const {
  std::fill(counts, counts + labels_.size(), 0);
  for (int root : roots_) {
    const Node* node = &nodes_[root];
    while (node->feature >= 0) {
      node = &nodes_[sample[node->feature] <= node->threshold ? node->left : node->right];
    }
    ++counts[node->label_index];
  }
}

}  // namespace underwater_stereo
