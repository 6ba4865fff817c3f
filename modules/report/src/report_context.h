#pragma once
// What the report's sections share: the time origin, the alignment to the ground truth and the
// plane of the top views, computed once per page; and the section functions themselves.
#include <string>
#include <vector>

#include <Eigen/Core>

#include "pf2/eval/trajectory_metrics.h"
#include "pf2/registration/tracker.h"
#include "pf2/report/run_report.h"

namespace pf2 {
namespace report {

// The plane the top views are drawn on and the similarity that carries the estimate's world into
// the ground truth's (identity without ground truth).
struct TopView {
  int axis_u = 0, axis_v = 1;
  int up_axis = -1;  // the vertical the plane is across, -1: chosen by the positions' spread
  bool flip_v = false;  // v drawn negated, so the view is from above, not mirrored from below
  double scale = 1.0;
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();

  // A point of the estimate's world (camera, people) in the view's world.
  Eigen::Vector3d fromEstimate(const Eigen::Vector3d& p) const { return scale * (rotation * p) + offset; }
  // A point of the view's world on the view's plane.
  Eigen::Vector2d project(const Eigen::Vector3d& p) const { return {p[axis_u], flip_v ? -p[axis_v] : p[axis_v]}; }
  // "x (m)" for an axis; vLabel() says "-z (m)" when v is flipped.
  std::string axisLabel(int axis) const;
  std::string uLabel() const { return axisLabel(axis_u); }
  std::string vLabel() const { return (flip_v ? "-" : "") + axisLabel(axis_v); }
};

struct ReportContext {
  const RunReportInput* input = nullptr;
  const SlamResult* result = nullptr;
  Trajectory estimate;     // the result's poses with finite values, sorted by time
  Trajectory ground_truth; // the same of the ground truth (empty without)
  double t0 = 0.0;         // time origin of every time axis: the first frame's timestamp
  bool has_ate = false;    // ground truth given and associated with the estimate
  AteResult ate;
  std::string ate_note;    // why given ground truth was not used (empty otherwise)
  TopView view;
};

ReportContext makeContext(const RunReportInput& input);

// One colour and name per tracking status, the same in every section.
std::string statusColour(TrackStatus status);
const char* statusName(TrackStatus status);
// The statuses in the order the page lists them.
const std::vector<TrackStatus>& allStatuses();

// Seconds since the context's time origin.
inline double relativeTime(const ReportContext& context, double timestamp) { return timestamp - context.t0; }

// points with a non-finite point inserted wherever consecutive times lie more than three typical
// (median) intervals apart, so a line breaks where tracking was lost or a person unseen instead
// of jumping straight across. times: one per point, increasing.
std::vector<Eigen::Vector2d> breakAtGaps(const std::vector<double>& times,
                                         const std::vector<Eigen::Vector2d>& points);

// <section id=..><h2>title</h2>body</section>
std::string section(const std::string& id, const std::string& title, const std::string& body);
// <p class="note">text</p>, text escaped.
std::string note(const std::string& text);

// The page's sections, in page order; each returns HTML.
std::string summarySection(const ReportContext& context);
std::string stageSection(const ReportContext& context);
std::string trajectorySection(const ReportContext& context);
std::string errorSection(const ReportContext& context);
std::string statusSection(const ReportContext& context);
std::string peopleSection(const ReportContext& context);
std::string detectorSection(const ReportContext& context);
std::string settingsSection(const ReportContext& context);

}  // namespace report
}  // namespace pf2
