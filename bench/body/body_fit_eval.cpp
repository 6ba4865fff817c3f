// pf2_body_fit_eval: BodyFitter against a pf2_synth sequence's ground-truth joints. For every k-th
// frame and every person in view (gt/boxes.txt), keypoints come either from the ground-truth joints
// (gt/joints.txt) projected into the camera (groundtruth.txt pose) through the fitter's COCO table,
// or from the `learned` detector's MoveNet poses matched to the people by box IoU; the person's
// depth is the frame's depth under the person's mask (gt/masks, or the detector's mask). Errors in
// the camera frame: MPJPE over the 24 joints, after root (pelvis) alignment, and after a similarity
// alignment (PA-MPJPE).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <map>
#include <random>
#include <sstream>
#include <utility>

#include <Eigen/Geometry>
#include <opencv2/imgcodecs.hpp>

#include "pf2/body/body_fitter.h"
#include "pf2/core/command_line.h"
#include "pf2/core/error.h"
#include "pf2/core/median.h"
#include "pf2/core/text_lines.h"
#include "pf2/detection/detector_factory.h"
#include "pf2/detection/pose_refiner.h"
#include "pf2/eval/body_metrics.h"
#include "pf2/detection/gt_detector.h"
#include "pf2/io/trajectory_io.h"
#include "pf2/io/tum_sequence.h"

namespace {

const char* kUsage =
    "Usage: pf2_body_fit_eval SEQUENCE_DIR [--every K] [--noise PX] [--detector gt|learned]\n"
    "                         [--min-visible F] [--temporal] [--no-depth] [--frames N] [--json]\n"
    "                         [--no-keypoint-offsets] [--no-side-views] [--no-surface-alignment]\n"
    "                         [--surface-quantile Q]\n"
    "                         [--weight-depth W] [--weight-pose W] [--weight-shape W] [--weight-upright W]\n"
    "                         [--refine] [--refine-input PX] [--refine-margin M]\n"
    "Fits the body model to every person in view (gt/boxes.txt, visible fraction >= F, default 0.3)\n"
    "in every K-th frame (default 10) of a pf2_synth sequence and scores the fitted joints against\n"
    "gt/joints.txt in the camera frame. --detector gt (default): keypoints are the ground-truth\n"
    "joints projected into the image (outside the image or hidden behind something else = missing),\n"
    "plus Gaussian noise of PX pixels; learned: MoveNet keypoints of the `learned` detector, matched\n"
    "to people by box IoU >= 0.3. --temporal starts each fit from the same person's previous fit.\n"
    "--no-depth fits the keypoints alone. --weight-* override BodyFitter::Options. The fitter places\n"
    "MoveNet's keypoints beside their joints (CocoJointLink::offset) unless --no-keypoint-offsets;\n"
    "with --detector gt, whose keypoints are the joints themselves, never. --no-side-views keeps every\n"
    "depth term two-sided (BodyFitter::Options::side_view_separation 0). --no-surface-alignment leaves\n"
    "each fit where the solver put it (BodyFitter::Options::surface_alignment false); --surface-quantile\n"
    "sets the quantile of the torso's depth differences it moves the body to (BodySurfaceAligner::Options::\n"
    "quantile, default 0.6, 0.5 = median). --refine (learned\n"
    "only): each person's keypoints from MoveNet run again on a crop around them (PoseRefiner; its input side and\n"
    "margin by --refine-input and --refine-margin), as pf2_slam does before its fits.\n";

using Joints = pf2::BodyJoints;
long long micros(double stamp) { return pf2::timestampMicros(stamp); }

// The people in view of each frame (gt/boxes.txt), by timestamp in microseconds.
std::map<long long, std::vector<pf2::GroundTruthBox>> readBoxes(const std::string& path) {
  std::map<long long, std::vector<pf2::GroundTruthBox>> boxes;
  for (const pf2::GroundTruthBox& b : pf2::readGroundTruthBoxes(path)) boxes[micros(b.timestamp)].push_back(b);
  return boxes;
}

double iou(const cv::Rect2d& a, const cv::Rect2d& b) {
  const double inter = (a & b).area();
  return inter > 0 ? inter / (a.area() + b.area() - inter) : 0.0;
}

// Keypoints from ground-truth joints: projected through the COCO table; missing when behind the
// camera, outside the image, or hidden (the pixel shows something else more than 15 cm in front of
// the joint's surface).
pf2::BodyFitInput projectedKeypoints(const Joints& joints_c, int id, const cv::Mat& labels, const cv::Mat& depth,
                                     const pf2::CameraIntrinsics& K, double noise_px, std::mt19937* rng) {
  std::normal_distribution<double> noise(0.0, 1.0);
  pf2::BodyFitInput input;
  for (int k = 0; k < pf2::kCocoKeypointCount; ++k) {
    const int joint = pf2::kCocoToBodyJoint[k].joint;
    if (joint < 0 || joints_c[joint].z() < 0.1) continue;
    const Eigen::Vector2d px = K.project(joints_c[joint]);
    const int u = static_cast<int>(std::lround(px.x())), v = static_cast<int>(std::lround(px.y()));
    if (u < 0 || v < 0 || u >= K.width || v >= K.height) continue;
    const float z = depth.at<float>(v, u);
    const bool hidden = labels.at<uint16_t>(v, u) != id && z > 0 && z < joints_c[joint].z() - 0.25;
    if (hidden) continue;
    input.keypoints[k] = {px.x() + noise_px * noise(*rng), px.y() + noise_px * noise(*rng), 1.0};
  }
  return input;
}

std::vector<Eigen::Vector3d> maskedPoints(const cv::Mat& depth, const cv::Mat& mask, const pf2::CameraIntrinsics& K) {
  cv::Mat person(depth.size(), CV_32F, cv::Scalar(0));
  depth.copyTo(person, mask);
  return pf2::depthPointsFromImage(person, K, 2);
}

double mean(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return v.empty() ? 0.0 : s / v.size();
}
double median(std::vector<double> v) { return pf2::upperMedian(&v); }

int run(int argc, char** argv) {
  pf2::CommandLine cli(argc, argv);
  if (cli.helpRequested()) {
    std::cout << kUsage;
    return 0;
  }
  const int every = cli.integer("--every", 10);
  const double noise_px = cli.number("--noise", 0.0);
  const std::string detector_name = cli.value("--detector", "gt");
  const double min_visible = cli.number("--min-visible", 0.3);
  const bool temporal = cli.flag("--temporal");
  const bool no_depth = cli.flag("--no-depth");
  const int max_frames = cli.integer("--frames", 0);
  const bool json = cli.flag("--json");
  const bool refine = cli.flag("--refine");
  pf2::BodyFitter::Options fit_options;
  fit_options.weight_depth = cli.number("--weight-depth", fit_options.weight_depth);
  fit_options.weight_pose = cli.number("--weight-pose", fit_options.weight_pose);
  fit_options.weight_shape = cli.number("--weight-shape", fit_options.weight_shape);
  fit_options.weight_upright = cli.number("--weight-upright", fit_options.weight_upright);
  fit_options.keypoint_offsets = !cli.flag("--no-keypoint-offsets");
  if (cli.flag("--no-side-views")) fit_options.side_view_separation = 0;
  fit_options.surface_alignment = !cli.flag("--no-surface-alignment");
  fit_options.surface.quantile = cli.number("--surface-quantile", fit_options.surface.quantile);
  const auto positionals = cli.positionals();
  if (positionals.size() != 1) throw pf2::Error("expected SEQUENCE_DIR (see -h)");
  if (every < 1 || noise_px < 0) throw pf2::Error("--every must be >= 1 and --noise >= 0");
  if (detector_name != "gt" && detector_name != "learned") throw pf2::Error("--detector must be gt or learned");
  if (detector_name == "gt") fit_options.keypoint_offsets = false;
  if (refine && detector_name != "learned") throw pf2::Error("--refine needs --detector learned");
  const std::string folder = positionals[0];

  const pf2::TumSequence sequence(folder);
  const pf2::CameraIntrinsics K = sequence.intrinsics();
  const pf2::Trajectory ground_truth = sequence.groundTruth();
  if (ground_truth.empty()) throw pf2::fileError(folder + "/groundtruth.txt", "no ground-truth poses");
  const auto joints_w = pf2::readGroundTruthJoints(folder + "/gt/joints.txt");
  const auto boxes = readBoxes(folder + "/gt/boxes.txt");

  std::unique_ptr<pf2::HumanDetector> detector;
  if (detector_name == "learned") {
    pf2::DetectorOptions options;
    options.extra["learned.pose_every"] = "1";  // fresh MoveNet keypoints on every evaluated frame
    detector = pf2::createHumanDetector("learned", options);
  }
  std::unique_ptr<pf2::PoseRefiner> refiner;
  pf2::PoseRefiner::Options refine_options;
  refine_options.input_size = cli.integer("--refine-input", refine_options.input_size);
  refine_options.margin = cli.number("--refine-margin", refine_options.margin);
  if (refine) refiner = std::make_unique<pf2::PoseRefiner>(refine_options);

  const pf2::BodyModel model = pf2::BodyModel::loadDefault();
  const pf2::BodyFitter fitter(model, fit_options);
  std::mt19937 rng(1);
  struct PreviousFit {
    std::size_t frame;
    Eigen::Isometry3d T_w_c;
    pf2::BodyParameters body_c;
  };
  std::map<int, PreviousFit> previous;  // by person id
  pf2::BodyParameters warm_start;
  std::vector<double> mpjpe, aligned, procrustes, fit_ms;
  std::array<std::vector<double>, pf2::kBodyJointCount> joint_errors;  // mm, per joint
  // Signed pelvis error in the fitted body's frame (x to its left, y up, z forward), mm: the bias
  // a keypoint convention or the depth table leaves.
  Eigen::Vector3d pelvis_bias_sum = Eigen::Vector3d::Zero();
  int person_frames = 0, no_keypoints = 0, invalid = 0, unmatched = 0;

  const std::size_t frames = max_frames > 0 ? std::min<std::size_t>(max_frames, sequence.size()) : sequence.size();
  for (std::size_t i = 0; i < frames; i += every) {
    const double stamp = sequence.timestamp(i);
    const auto in_view = boxes.find(micros(stamp));
    if (in_view == boxes.end()) continue;
    Eigen::Isometry3d T_w_c;
    if (!pf2::interpolateAt(ground_truth, stamp, 0.02, &T_w_c)) continue;
    const Eigen::Isometry3d T_c_w = T_w_c.inverse();
    const pf2::Frame frame = sequence.frame(i);
    const std::string depth_file = sequence.files(i).depth.file;
    const std::string mask_path = folder + "/gt/masks/" + depth_file.substr(depth_file.find_last_of('/') + 1);
    const cv::Mat labels = cv::imread(mask_path, cv::IMREAD_UNCHANGED);
    if (labels.type() != CV_16UC1 || labels.size() != frame.depth.size()) {
      throw pf2::fileError(mask_path, "missing, or not a 16-bit mask of the depth image's size");
    }
    pf2::Detections detections;
    if (detector) detections = detector->detect(frame);
    std::vector<bool> taken(detections.people.size(), false);

    for (const pf2::GroundTruthBox& person : in_view->second) {
      if (person.visible_fraction < min_visible) continue;
      const auto truth = joints_w.find({micros(stamp), person.id});
      if (truth == joints_w.end()) throw pf2::fileError(folder + "/gt/joints.txt", "no joints for a person in view");
      ++person_frames;
      Joints joints_c;
      for (int j = 0; j < pf2::kBodyJointCount; ++j) joints_c[j] = T_c_w * truth->second[j];

      pf2::BodyFitInput input;
      cv::Mat mask = labels == person.id;
      if (!detector) {
        input = projectedKeypoints(joints_c, person.id, labels, frame.depth, K, noise_px, &rng);
      } else {
        // Greedy: the unmatched detection with the largest IoU.
        int best = -1;
        double best_iou = 0.3;
        for (std::size_t d = 0; d < detections.people.size(); ++d) {
          const pf2::PersonBox& b = detections.people[d].box;
          const double o = iou(cv::Rect2d(person.box.x_ul, person.box.y_ul, person.box.width(), person.box.height()),
                               cv::Rect2d(b.x_ul, b.y_ul, b.width(), b.height()));
          if (!taken[d] && o >= best_iou && detections.people[d].keypoints.size() == pf2::kCocoKeypointCount) {
            best = static_cast<int>(d), best_iou = o;
          }
        }
        if (best < 0) {
          ++unmatched;
          continue;
        }
        taken[best] = true;
        const pf2::PersonDetection& d = detections.people[best];
        std::vector<pf2::Keypoint2d> keypoints = d.keypoints;
        if (refiner) refiner->refine(frame.rgb, d.box, &keypoints);
        for (int k = 0; k < pf2::kCocoKeypointCount; ++k) {
          input.keypoints[k] = {keypoints[k].u, keypoints[k].v, keypoints[k].score};
        }
        if (!d.mask.empty()) mask = d.mask > 0;
      }
      if (!no_depth) input.points_c = maskedPoints(frame.depth, mask, K);
      input.up_c = T_c_w.linear() * Eigen::Vector3d::UnitZ();  // the synthetic world is z up
      const auto prev = previous.find(person.id);
      if (temporal && prev != previous.end() && prev->second.frame + every == i) {
        // The previous fit moved into this frame's camera (ground-truth camera motion).
        const pf2::BodyParameters& body = prev->second.body_c;
        warm_start = pf2::bodyToWorld(body, T_c_w * prev->second.T_w_c, model.restJoints(body.shape)[0]);
        input.previous = &warm_start;
      }
      const auto start = std::chrono::steady_clock::now();
      const pf2::BodyFitResult fit = fitter.fit(input, K);
      fit_ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
      if (!fit.valid) {
        ++(fit.keypoints_used < fitter.options().min_keypoints ? no_keypoints : invalid);
        previous.erase(person.id);
        continue;
      }
      previous[person.id] = {i, T_w_c, fit.parameters};
      double e = 0, a = 0;
      for (int j = 0; j < pf2::kBodyJointCount; ++j) {
        e += (fit.joints_c[j] - joints_c[j]).norm();
        joint_errors[j].push_back(1000 * (fit.joints_c[j] - joints_c[j]).norm());
        a += ((fit.joints_c[j] - fit.joints_c[0]) - (joints_c[j] - joints_c[0])).norm();
      }
      mpjpe.push_back(1000 * e / pf2::kBodyJointCount);
      const Eigen::AngleAxisd root(fit.parameters.pose[0].norm(), fit.parameters.pose[0].normalized());
      pelvis_bias_sum += 1000 * (root.toRotationMatrix().transpose() * (fit.joints_c[0] - joints_c[0]));
      // PA-MPJPE: after the similarity (rotation, translation, scale) that best aligns the fitted
      // joints to the true ones (Umeyama).
      Eigen::Matrix<double, 3, pf2::kBodyJointCount> fitted, truth_c;
      for (int j = 0; j < pf2::kBodyJointCount; ++j) fitted.col(j) = fit.joints_c[j], truth_c.col(j) = joints_c[j];
      const Eigen::Matrix4d S = Eigen::umeyama(fitted, truth_c, true);
      const Eigen::Matrix<double, 3, pf2::kBodyJointCount> moved =
          (S.topLeftCorner<3, 3>() * fitted).colwise() + S.topRightCorner<3, 1>();
      procrustes.push_back(1000 * (moved - truth_c).colwise().norm().mean());
      aligned.push_back(1000 * a / pf2::kBodyJointCount);
    }
  }

  char noise_text[64] = "";
  if (!detector) std::snprintf(noise_text, sizeof noise_text, " + noise %.1f px", noise_px);
  std::printf("keypoints %s%s, offsets %s, side views %s, depth %s, %s start: person-frames %d (visible >= %.2f, "
              "every %d-th frame)\n",
              detector ? "learned (MoveNet)" : "gt-projected", noise_text, fit_options.keypoint_offsets ? "on" : "off",
              fit_options.side_view_separation > 0 ? "one-sided" : "two-sided", no_depth ? "off" : "on",
              temporal ? "temporal" : "eq. 2", person_frames, min_visible, every);
  std::printf("fitted %zu, too few keypoints %d, other invalid %d, unmatched %d\n", mpjpe.size(), no_keypoints,
              invalid, unmatched);
  if (mpjpe.empty()) {
    std::printf("no fitted person: no errors\n");
  } else {
    std::printf("MPJPE camera frame: mean %.1f  median %.1f mm\n", mean(mpjpe), median(mpjpe));
    std::printf("MPJPE root-aligned: mean %.1f  median %.1f mm\n", mean(aligned), median(aligned));
    std::printf("PA-MPJPE (similarity-aligned): mean %.1f  median %.1f mm\n", mean(procrustes), median(procrustes));
    const Eigen::Vector3d bias = pelvis_bias_sum / static_cast<double>(mpjpe.size());
    std::printf("pelvis signed error, body frame (x left, y up, z forward): mean %.1f %.1f %.1f mm\n", bias.x(),
                bias.y(), bias.z());
    std::printf("per joint, median mm (camera frame):");
    for (int j = 0; j < pf2::kBodyJointCount; ++j) {
      std::printf(" %s %.0f", pf2::kBodyJointNames[j], median(joint_errors[j]));
    }
    std::printf("\n");
  }
  std::printf("fit time: median %.2f  mean %.2f ms\n", median(fit_ms), mean(fit_ms));
  if (json) {
    std::printf("{\"person_frames\":%d,\"fitted\":%zu,\"too_few_keypoints\":%d,\"invalid\":%d,\"unmatched\":%d,"
                "\"mpjpe_mean_mm\":%.2f,\"mpjpe_median_mm\":%.2f,\"aligned_mean_mm\":%.2f,"
                "\"aligned_median_mm\":%.2f,\"pa_mean_mm\":%.2f,\"pa_median_mm\":%.2f,\"fit_median_ms\":%.3f}\n",
                person_frames, mpjpe.size(), no_keypoints, invalid, unmatched, mean(mpjpe), median(mpjpe),
                mean(aligned), median(aligned), mean(procrustes), median(procrustes), median(fit_ms));
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return pf2::runApp("pf2_body_fit_eval", run, argc, argv); }
