#include "pf2/report/run_report.h"

#include <ostream>
#include <sstream>

#include "html_text.h"
#include "pf2/core/atomic_file.h"
#include "pf2/core/error.h"
#include "report_context.h"

namespace pf2 {

namespace {

// Dark, because the people's colours (personColour) are chosen to read on a dark background.
// System fonts only: the page must not fetch anything.
const char* const kStyle = R"(
:root { color-scheme: dark; }
body { background: #0d1117; color: #e6edf3; font: 14px/1.45 system-ui, sans-serif; margin: 0; }
main { max-width: 1000px; margin: 0 auto; padding: 16px 20px 40px; }
h1 { font-size: 22px; margin: 8px 0 4px; word-break: break-word; }
h2 { font-size: 17px; margin: 28px 0 8px; border-bottom: 1px solid #30363d; padding-bottom: 4px; }
nav a { color: #58a6ff; margin-right: 12px; text-decoration: none; }
table { border-collapse: collapse; margin: 8px 0; }
td, th { border: 1px solid #30363d; padding: 3px 10px; text-align: left; vertical-align: top; }
th { background: #161b22; }
td:not(:first-child) { font-variant-numeric: tabular-nums; }
details summary { cursor: pointer; color: #58a6ff; }
.note { color: #9da7b3; }
.swatch { display: inline-block; width: 12px; height: 12px; margin-right: 6px; border-radius: 2px;
          vertical-align: -1px; }
svg.plot { display: block; background: #161b22; border: 1px solid #30363d; border-radius: 6px;
           margin: 8px 0; max-width: 100%; height: auto; }
svg.plot .area { fill: #0d1117; }
svg.plot .grid { stroke: #21262d; stroke-width: 1; fill: none; }
svg.plot .axis { stroke: #8b949e; stroke-width: 1; fill: none; }
svg.plot text { fill: #c9d1d9; font: 12px system-ui, sans-serif; }
svg.plot .plot-title { font-weight: 600; font-size: 13px; }
svg.plot .tick { fill: #8b949e; font-size: 11px; }
svg.plot .data-label { font-weight: 700; }
)";

std::string navigation() {
  static const char* const kLinks[][2] = {
      {"summary", "Summary"}, {"stages", "Stages"}, {"trajectory", "Trajectory"}, {"error", "Error"},
      {"status", "Status"},   {"people", "People"}, {"detector", "Detector"},     {"settings", "Settings"}};
  std::string html = "<nav>";
  for (const auto& link : kLinks) html += "<a href=\"#" + std::string(link[0]) + "\">" + link[1] + "</a>";
  return html + "</nav>\n";
}

std::string page(const RunReportInput& input) {
  const report::ReportContext context = report::makeContext(input);
  const std::string title = "PoseFusion2 run report" + (input.title.empty() ? "" : ": " + input.title);
  std::ostringstream html;
  html << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
       << "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n"
       << "<title>" << report::escapeHtml(title) << "</title>\n<style>" << kStyle << "</style>\n</head>\n"
       << "<body>\n<main>\n<h1>" << report::escapeHtml(title) << "</h1>\n"
       << navigation() << report::summarySection(context) << report::stageSection(context)
       << report::trajectorySection(context) << report::errorSection(context) << report::statusSection(context)
       << report::peopleSection(context) << report::detectorSection(context) << report::settingsSection(context)
       << "</main>\n</body>\n</html>\n";
  return html.str();
}

}  // namespace

void writeRunReport(const std::string& path, const RunReportInput& input) {
  if (!input.result) throw fileError(path, "run report needs the run's result");
  if (!input.stages) throw fileError(path, "run report needs the run's stage timings");
  const std::string html = page(input);
  writeFileAtomically(path, [&html](std::ostream& out) { out << html; });
}

}  // namespace pf2
