#include "pf2/registration/loop_detector.h"

#include <algorithm>
#include <map>

#include <opencv2/features2d.hpp>
#include <opencv2/flann.hpp>

#include "pf2/core/error.h"

namespace pf2 {

LoopDetector::LoopDetector() : LoopDetector(Options()) {}
LoopDetector::LoopDetector(const Options& options) : options_(options) {}
LoopDetector::~LoopDetector() = default;

void LoopDetector::add(int keyframe_id, const cv::Mat& descriptors) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!ids_.empty() && keyframe_id <= ids_.back())
    throw Error("LoopDetector::add: keyframe ids must increase (" + std::to_string(keyframe_id) +
                " after " + std::to_string(ids_.back()) + ")");
  ids_.push_back(keyframe_id);
  descriptors_.push_back(descriptors.clone());
}

size_t LoopDetector::size() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return ids_.size();
}

std::vector<LoopDetector::Candidate> LoopDetector::query(const cv::Mat& descriptors,
                                                         int max_keyframe_id,
                                                         int max_candidates) const {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<Candidate> out;
  if (descriptors.empty() || ids_.empty()) return out;
  // Only keyframes up to max_keyframe_id are indexed: otherwise the query's own descriptors and
  // its recent neighbours would be every descriptor's nearest neighbour and take all the votes.
  const size_t prefix = static_cast<size_t>(
      std::upper_bound(ids_.begin(), ids_.end(), max_keyframe_id) - ids_.begin());
  if (prefix == 0) return out;
  if (!matcher_ || indexed_ != prefix) {
    // FLANN's LSH index cannot grow in place through OpenCV, so a stale one is rebuilt.
    matcher_ = std::make_unique<cv::FlannBasedMatcher>(
        cv::makePtr<cv::flann::LshIndexParams>(options_.lsh_tables, options_.lsh_key_bits,
                                               options_.lsh_multi_probe),
        cv::makePtr<cv::flann::SearchParams>());
    std::vector<cv::Mat> nonempty;
    std::vector<int> image_ids;
    for (size_t i = 0; i < prefix; ++i) {
      if (descriptors_[i].empty()) continue;
      nonempty.push_back(descriptors_[i]);
      image_ids.push_back(ids_[i]);
    }
    image_ids_ = image_ids;
    if (!nonempty.empty()) {
      matcher_->add(nonempty);
      matcher_->train();
    }
    indexed_ = prefix;
  }
  if (image_ids_.empty()) return out;
  // No ratio test: several keyframes see the same place, so the two nearest descriptors of a
  // good match often come from two keyframes and would cancel each other.
  std::vector<std::vector<cv::DMatch>> knn;
  matcher_->knnMatch(descriptors, knn, 1);
  std::map<int, int> votes;
  for (const auto& m : knn) {
    if (m.empty() || m[0].distance > options_.max_hamming) continue;
    ++votes[image_ids_[m[0].imgIdx]];
  }
  const int needed = std::max(options_.min_votes,
                              static_cast<int>(options_.min_vote_fraction * descriptors.rows));
  for (const auto& [id, count] : votes)
    if (count >= needed) out.push_back({id, count});
  std::sort(out.begin(), out.end(), [](const Candidate& a, const Candidate& b) {
    return a.votes != b.votes ? a.votes > b.votes : a.keyframe_id > b.keyframe_id;
  });
  if (static_cast<int>(out.size()) > max_candidates) out.resize(max_candidates);
  return out;
}

}  // namespace pf2
