#include "pf2/core/settings.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "pf2/core/config_file.h"
#include "pf2/core/error.h"

namespace pf2 {
namespace {

// Shortest text that reads back as the same number for the values settings hold.
std::string numberText(double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "%.10g", value);
  return buffer;
}

std::string rangeText(double lo, double hi) { return "[" + numberText(lo) + ", " + numberText(hi) + "]"; }

double parseNumber(const std::string& text) {
  try {
    size_t end = 0;
    const double v = std::stod(text, &end);
    if (end == text.size() && std::isfinite(v)) return v;
  } catch (const std::exception&) {
  }
  throw Error("expected a number");
}

int parseInteger(const std::string& text) {
  try {
    size_t end = 0;
    const long v = std::stol(text, &end);
    if (end == text.size() && v >= INT32_MIN && v <= INT32_MAX) return static_cast<int>(v);
  } catch (const std::exception&) {
  }
  throw Error("expected an integer");
}

bool parseBoolean(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(), ::tolower);
  if (text == "true" || text == "1" || text == "on" || text == "yes") return true;
  if (text == "false" || text == "0" || text == "off" || text == "no") return false;
  throw Error("expected true or false");
}

std::string join(const std::vector<std::string>& values) {
  std::string out;
  for (size_t i = 0; i < values.size(); ++i) out += (i ? ", " : "") + values[i];
  return out;
}

}  // namespace

Settings& Settings::add(Entry entry) {
  if (has(entry.key)) throw Error("setting " + entry.key + " declared twice");
  entry.default_value = entry.print();
  entries_.push_back(std::move(entry));
  return *this;
}

Settings& Settings::number(const std::string& key, double* field, double lo, double hi, const std::string& unit,
                           const std::string& meaning) {
  return add({key, unit, rangeText(lo, hi), meaning, "",
              [field, lo, hi](const std::string& text) {
                const double v = parseNumber(text);
                if (!(v >= lo && v <= hi)) throw Error("outside its range " + rangeText(lo, hi));
                *field = v;
              },
              [field] { return numberText(*field); },
              [field, lo, hi] { return *field >= lo && *field <= hi; }});
}

Settings& Settings::integer(const std::string& key, int* field, int lo, int hi, const std::string& unit,
                            const std::string& meaning) {
  return add({key, unit, rangeText(lo, hi), meaning, "",
              [field, lo, hi](const std::string& text) {
                const int v = parseInteger(text);
                if (v < lo || v > hi) throw Error("outside its range " + rangeText(lo, hi));
                *field = v;
              },
              [field] { return std::to_string(*field); },
              [field, lo, hi] { return *field >= lo && *field <= hi; }});
}

Settings& Settings::seed(const std::string& key, std::uint64_t* field, const std::string& meaning) {
  constexpr long long kMaxSeed = 2147483647;  // 2^31 - 1: plenty of distinct seeds, and the same on every platform
  return add({key, "", rangeText(0, kMaxSeed), meaning, "",
              [field](const std::string& text) {
                long long v = 0;
                try {
                  size_t end = 0;
                  v = std::stoll(text, &end);
                  if (end != text.size()) throw Error("");
                } catch (const std::exception&) {
                  throw Error("expected an integer");
                }
                if (v < 0 || v > kMaxSeed) throw Error("outside its range " + rangeText(0, kMaxSeed));
                *field = static_cast<std::uint64_t>(v);
              },
              [field] { return std::to_string(*field); }, [field] { return *field <= kMaxSeed; }});
}

Settings& Settings::boolean(const std::string& key, bool* field, const std::string& meaning) {
  return add({key, "", "true, false", meaning, "",
              [field](const std::string& text) { *field = parseBoolean(text); },
              [field] { return std::string(*field ? "true" : "false"); }, [] { return true; }});
}

Settings& Settings::choice(const std::string& key, std::string* field, const std::vector<std::string>& allowed,
                           const std::string& meaning) {
  auto known = [allowed](const std::string& v) {
    return std::find(allowed.begin(), allowed.end(), v) != allowed.end();
  };
  return add({key, "", join(allowed), meaning, "",
              [field, known, allowed](const std::string& text) {
                if (!known(text)) throw Error("expected one of " + join(allowed));
                *field = text;
              },
              [field] { return *field; }, [field, known] { return known(*field); }});
}

Settings& Settings::custom(const std::string& key, std::function<void(const std::string&)> parse,
                           std::function<std::string()> print, const std::string& allowed,
                           const std::string& meaning) {
  return add({key, "", allowed, meaning, "", std::move(parse), std::move(print), [] { return true; }});
}

Settings& Settings::require(std::function<bool()> holds, const std::string& description,
                            std::function<std::string()> details) {
  rules_.push_back({std::move(holds), description, std::move(details)});
  return *this;
}

Settings& Settings::require(std::function<bool()> holds, const std::string& message) {
  rules_.push_back({std::move(holds), message, nullptr});
  return *this;
}

const Settings::Entry& Settings::find(const std::string& key) const {
  for (const Entry& e : entries_)
    if (e.key == key) return e;
  throw Error("unknown setting '" + key + "' (docs/config.md lists them)");
}

bool Settings::has(const std::string& key) const {
  return std::any_of(entries_.begin(), entries_.end(), [&](const Entry& e) { return e.key == key; });
}

void Settings::set(const std::string& key, const std::string& value) {
  const Entry& entry = find(key);
  try {
    entry.parse(value);
  } catch (const Error& e) {
    throw Error("setting " + key + " = " + value + ": " + e.what() +
                (entry.unit.empty() ? "" : " " + entry.unit));
  }
}

void Settings::setAssignment(const std::string& assignment) {
  const auto equals = assignment.find('=');
  if (equals == std::string::npos || equals == 0) {
    throw Error("--set: expected key=value, got '" + assignment + "'");
  }
  set(assignment.substr(0, equals), assignment.substr(equals + 1));
}

void Settings::apply(const ConfigFile& config) {
  for (const Entry& entry : entries_) {
    if (!config.has(entry.key)) continue;
    try {
      set(entry.key, config.text(entry.key, ""));
    } catch (const Error& e) {
      throw Error(config.where(entry.key) + ": " + e.what());
    }
  }
  config.checkAllUsed();
}

void Settings::validate() const {
  for (const Entry& entry : entries_) {
    if (!entry.in_range()) {
      throw Error("setting " + entry.key + " = " + entry.print() + " is outside its range " + entry.allowed +
                  (entry.unit.empty() ? "" : " " + entry.unit));
    }
  }
  for (const Rule& rule : rules_) {
    if (!rule.holds()) throw Error("settings: " + (rule.details ? rule.details() : rule.description));
  }
}

std::vector<std::string> Settings::keys() const {
  std::vector<std::string> out;
  for (const Entry& e : entries_) out.push_back(e.key);
  return out;
}

std::string Settings::value(const std::string& key) const { return find(key).print(); }

std::string Settings::allowed(const std::string& key) const { return find(key).allowed; }

std::string Settings::markdown() const {
  std::ostringstream out;
  out << "| key | default | unit | allowed | meaning |\n| --- | --- | --- | --- | --- |\n";
  for (const Entry& e : entries_) {
    out << "| `" << e.key << "` | " << e.default_value << " | " << e.unit << " | " << e.allowed << " | "
        << e.meaning << " |\n";
  }
  if (!rules_.empty()) out << "\nBetween settings:\n\n";
  for (const Rule& rule : rules_) out << "- " << rule.description << "\n";
  return out.str();
}

}  // namespace pf2
