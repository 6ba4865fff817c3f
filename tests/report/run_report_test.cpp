#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <dirent.h>

#include "pf2/core/error.h"
#include "pf2/report/run_report.h"
#include "sample_run.h"

namespace pf2 {
namespace {

std::string readFile(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

size_t countOf(const std::string& text, const std::string& needle) {
  size_t count = 0;
  for (size_t at = text.find(needle); at != std::string::npos; at = text.find(needle, at + needle.size())) ++count;
  return count;
}

// The ids of the page's <svg class="plot"> elements, in page order.
std::vector<std::string> plotIds(const std::string& html) {
  std::vector<std::string> ids;
  const std::regex plot("<svg class=\"plot\" id=\"([^\"]+)\"");
  for (auto it = std::sregex_iterator(html.begin(), html.end(), plot); it != std::sregex_iterator(); ++it) {
    ids.push_back((*it)[1]);
  }
  return ids;
}

// The text of one plot's element.
std::string plotText(const std::string& html, const std::string& id) {
  const size_t begin = html.find("<svg class=\"plot\" id=\"" + id + "\"");
  if (begin == std::string::npos) return "";
  return html.substr(begin, html.find("</svg>", begin) - begin);
}

// True when the SVG text has a <path class="series"> whose d starts with "M<number>,<number>".
// (Searched by hand: std::regex recurses per character and overflows on long path data.)
bool hasDrawnSeries(const std::string& svg) {
  for (size_t at = svg.find("<path class=\"series\""); at != std::string::npos;
       at = svg.find("<path class=\"series\"", at + 1)) {
    const size_t d = svg.find(" d=\"", at);
    if (d == std::string::npos || d > svg.find('>', at)) continue;
    double x = 0, y = 0;
    if (std::sscanf(svg.c_str() + d + 4, "M%lf,%lf", &x, &y) == 2) return true;
  }
  return false;
}

// Every plot draws at least one series with path data.
void expectSeriesInEveryPlot(const std::string& html) {
  for (const std::string& id : plotIds(html)) {
    EXPECT_TRUE(hasDrawnSeries(plotText(html, id))) << id << " has no drawn series";
  }
}

void expectSelfContainedAndFinite(const std::string& html) {
  EXPECT_EQ(html.find("http://"), std::string::npos);
  EXPECT_EQ(html.find("https://"), std::string::npos);
  EXPECT_EQ(html.find("src="), std::string::npos);
  EXPECT_EQ(html.find("<script"), std::string::npos);
  EXPECT_EQ(html.find("<link"), std::string::npos);
  EXPECT_EQ(html.find("@import"), std::string::npos);
  EXPECT_EQ(countOf(html, "url("), countOf(html, "url(#"));  // only the plots' own clip paths
  EXPECT_FALSE(std::regex_search(html, std::regex("\\b(nan|inf)\\b", std::regex::icase)));
}

class RunReportTest : public testing::Test {
 protected:
  void SetUp() override { test::makeSampleRun(test::SampleOptions(), &run_); }
  std::string write(const RunReportInput& input, const std::string& name) {
    const std::string path = testing::TempDir() + name;
    writeRunReport(path, input);
    return readFile(path);
  }
  test::SampleRun run_;
};

TEST_F(RunReportTest, PageIsSelfContainedWithEverySectionAndPlot) {
  const std::string html = write(run_.input(), "pf2_report_full.html");
  expectSelfContainedAndFinite(html);
  for (const char* id : {"summary", "stages", "trajectory", "error", "status", "people", "detector", "settings"}) {
    EXPECT_NE(html.find("<section id=\"" + std::string(id) + "\">"), std::string::npos) << id;
  }
  const std::vector<std::string> expected = {"stage-times",  "top-view",        "ate-over-time",
                                             "status-strip", "people-top-view", "people-per-frame"};
  EXPECT_EQ(plotIds(html), expected);
  EXPECT_EQ(countOf(html, "<svg class=\"plot\""), expected.size());
  expectSeriesInEveryPlot(html);
  EXPECT_NE(html.find("<details>"), std::string::npos);
  EXPECT_NE(html.find("ATE RMSE"), std::string::npos);
}

TEST_F(RunReportTest, PlotsShowTheRunsContents) {
  const std::string html = write(run_.input(), "pf2_report_contents.html");
  for (const char* stage : {"detect", "filter", "track", "humans", "frame"}) {
    EXPECT_NE(plotText(html, "stage-times").find("data-name=\"" + std::string(stage) + "\""), std::string::npos);
  }
  // The slow first detector call cuts the y axis, and the caption says so.
  EXPECT_NE(html.find("The y axis is cut at"), std::string::npos);
  const std::string top = plotText(html, "top-view");
  for (const char* name : {"ground truth", "estimate (aligned)", "bridged", "relocalised", "lost after this pose"}) {
    EXPECT_NE(top.find("data-name=\"" + std::string(name) + "\""), std::string::npos) << name;
  }
  const std::string strip = plotText(html, "status-strip");
  EXPECT_NE(strip.find("data-name=\"lost (21)\""), std::string::npos);
  EXPECT_NE(strip.find("data-name=\"bridged (18)\""), std::string::npos);
  EXPECT_NE(strip.find("data-name=\"relocalised (1)\""), std::string::npos);
  const std::string people = plotText(html, "people-top-view");
  EXPECT_NE(people.find("data-name=\"person 1\""), std::string::npos);
  EXPECT_NE(people.find("data-name=\"person 2\""), std::string::npos);
  EXPECT_NE(people.find("#4073ff"), std::string::npos);  // personColour(1)
}

TEST_F(RunReportTest, AccuracyMatchesTheDriftOfTheSample) {
  const std::string html = write(run_.input(), "pf2_report_accuracy.html");
  const std::regex rmse("ATE RMSE / mean / max \\(m\\)</td><td>([0-9.]+) / ");
  std::smatch match;
  ASSERT_TRUE(std::regex_search(html, match, rmse));
  // The sample drifts by up to 12 cm (plus 3 cm while bridged): the aligned RMSE is a few cm.
  EXPECT_GT(std::stod(match[1]), 0.005);
  EXPECT_LT(std::stod(match[1]), 0.08);
}

TEST_F(RunReportTest, EscapesTitleAndSettings) {
  RunReportInput input = run_.input();
  input.title = "<script>alert(1)</script> & \"run\"";
  const std::string html = write(input, "pf2_report_escape.html");
  EXPECT_EQ(html.find("<script"), std::string::npos);
  EXPECT_NE(html.find("&lt;script&gt;alert(1)&lt;/script&gt; &amp; &quot;run&quot;"), std::string::npos);
  EXPECT_NE(html.find("camera &lt;fr3&gt; &amp; &quot;quoted&quot;"), std::string::npos);
}

TEST_F(RunReportTest, WithoutGroundTruthTheErrorSectionSaysSo) {
  const std::string html = write(run_.input(false), "pf2_report_no_gt.html");
  expectSelfContainedAndFinite(html);
  EXPECT_EQ(plotIds(html).size(), 5u);
  EXPECT_NE(html.find("No ground truth was given."), std::string::npos);
  EXPECT_NE(plotText(html, "top-view").find("data-name=\"estimate\""), std::string::npos);
  expectSeriesInEveryPlot(html);
}

// The top view looks down the vertical the cameras agree on: z in pf2_synth's world (as in the
// sample's ground truth), y (downwards) in the estimate's own, the first camera's, frame.
TEST_F(RunReportTest, TopViewIsSeenFromAbove) {
  const std::string with_gt = write(run_.input(), "pf2_report_view_gt.html");
  EXPECT_NE(with_gt.find("the x-y plane of the ground truth&#39;s world (vertical: z"), std::string::npos);
  const std::string without = write(run_.input(false), "pf2_report_view_estimate.html");
  EXPECT_NE(without.find("the x-z plane of the estimate&#39;s world (vertical: y"), std::string::npos);
  EXPECT_EQ(without.find("drawn downwards"), std::string::npos);
  // A y-up world (Bonn's): x right and z up the page would be the view from below; z is negated.
  Trajectory y_up = run_.ground_truth;
  const Eigen::Isometry3d z_to_y(Eigen::AngleAxisd(-M_PI / 2, Eigen::Vector3d::UnitX()));
  for (StampedPose& pose : y_up) pose.T_w_c = z_to_y * pose.T_w_c;
  RunReportInput input = run_.input();
  input.ground_truth = &y_up;
  const std::string html = write(input, "pf2_report_view_y_up.html");
  EXPECT_NE(html.find("the x-z plane of the ground truth&#39;s world (vertical: y"), std::string::npos);
  EXPECT_NE(html.find("z drawn downwards"), std::string::npos);
  EXPECT_NE(plotText(html, "top-view").find(">-z (m)</text>"), std::string::npos);
}

TEST_F(RunReportTest, UnassociatedGroundTruthIsReportedNotFatal) {
  Trajectory shifted = run_.ground_truth;
  for (StampedPose& pose : shifted) pose.timestamp += 1000.0;
  RunReportInput input = run_.input();
  input.ground_truth = &shifted;
  const std::string html = write(input, "pf2_report_bad_gt.html");
  EXPECT_NE(html.find("Ground truth not used: only 0 estimate poses"), std::string::npos);
  EXPECT_EQ(plotText(html, "ate-over-time"), "");
}

TEST(RunReport, EmptyRunGivesAPageThatSaysWhatIsMissing) {
  const SlamResult result;
  const StageStats stages;
  const Trajectory ground_truth;
  RunReportInput input;
  input.result = &result;
  input.stages = &stages;
  input.ground_truth = &ground_truth;
  const std::string path = testing::TempDir() + "pf2_report_empty.html";
  writeRunReport(path, input);
  const std::string html = readFile(path);
  expectSelfContainedAndFinite(html);
  EXPECT_TRUE(plotIds(html).empty());
  for (const char* text : {"No stage timings were recorded.", "No poses: the camera was never tracked.",
                           "Ground truth not used", "No frame status was recorded.", "No people",
                           "No settings were passed"}) {
    EXPECT_NE(html.find(text), std::string::npos) << text;
  }
}

TEST(RunReport, OnePoseAndNonFiniteValuesDrawWithoutNan) {
  SlamResult result;
  result.trajectory.push_back({10.0, Eigen::Isometry3d::Identity()});
  StampedPose broken{10.1, Eigen::Isometry3d::Identity()};
  broken.T_w_c.translation().x() = std::numeric_limits<double>::quiet_NaN();
  result.trajectory.push_back(broken);
  result.frame_status = {{10.0, TrackStatus::kOk}, {10.1, TrackStatus::kBridged}};
  result.has_humans = true;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  result.humans = {{3, {{10.0, Eigen::Vector3d(1, 2, 0)}, {10.1, Eigen::Vector3d::Constant(nan)}}}};
  StageStats stages;
  stages.add("track", 5.0);
  stages.add("track", std::numeric_limits<double>::infinity());
  stages.add("map_export", 100.0);
  RunReportInput input;
  input.result = &result;
  input.stages = &stages;
  const std::string path = testing::TempDir() + "pf2_report_one_pose.html";
  writeRunReport(path, input);
  const std::string html = readFile(path);
  expectSelfContainedAndFinite(html);
  EXPECT_NE(plotText(html, "top-view"), "");
  EXPECT_NE(plotText(html, "people-top-view"), "");
  expectSeriesInEveryPlot(html);
}

TEST(RunReport, TrackedPeopleListEmptySaysNoPeople) {
  SlamResult result;
  result.has_humans = true;
  const StageStats stages;
  RunReportInput input;
  input.result = &result;
  input.stages = &stages;
  const std::string path = testing::TempDir() + "pf2_report_no_people.html";
  writeRunReport(path, input);
  EXPECT_NE(readFile(path).find("No people were tracked."), std::string::npos);
}

TEST(RunReport, LongRunsStaySmall) {
  test::SampleRun run;
  test::SampleOptions options;
  options.frames = 20000;
  test::makeSampleRun(options, &run);
  const std::string path = testing::TempDir() + "pf2_report_long.html";
  writeRunReport(path, run.input());
  const std::string html = readFile(path);
  // Thinned to the pixels: far below the ~12 MB of every point of every series.
  EXPECT_LT(html.size(), 3000000u);
  expectSeriesInEveryPlot(html);
}

TEST(RunReport, MissingInputOrUnwritablePathThrowsNamingThePath) {
  const SlamResult result;
  const StageStats stages;
  RunReportInput input;
  input.stages = &stages;
  const std::string path = testing::TempDir() + "pf2_report_missing.html";
  try {
    writeRunReport(path, input);
    ADD_FAILURE() << "no exception without a result";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find(path), std::string::npos);
  }
  input.result = &result;
  const std::string bad = testing::TempDir() + "no_such_folder/report.html";
  try {
    writeRunReport(bad, input);
    ADD_FAILURE() << "no exception for a missing folder";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find(bad), std::string::npos);
  }
}

}  // namespace
}  // namespace pf2
