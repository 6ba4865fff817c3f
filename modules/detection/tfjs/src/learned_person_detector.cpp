#include "pf2/detection/learned_person_detector.h"

#include <algorithm>
#include <limits>

#include <opencv2/imgproc.hpp>

#include "pf2/core/error.h"

namespace pf2 {
namespace {

// The pixels a pose may claim: its box enlarged by box_margin of its size on each side.
cv::Rect claimRect(const PersonDetection& pose, float box_margin, cv::Size image) {
  const float mx = box_margin * pose.box.width(), my = box_margin * pose.box.height();
  const cv::Point ul(cvFloor(pose.box.x_ul - mx), cvFloor(pose.box.y_ul - my));
  const cv::Point lr(cvCeil(pose.box.x_lr + mx), cvCeil(pose.box.y_lr + my));
  return cv::Rect(ul, lr) & cv::Rect(cv::Point(0, 0), image);
}

int confidentKeypoints(const PersonDetection& pose, float min_score) {
  return static_cast<int>(std::count_if(pose.keypoints.begin(), pose.keypoints.end(),
                                        [min_score](const Keypoint2d& k) { return k.score >= min_score; }));
}

// A component several poses claim: each pixel to the owner with the nearest confident keypoint
// among those whose claim contains it (any owner if none does), set in that owner's pose mask.
void splitSharedComponent(const cv::Mat& mask, const PersonBox& box, const std::vector<size_t>& owners,
                          const std::vector<PersonDetection>& poses, const std::vector<cv::Rect>& claims,
                          float min_score, std::vector<cv::Mat>* pose_masks) {
  // Per owner its confident keypoints, and per row their squared vertical distances (the sum
  // below adds the same two float terms as the distance written out, so the result is the same).
  std::vector<std::vector<cv::Point2f>> keypoints(owners.size());
  for (size_t o = 0; o < owners.size(); ++o)
    for (const Keypoint2d& k : poses[owners[o]].keypoints)
      if (k.score >= min_score) keypoints[o].emplace_back(k.u, k.v);
  std::vector<std::vector<float>> dv2(owners.size());
  const int u0 = static_cast<int>(box.x_ul), u1 = static_cast<int>(box.x_lr);
  for (int v = static_cast<int>(box.y_ul); v < static_cast<int>(box.y_lr); ++v) {
    for (size_t o = 0; o < owners.size(); ++o) {
      dv2[o].resize(keypoints[o].size());
      for (size_t j = 0; j < keypoints[o].size(); ++j) dv2[o][j] = (keypoints[o][j].y - v) * (keypoints[o][j].y - v);
    }
    const uint8_t* in = mask.ptr<uint8_t>(v);
    for (int u = u0; u < u1; ++u) {
      if (!in[u]) continue;
      size_t best = owners[0];
      float best_d2 = std::numeric_limits<float>::max();
      bool best_inside = false;
      for (size_t o = 0; o < owners.size(); ++o) {
        const bool inside = claims[owners[o]].contains(cv::Point(u, v));
        if (best_inside && !inside) continue;
        float d2 = std::numeric_limits<float>::max();
        for (size_t j = 0; j < keypoints[o].size(); ++j)
          d2 = std::min(d2, (keypoints[o][j].x - u) * (keypoints[o][j].x - u) + dv2[o][j]);
        if ((inside && !best_inside) || d2 < best_d2) {
          best = owners[o];
          best_d2 = d2;
          best_inside = inside;
        }
      }
      (*pose_masks)[best].at<uint8_t>(v, u) = 255;
    }
  }
}

// Whether a box lies within 2 pixels of the edge of an image of `size`.
bool touchesBorder(const PersonBox& box, const cv::Size& size) {
  constexpr float kBorder = 2.f;
  return box.x_ul <= kBorder || box.y_ul <= kBorder || box.x_lr >= size.width - 1 - kBorder ||
         box.y_lr >= size.height - 1 - kBorder;
}

// Whether the selfie mask covers a pose badly: its box reaches the image border (the selfie
// network misses the cut person's limbs there) or one of its confident keypoints inside the image
// lies off the mask.
bool selfieMaskMisses(const PersonDetection& pose, const cv::Mat& selfie_mask, float min_score) {
  if (touchesBorder(pose.box, selfie_mask.size())) return true;
  for (const Keypoint2d& k : pose.keypoints) {
    const int u = cvRound(k.u), v = cvRound(k.v);
    if (k.score >= min_score && u >= 0 && v >= 0 && u < selfie_mask.cols && v < selfie_mask.rows &&
        selfie_mask.at<uint8_t>(v, u) == 0)
      return true;
  }
  return false;
}

}  // namespace

void addCropMasks(const cv::Mat& crop_masks, float box_margin, std::vector<PersonDetection>* people) {
  for (PersonDetection& person : *people) {
    if (person.keypoints.empty()) continue;
    const cv::Rect r = claimRect(person, box_margin, crop_masks.size());
    if (r.empty()) continue;
    if (person.mask.empty()) person.mask = cv::Mat(crop_masks.size(), CV_8U, cv::Scalar(0));
    cv::Mat claimed = person.mask(r);
    claimed |= crop_masks(r);
  }
}

std::vector<PersonDetection> combineMasksAndPoses(const std::vector<PersonDetection>& components,
                                                 const std::vector<PersonDetection>& all_poses,
                                                 const cv::Mat& probability,
                                                 const LearnedPersonDetector::Options& options,
                                                 std::vector<PersonDetection>* unclaimed) {
  // Only confident poses are people; the selfie mask alone is no evidence of one.
  std::vector<PersonDetection> poses;
  for (const PersonDetection& pose : all_poses)
    if (confidentKeypoints(pose, options.keypoint_min_score) >= options.min_pose_keypoints) poses.push_back(pose);
  std::vector<cv::Rect> claims;
  for (const PersonDetection& pose : poses) claims.push_back(claimRect(pose, options.box_margin, probability.size()));
  std::vector<cv::Mat> pose_masks(poses.size());
  for (cv::Mat& m : pose_masks) m = cv::Mat(probability.size(), CV_8U, cv::Scalar(0));
  const double max_area = options.max_component_fraction * static_cast<double>(probability.total());
  std::vector<PersonDetection> people;

  for (const PersonDetection& component : components) {
    std::vector<size_t> owners;
    for (size_t i = 0; i < poses.size(); ++i)
      if (!claims[i].empty() && cv::countNonZero(component.mask(claims[i])) > 0) owners.push_back(i);
    const bool too_large = cv::countNonZero(component.mask) > max_area;
    if (owners.empty()) {  // no person supports it: at most a candidate
      if (unclaimed && !too_large) {
        unclaimed->push_back(component);
        unclaimed->back().score = static_cast<float>(cv::mean(probability, component.mask)[0]);
      }
      continue;
    }
    cv::Mat mask = component.mask;
    if (too_large) {  // implausibly large: keep only what the people claim
      cv::Mat claimed(mask.size(), CV_8U, cv::Scalar(0));
      for (size_t i : owners) claimed(claims[i]).setTo(255);
      mask = cv::Mat();  // a new buffer: the caller's component stays as it was
      cv::bitwise_and(component.mask, claimed, mask);
    }
    if (owners.size() == 1) {
      pose_masks[owners[0]] |= mask;
      continue;
    }
    splitSharedComponent(mask, component.box, owners, poses, claims, options.keypoint_min_score, &pose_masks);
  }

  for (size_t i = 0; i < poses.size(); ++i) {
    PersonDetection person = poses[i];
    if (cv::countNonZero(pose_masks[i]) > 0) {
      person.mask = pose_masks[i];
      // The box must cover the mask the filter removes, and the body parts the mask missed.
      const cv::Rect r = cv::boundingRect(pose_masks[i]);
      person.box = {std::min(person.box.x_ul, static_cast<float>(r.x)), std::min(person.box.y_ul, static_cast<float>(r.y)),
                    std::max(person.box.x_lr, static_cast<float>(r.x + r.width)),
                    std::max(person.box.y_lr, static_cast<float>(r.y + r.height))};
      person.score = static_cast<float>(cv::mean(probability, person.mask)[0]);
    } else {
      // MoveNet's person score (centre heat x mean keypoint score) stays below 0.5 for people it
      // sees whole but small or in dark clothes (a seated person 3 m away with 15-17 of 17
      // keypoints confident: 0.43-0.49), and the filter uses boxes above 0.5. A pose seen whole
      // is a person whatever the centre's heat: it scores at least its share of confident keypoints.
      const int confident = confidentKeypoints(person, options.keypoint_min_score);
      if (confident >= options.whole_pose_keypoints)
        person.score = std::max(person.score, static_cast<float>(confident) / static_cast<float>(person.keypoints.size()));
    }
    people.push_back(std::move(person));
  }
  return people;
}

LearnedPersonDetector::LearnedPersonDetector(const Options& options) : options_(options) {
  if (options_.pose_every < 1) throw Error("learned detector: pose_every must be at least 1");
  if (options_.min_pose_keypoints < 1) throw Error("learned detector: min_pose_keypoints must be at least 1");
  if (options_.whole_pose_keypoints < 1) throw Error("learned detector: whole_pose_keypoints must be at least 1");
  if (options_.crop_candidate_min_area < 0) throw Error("learned detector: crop_candidate_min_area must be at least 0");
  if (options_.candidate_pose_min_area < 0) throw Error("learned detector: candidate_pose_min_area must be at least 0");
  if (options_.segmenter == "selfie") {
    selfie_ = std::make_unique<SelfieSegmenter>(options_.selfie);
  } else if (options_.segmenter == "rvm") {
    matting_ = std::make_unique<VideoMatting>(options_.matting);
  } else {
    throw Error("learned detector: segmenter '" + options_.segmenter + "' is not selfie or rvm");
  }
  movenet_ = std::make_unique<MoveNetDetector>(options_.movenet);
  if (options_.crop_masks) crop_ = std::make_unique<PersonCropSegmenter>(options_.crop);
  if (options_.candidate_poses) candidate_pose_ = std::make_unique<PoseRefiner>(options_.candidate_pose);
}

LearnedPersonDetector::~LearnedPersonDetector() = default;

// Between MoveNet runs a person moves as the mask under its box moves: the shift that best aligns
// the previous mask inside the box with the current mask (sum of squared differences, searched at
// half resolution, so to 2 px) moves box and keypoints.
void LearnedPersonDetector::carryPoses(const cv::Mat& mask) {
  if (previous_mask_.size() != mask.size()) return;
  constexpr double kScale = 0.5;
  const int radius = std::max(1, cvRound(options_.max_motion * kScale));
  cv::Mat before, now, padded;
  cv::resize(previous_mask_, before, cv::Size(), kScale, kScale, cv::INTER_AREA);
  cv::resize(mask, now, cv::Size(), kScale, kScale, cv::INTER_AREA);
  cv::copyMakeBorder(now, padded, radius, radius, radius, radius, cv::BORDER_CONSTANT, cv::Scalar(0));
  for (PersonDetection& pose : poses_) {
    const cv::Rect full = claimRect(pose, options_.box_margin, mask.size());
    const cv::Rect r = cv::Rect(cvFloor(full.x * kScale), cvFloor(full.y * kScale), cvCeil(full.width * kScale),
                                cvCeil(full.height * kScale)) & cv::Rect(cv::Point(0, 0), before.size());
    if (r.empty() || cv::countNonZero(before(r)) == 0) continue;
    cv::Mat cost;
    cv::matchTemplate(padded(cv::Rect(r.x, r.y, r.width + 2 * radius, r.height + 2 * radius)), before(r), cost,
                      cv::TM_SQDIFF);
    cv::Point best;
    cv::minMaxLoc(cost, nullptr, nullptr, &best, nullptr);
    const float du = static_cast<float>((best.x - radius) / kScale);
    const float dv = static_cast<float>((best.y - radius) / kScale);
    pose.box = {pose.box.x_ul + du, pose.box.y_ul + dv, pose.box.x_lr + du, pose.box.y_lr + dv};
    for (Keypoint2d& k : pose.keypoints) {
      k.u += du;
      k.v += dv;
    }
  }
}

cv::Mat LearnedPersonDetector::cropMasks(const cv::Mat& bgr, const cv::Mat& selfie_mask) {
  cv::Mat all(bgr.size(), CV_8U, cv::Scalar(0));
  for (const PersonDetection& pose : poses_) {
    if (confidentKeypoints(pose, options_.keypoint_min_score) < options_.min_pose_keypoints) continue;
    if (selfieMaskMisses(pose, selfie_mask, options_.keypoint_min_score)) all |= crop_->segment(bgr, pose.box);
  }
  return all;
}

void LearnedPersonDetector::cropCandidates(const cv::Mat& bgr, std::vector<PersonDetection>* candidates) {
  for (PersonDetection& candidate : *candidates) {  // a candidate's box bounds its mask component
    const PersonBox& box = candidate.box;
    if (candidate.mask.empty() || box.width() * box.height() < options_.crop_candidate_min_area ||
        !touchesBorder(box, bgr.size()))
      continue;
    candidate.mask |= crop_->segment(bgr, box);
  }
}

void LearnedPersonDetector::findCandidatePoses(const cv::Mat& bgr, const std::vector<PersonDetection>& components,
                                               const cv::Mat& probability) {
  // The candidates are what the merge with this frame's poses leaves; only their boxes are used
  // here, and the merge runs again in detect() once the poses found on them have joined.
  std::vector<PersonDetection> candidates;
  combineMasksAndPoses(components, poses_, probability, options_, &candidates);
  for (const PersonDetection& candidate : candidates) {
    if (cv::countNonZero(candidate.mask) < options_.candidate_pose_min_area) continue;
    PersonDetection pose;
    if (candidate_pose_->find(bgr, candidate.box, &pose) &&
        confidentKeypoints(pose, options_.keypoint_min_score) >= options_.min_pose_keypoints)
      poses_.push_back(std::move(pose));
  }
}

Detections LearnedPersonDetector::detect(const Frame& frame) {
  const cv::Mat probability = matting_ ? matting_->alpha(frame.rgb) : selfie_->probability(frame.rgb);
  const std::vector<PersonDetection> components = maskComponents(probability, options_.selfie);
  cv::Mat mask(probability.size(), CV_8U, cv::Scalar(0));
  for (const PersonDetection& c : components) mask |= c.mask;

  if (frames_ % options_.pose_every == 0) {
    poses_ = movenet_->detect(frame).people;
    if (candidate_pose_) findCandidatePoses(frame.rgb, components, probability);
  } else {
    carryPoses(mask);
  }
  ++frames_;
  previous_mask_ = mask;

  Detections result;
  result.timestamp = frame.timestamp;
  result.people = combineMasksAndPoses(components, poses_, probability, options_, &result.candidates);
  if (crop_) {
    addCropMasks(cropMasks(frame.rgb, mask), options_.box_margin, &result.people);
    cropCandidates(frame.rgb, &result.candidates);
  }
  return result;
}

}  // namespace pf2
