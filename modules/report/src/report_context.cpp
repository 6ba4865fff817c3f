#include "report_context.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>

#include "html_text.h"

namespace pf2 {
namespace report {

namespace {

// Poses with a finite time and matrix, sorted by time: what the alignment and the plots can use.
Trajectory usablePoses(const Trajectory& poses) {
  Trajectory out;
  for (const StampedPose& pose : poses) {
    if (std::isfinite(pose.timestamp) && pose.T_w_c.matrix().allFinite()) out.push_back(pose);
  }
  std::stable_sort(out.begin(), out.end(),
                   [](const StampedPose& a, const StampedPose& b) { return a.timestamp < b.timestamp; });
  return out;
}

std::vector<Eigen::Vector3d> positions(const Trajectory& poses) {
  std::vector<Eigen::Vector3d> out;
  for (const StampedPose& pose : poses) out.push_back(pose.T_w_c.translation());
  return out;
}

// The first frame's time; the first pose's when no frame has a status; 0 without either.
double timeOrigin(const RunReportInput& input) {
  double t = std::numeric_limits<double>::infinity();
  for (const auto& [timestamp, status] : input.result->frame_status) {
    if (std::isfinite(timestamp)) t = std::min(t, timestamp);
  }
  for (const StampedPose& pose : input.result->trajectory) {
    if (std::isfinite(pose.timestamp)) t = std::min(t, pose.timestamp);
  }
  return std::isfinite(t) ? t : 0.0;
}

// The world's vertical axis when the cameras agree on one: the axis along which their image
// "down" (camera y) points on average, if clearly (pf2_synth: z; Bonn and the estimate's own
// world: y); -1 otherwise (TUM fr1/desk looks down at a desk, fr1/rpy rolls: about 0.77).
// *up_sign: +1 when up is the axis' positive direction.
int upAxis(const Trajectory& poses, double* up_sign) {
  if (poses.empty()) return -1;
  Eigen::Vector3d down = Eigen::Vector3d::Zero();
  for (const StampedPose& pose : poses) down += pose.T_w_c.linear().col(1) / static_cast<double>(poses.size());
  Eigen::Index axis = 0;
  const double along = down.cwiseAbs().maxCoeff(&axis);
  *up_sign = down[axis] > 0.0 ? -1.0 : 1.0;
  return down.norm() > 0.5 && along > 0.8 * down.norm() ? static_cast<int>(axis) : -1;
}

// Seen from above, u to the right and v up the page must give u x v = up (out of the page);
// otherwise the picture is the view from below, mirrored, and v is drawn negated.
bool mirrored(int axis_u, int axis_v, int up_axis, double up_sign) {
  const Eigen::Vector3d out = Eigen::Vector3d::Unit(axis_u).cross(Eigen::Vector3d::Unit(axis_v));
  return out[up_axis] * up_sign < 0.0;
}

// The view plane: the two axes across the vertical one, so the view is from above; without a
// clear vertical, the two axes along which the positions spread most (by variance for the ground
// truth, by extent for the estimate, whose brief excursions count). In x, y, z order.
void chooseAxes(const Trajectory& poses, bool by_variance, TopView* view) {
  if (poses.empty()) return;
  double up_sign = 1.0;
  view->up_axis = upAxis(poses, &up_sign);
  view->flip_v = false;
  Eigen::Vector3d spread = Eigen::Vector3d::Zero();
  if (view->up_axis >= 0) {
    spread[view->up_axis] = -1.0;  // the other two win
  } else {
    const std::vector<Eigen::Vector3d> points = positions(poses);
    Eigen::Vector3d lo = points.front(), hi = points.front(), mean = Eigen::Vector3d::Zero();
    for (const Eigen::Vector3d& p : points) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
      mean += p / static_cast<double>(points.size());
    }
    spread = hi - lo;
    if (by_variance) {
      spread.setZero();
      for (const Eigen::Vector3d& p : points) spread += (p - mean).cwiseAbs2();
    }
  }
  int order[3] = {0, 1, 2};
  std::stable_sort(order, order + 3, [&](int a, int b) { return spread[a] > spread[b]; });
  view->axis_u = std::min(order[0], order[1]);
  view->axis_v = std::max(order[0], order[1]);
  if (view->up_axis >= 0) view->flip_v = mirrored(view->axis_u, view->axis_v, view->up_axis, up_sign);
}

// computeAte on the usable poses; on success the view carries the estimate into the ground
// truth's world, otherwise ate_note says why the ground truth was not used.
void alignToGroundTruth(ReportContext* context) {
  const Trajectory& gt = context->ground_truth;
  const Trajectory& estimate = context->estimate;
  if (gt.empty() || estimate.empty()) {
    context->ate_note = gt.empty() ? "the ground truth has no usable poses" : "no estimated poses to compare";
    return;
  }
  try {
    context->ate = computeAte(gt, estimate);
  } catch (const std::exception& error) {
    context->ate_note = error.what();
    return;
  }
  const AteResult& ate = context->ate;
  if (!ate.rotation.allFinite() || !ate.translation_offset.allFinite() || !std::isfinite(ate.scale)) {
    context->ate_note = "the alignment to the ground truth is degenerate";
    return;
  }
  context->has_ate = true;
  context->view.rotation = ate.rotation;
  context->view.offset = ate.translation_offset;
  context->view.scale = ate.scale;
  chooseAxes(gt, true, &context->view);
}

}  // namespace

std::string TopView::axisLabel(int axis) const {
  static const char* const kNames[] = {"x (m)", "y (m)", "z (m)"};
  return kNames[std::clamp(axis, 0, 2)];
}

ReportContext makeContext(const RunReportInput& input) {
  ReportContext context;
  context.input = &input;
  context.result = input.result;
  context.estimate = usablePoses(input.result->trajectory);
  if (input.ground_truth) context.ground_truth = usablePoses(*input.ground_truth);
  context.t0 = timeOrigin(input);
  chooseAxes(context.estimate, false, &context.view);
  if (input.ground_truth) alignToGroundTruth(&context);
  return context;
}

std::string statusColour(TrackStatus status) {
  switch (status) {
    case TrackStatus::kOk: return "#3fb950";
    case TrackStatus::kBridged: return "#f0883e";
    case TrackStatus::kRelocalised: return "#58a6ff";
    case TrackStatus::kLost: return "#f85149";
  }
  return "#8b949e";
}

const char* statusName(TrackStatus status) { return toString(status); }

const std::vector<TrackStatus>& allStatuses() {
  static const std::vector<TrackStatus> kAll = {TrackStatus::kOk, TrackStatus::kBridged,
                                                TrackStatus::kRelocalised, TrackStatus::kLost};
  return kAll;
}

std::vector<Eigen::Vector2d> breakAtGaps(const std::vector<double>& times,
                                         const std::vector<Eigen::Vector2d>& points) {
  std::vector<double> steps;
  for (size_t k = 1; k < times.size(); ++k) steps.push_back(times[k] - times[k - 1]);
  const double gap = 3.0 * percentile(steps, 50.0);
  std::vector<Eigen::Vector2d> out;
  for (size_t k = 0; k < points.size(); ++k) {
    if (k > 0 && k < times.size() && gap > 0.0 && times[k] - times[k - 1] > gap) {
      out.push_back(Eigen::Vector2d::Constant(std::numeric_limits<double>::quiet_NaN()));
    }
    out.push_back(points[k]);
  }
  return out;
}

std::string section(const std::string& id, const std::string& title, const std::string& body) {
  return "<section id=\"" + escapeHtml(id) + "\">\n<h2>" + escapeHtml(title) + "</h2>\n" + body + "</section>\n";
}

std::string note(const std::string& text) { return "<p class=\"note\">" + escapeHtml(text) + "</p>\n"; }

}  // namespace report
}  // namespace pf2
