#pragma once
// Appearance-based loop and relocalisation candidates: the ORB descriptors of all keyframes in a
// FLANN LSH index (multi-probe locality-sensitive hashing on Hamming space); a query's
// descriptors vote, through ratio-tested nearest neighbours, for the keyframes they come from.
// Candidates are only proposals: the caller verifies them geometrically (RgbdOdometry).
#include <memory>
#include <mutex>
#include <vector>

#include <opencv2/core.hpp>

namespace cv {
class DescriptorMatcher;
}

namespace pf2 {

class LoopDetector {
 public:
  struct Options {
    int lsh_tables = 8;         // LSH hash tables
    int lsh_key_bits = 16;      // bits per hash key
    int lsh_multi_probe = 1;    // neighbouring buckets probed
    int max_hamming = 50;       // bits; farther neighbours do not vote
    int min_votes = 25;         // fewer votes -> not a candidate
    double min_vote_fraction = 0.05;  // votes / query descriptors below this -> not a candidate
  };

  struct Candidate {
    int keyframe_id = -1;
    int votes = 0;
  };

  LoopDetector();
  explicit LoopDetector(const Options& options);
  ~LoopDetector();

  // Adds a keyframe's descriptors (CV_8U ORB rows; empty is allowed and never matches). Ids must
  // increase from call to call (throws pf2::Error otherwise). The index is rebuilt lazily at the
  // next query. Thread safe.
  void add(int keyframe_id, const cv::Mat& descriptors);
  size_t size() const;

  // Up to max_candidates keyframes with id <= max_keyframe_id, most votes first. Thread safe
  // (queries are serialised). The index holds the keyframes up to max_keyframe_id and is rebuilt
  // when that set changed since the last query (a few ms per 100 keyframes).
  std::vector<Candidate> query(const cv::Mat& descriptors, int max_keyframe_id,
                               int max_candidates) const;

 private:
  Options options_;
  mutable std::mutex mutex_;
  std::vector<int> ids_;             // keyframe id per stored image
  std::vector<cv::Mat> descriptors_;
  mutable std::unique_ptr<cv::DescriptorMatcher> matcher_;
  mutable size_t indexed_ = 0;       // images (a prefix of ids_) in the built index
  mutable std::vector<int> image_ids_;  // keyframe id per image of the built index
};

}  // namespace pf2
