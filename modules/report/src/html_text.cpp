#include "html_text.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace pf2 {
namespace report {

std::string escapeHtml(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (const char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&#39;"; break;
      default: out += c;
    }
  }
  return out;
}

std::string fixed(double value, int decimals) {
  if (!std::isfinite(value)) return "n/a";
  char text[64];
  std::snprintf(text, sizeof(text), "%.*f", std::clamp(decimals, 0, 12), value);
  return text;
}

std::string colourHex(const std::array<double, 3>& rgb) {
  char text[8];
  const auto byte = [](double v) {
    return static_cast<int>(std::lround(std::clamp(std::isfinite(v) ? v : 0.0, 0.0, 1.0) * 255.0));
  };
  std::snprintf(text, sizeof(text), "#%02x%02x%02x", byte(rgb[0]), byte(rgb[1]), byte(rgb[2]));
  return text;
}

HtmlTable::HtmlTable(std::vector<std::string> header) : header_(std::move(header)) {}

void HtmlTable::addRow(std::vector<std::string> cells) { rows_.push_back(std::move(cells)); }

std::string HtmlTable::render() const {
  std::ostringstream out;
  out << "<table>\n";
  if (!header_.empty()) {
    out << "<thead><tr>";
    for (const std::string& cell : header_) out << "<th>" << cell << "</th>";
    out << "</tr></thead>\n";
  }
  out << "<tbody>\n";
  for (const auto& row : rows_) {
    out << "<tr>";
    for (const std::string& cell : row) out << "<td>" << cell << "</td>";
    out << "</tr>\n";
  }
  out << "</tbody>\n</table>\n";
  return out.str();
}

std::string keyValueTable(const std::vector<std::pair<std::string, std::string>>& rows) {
  HtmlTable table({});
  for (const auto& [key, value] : rows) table.addRow({escapeHtml(key), escapeHtml(value)});
  return table.render();
}

}  // namespace report
}  // namespace pf2
