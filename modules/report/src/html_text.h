#pragma once
// Text helpers of the run report: escaping, number formatting, colours and tables.
#include <array>
#include <string>
#include <utility>
#include <vector>

namespace pf2 {
namespace report {

// & < > " ' replaced by entities: safe inside elements and quoted attributes.
std::string escapeHtml(const std::string& text);
// value with `decimals` digits after the point; "n/a" for NaN or infinity, so that no "nan"
// ever reaches the page.
std::string fixed(double value, int decimals);
// "#rrggbb" from RGB in [0, 1] (clamped).
std::string colourHex(const std::array<double, 3>& rgb);

// A table whose cells are HTML already (callers escape their text); no header row when the
// header is empty.
class HtmlTable {
 public:
  explicit HtmlTable(std::vector<std::string> header);
  void addRow(std::vector<std::string> cells);
  bool empty() const { return rows_.empty(); }
  std::string render() const;

 private:
  std::vector<std::string> header_;
  std::vector<std::vector<std::string>> rows_;
};

// Two columns, both escaped: a list of (name, value).
std::string keyValueTable(const std::vector<std::pair<std::string, std::string>>& rows);

}  // namespace report
}  // namespace pf2
