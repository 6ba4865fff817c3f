#include "pf2/core/config_file.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "pf2/core/error.h"
#include "pf2/core/text_lines.h"

namespace pf2 {

ConfigFile ConfigFile::load(const std::string& path) {
  ConfigFile config;
  config.path_ = path;
  forEachDataLine(path, "config file", [&](std::string line, int line_number) {
    const auto hash = line.find('#');
    if (hash != std::string::npos) line.erase(hash);
    std::istringstream fields(line);
    std::string key, value, extra;
    if (!(fields >> key)) return;  // only a trailing comment
    if (!(fields >> value) || (fields >> extra)) {
      throw fileError(path, line_number, "expected 'section.key value', got '" + line + "'");
    }
    if (config.values_.count(key)) {
      throw fileError(path, line_number, "key '" + key + "' set twice (first on line " +
                                             std::to_string(config.values_[key].line) + ")");
    }
    config.values_[key] = {value, line_number};
  });
  return config;
}

const ConfigFile::Entry* ConfigFile::find(const std::string& key) const {
  const auto it = values_.find(key);
  if (it == values_.end()) return nullptr;
  used_.insert(key);
  return &it->second;
}

void ConfigFile::fail(const std::string& key, const std::string& expected) const {
  const Entry& entry = values_.at(key);
  throw fileError(path_, entry.line, key + ": expected " + expected + ", got '" + entry.value + "'");
}

double ConfigFile::number(const std::string& key, double fallback) const {
  const Entry* entry = find(key);
  if (!entry) return fallback;
  try {
    size_t end = 0;
    const double v = std::stod(entry->value, &end);
    if (end == entry->value.size() && std::isfinite(v)) return v;
  } catch (const std::exception&) {
  }
  fail(key, "a number");
}

int ConfigFile::integer(const std::string& key, int fallback) const {
  const Entry* entry = find(key);
  if (!entry) return fallback;
  try {
    size_t end = 0;
    const int v = std::stoi(entry->value, &end);
    if (end == entry->value.size()) return v;
  } catch (const std::exception&) {
  }
  fail(key, "an integer");
}

bool ConfigFile::boolean(const std::string& key, bool fallback) const {
  const Entry* entry = find(key);
  if (!entry) return fallback;
  std::string v = entry->value;
  std::transform(v.begin(), v.end(), v.begin(), ::tolower);
  if (v == "true" || v == "1" || v == "on" || v == "yes") return true;
  if (v == "false" || v == "0" || v == "off" || v == "no") return false;
  fail(key, "true or false");
}

std::string ConfigFile::text(const std::string& key, const std::string& fallback) const {
  const Entry* entry = find(key);
  return entry ? entry->value : fallback;
}

std::string ConfigFile::where(const std::string& key) const {
  const auto it = values_.find(key);
  return it == values_.end() ? path_ : path_ + ":" + std::to_string(it->second.line);
}

void ConfigFile::checkAllUsed() const {
  for (const auto& [key, entry] : values_) {
    if (!used_.count(key)) throw fileError(path_, entry.line, "unknown key '" + key + "'");
  }
}

}  // namespace pf2
