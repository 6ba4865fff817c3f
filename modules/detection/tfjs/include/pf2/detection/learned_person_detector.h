#pragma once
// "learned": selfie masks (or video mattes, Options::segmenter) on every frame, MoveNet MultiPose boxes and keypoints every few frames,
// carried in between by the motion of the mask (the shift aligning the previous mask in a person's
// box with the current one). Only poses with enough confident keypoints count as people: the selfie
// model assumes someone is in view and marks blurred or plain scenes as "person" (on TUM fr1/rpy,
// often the whole image), so a mask alone is no evidence of a person. Each mask component is given
// to the people whose (enlarged) box it touches; a component touched by several people is split
// pixel by pixel to the person with the nearest confident keypoint, which separates touching people
// better than the mask alone. Components no person touches are dropped; a component larger than
// max_component_fraction of the image is cut to the boxes of the people touching it. People with no
// mask under them stay as boxes without a mask. A person's score is the mean mask probability when
// it has a mask, MoveNet's score otherwise (at least the share of confident keypoints of a pose
// seen whole). Components no person touches (and not implausibly
// large) are handed on as Detections::candidates; with candidate_poses, the large ones first get a
// second look for a pose on a crop around them. With crop_masks, the mask of each person the
// selfie mask covers badly is completed by PersonCropSegmenter on a crop around their pose.
#include <memory>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "pf2/detection/crop_segmenter.h"
#include "pf2/detection/human_detector.h"
#include "pf2/detection/movenet_detector.h"
#include "pf2/detection/pose_refiner.h"
#include "pf2/detection/selfie_segmenter.h"
#include "pf2/detection/video_matting.h"

namespace pf2 {

class LearnedPersonDetector : public HumanDetector {
 public:
  struct Options {
    // Where the person probability comes from: "selfie" (the selfie network, about 10 ms a frame)
    // or "rvm" (VideoMatting, about 85 ms at 320x240 on 2 cores: people's outlines without the
    // chairs and walls the selfie mask spreads onto, docs/learned_detection.md). Either way the
    // components are thresholded and filtered by `selfie`'s mask_threshold, min_area_fraction and
    // min_score.
    std::string segmenter = "selfie";
    VideoMatting::Options matting;
    SelfieSegmenter::Options selfie;
    MoveNetDetector::Options movenet;
    int pose_every = 3;                 // frames per MoveNet run (1 = every frame)
    float box_margin = 0.1f;            // fraction of a pose box's size added on each side when claiming mask
    float keypoint_min_score = 0.3f;    // a keypoint at least this score is "confident"
    // Confident keypoints a MoveNet pose needs to count as a person (and to claim mask). The people
    // of the real walking_xyz test frame have >= 8; MoveNet's best spurious pose on 120 frames of
    // TUM fr1/rpy (no people) has 3. 4 rather than 5: people cut by the border or blurred show few
    // (pf2_synth halfsphere: 89.5 % of person depth removed instead of 85.0; fr1/rpy: still no one).
    int min_pose_keypoints = 4;
    // A pose without mask with at least this many confident keypoints is seen whole, and scores at
    // least the share of its keypoints that are confident (MoveNet's own score weighs in its
    // centre's heat, which stays low for small people in dark clothes). Poses MoveNet puts beside
    // a person, on the wall above a seated one, show 12-13 (pf2_synth rpy). At least 1; above the
    // pose's keypoint count (17): never.
    int whole_pose_keypoints = 14;
    // A mask component larger than this fraction of the image is cut to the claimed boxes of the
    // people touching it (blur and plain walls make whole-image components).
    double max_component_fraction = 0.6;
    float max_motion = 32.f;            // largest image motion of a person between frames, pixels
    // Complete people's masks with PersonCropSegmenter, every frame, for each pose that is cut by
    // the image border or has a confident keypoint off the selfie mask: what the crop marks within
    // the person's claimed box joins their mask (a pose without mask gets one). Also for each
    // candidate cut by the border whose bounding box holds at least crop_candidate_min_area
    // pixels (MoveNet finds few of the people the border cuts): the crop around that box joins the
    // candidate's mask, which stays a candidate. Each crop costs about 0.7 of the selfie network's
    // time (crop.input_size 192), so off by default (not real time with two or three people); docs/learned_detection.md, "Crop
    // masks".
    bool crop_masks = false;
    PersonCropSegmenter::Options crop;
    int crop_candidate_min_area = 4000;  // pixels, >= 0: smaller candidates get no crop
    // Look again for a pose on each candidate (a mask component no confident pose touches) of at
    // least candidate_pose_min_area pixels, on the frames MoveNet runs: MoveNet on a square crop
    // around the candidate (PoseRefiner), where a person close to the lens or cut by the border
    // fills the input as the network expects. A pose found there with min_pose_keypoints confident
    // keypoints becomes a person.
    bool candidate_poses = false;
    int candidate_pose_min_area = 4000;     // pixels, >= 0
    // The crop's look: PoseRefiner's input and margin, but a pose need overlap the candidate's box
    // only by 0.3, not 0.5: the pose's box of a person cut by the border reaches beyond the image,
    // where the candidate's box stops.
    PoseRefiner::Options candidate_pose = [] {
      PoseRefiner::Options o;
      o.min_iou = 0.3;
      return o;
    }();
  };

  // Loads both models (and the crop model with crop_masks). Throws pf2::Error naming a
  // missing/unreadable model, an unknown segmenter, or if pose_every, min_pose_keypoints or
  // whole_pose_keypoints < 1, crop_candidate_min_area or candidate_pose_min_area < 0, or (with
  // candidate_poses) candidate_pose out of PoseRefiner's ranges.
  explicit LearnedPersonDetector(const Options& options);
  ~LearnedPersonDetector() override;

  std::string name() const override { return "learned"; }
  // NOT thread safe (networks and the pose history between frames).
  Detections detect(const Frame& frame) override;

 private:
  void carryPoses(const cv::Mat& mask);
  // The union of the crop masks of the current poses the selfie mask covers badly (image-sized
  // CV_8U).
  cv::Mat cropMasks(const cv::Mat& bgr, const cv::Mat& selfie_mask);
  // Adds its crop mask to each candidate cut by the image border and large enough.
  void cropCandidates(const cv::Mat& bgr, std::vector<PersonDetection>* candidates);
  // Adds to poses_ the poses found on crops around the large candidates the current poses leave.
  void findCandidatePoses(const cv::Mat& bgr, const std::vector<PersonDetection>& components,
                          const cv::Mat& probability);

  Options options_;
  std::unique_ptr<SelfieSegmenter> selfie_;   // one of these two, by options_.segmenter
  std::unique_ptr<VideoMatting> matting_;
  std::unique_ptr<MoveNetDetector> movenet_;
  std::unique_ptr<PersonCropSegmenter> crop_;  // only with options_.crop_masks
  std::unique_ptr<PoseRefiner> candidate_pose_;  // only with options_.candidate_poses
  std::vector<PersonDetection> poses_;  // latest MoveNet people, moved with the mask since
  cv::Mat previous_mask_;               // selfie mask of the previous frame (CV_8U)
  long frames_ = 0;
};

// The merge step of LearnedPersonDetector, separate so it can be tested without models: gives the
// selfie mask components (SelfieSegmenter::components) to the MoveNet poses with at least
// min_pose_keypoints confident keypoints, as described above (other poses and the components they
// leave are dropped); probability is the selfie probability image the components come from.
// With a non-null `unclaimed`, the components no confident pose touches and no larger than
// max_component_fraction of the image are appended to it (score: their mean probability), as
// candidates for Detections::candidates. Thread safe.
std::vector<PersonDetection> combineMasksAndPoses(const std::vector<PersonDetection>& components,
                                                 const std::vector<PersonDetection>& poses,
                                                 const cv::Mat& probability,
                                                 const LearnedPersonDetector::Options& options,
                                                 std::vector<PersonDetection>* unclaimed = nullptr);

// Adds crop_masks (image-sized CV_8U) within each posed person's claimed box (the box enlarged by
// box_margin of its size on each side) to that person's mask, giving a mask to a person without
// one. People without keypoints are left as they are. Box and score are unchanged. Thread safe.
void addCropMasks(const cv::Mat& crop_masks, float box_margin, std::vector<PersonDetection>* people);

}  // namespace pf2
