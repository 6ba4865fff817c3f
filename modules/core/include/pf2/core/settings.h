#pragma once
// Named settings bound to the fields of Options structs, each declared once: its key, the field
// it sets, its unit, its allowed range and what it means. From that one list come the config-file
// reader, `--set key=value` on the command line, range validation that names the key, the value
// and the allowed range, and the documentation table (docs/config.md).
//
//   SlamOptions options;
//   Settings settings;
//   settings.number("map.voxel_size", &options.mapper.tsdf.voxel_size, 0.002, 0.2, "metres",
//                   "TSDF voxel edge");
//   settings.apply(ConfigFile::load("run.cfg"));   // then checks every key of the file was known
//   settings.set("map.voxel_size", "0.01");          // --set map.voxel_size=0.01
//
// A Settings object holds pointers to the fields it was given: those must outlive it. NOT thread
// safe.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace pf2 {

class ConfigFile;

class Settings {
 public:
  // Declarations; the field's current value is recorded as the default (validate() checks it
  // like any value). Each throws pf2::Error when the key is declared twice; returns *this.
  Settings& number(const std::string& key, double* field, double lo, double hi, const std::string& unit,
                   const std::string& meaning);
  Settings& integer(const std::string& key, int* field, int lo, int hi, const std::string& unit,
                    const std::string& meaning);
  Settings& boolean(const std::string& key, bool* field, const std::string& meaning);
  // A random seed, an integer in [0, 2^31 - 1], held in a 64-bit field.
  Settings& seed(const std::string& key, std::uint64_t* field, const std::string& meaning);
  // A text setting with a fixed list of allowed values.
  Settings& choice(const std::string& key, std::string* field, const std::vector<std::string>& allowed,
                   const std::string& meaning);
  // A setting of another type: `parse` stores a value (throwing pf2::Error on a bad one), `print`
  // gives the current value as text; `allowed` describes the values for messages and the docs.
  Settings& custom(const std::string& key, std::function<void(const std::string&)> parse,
                   std::function<std::string()> print, const std::string& allowed, const std::string& meaning);
  // A rule between settings, checked by validate(): `holds` must be true, else the message.
  Settings& require(std::function<bool()> holds, const std::string& message);
  // The same with a message made from the values when the rule fails (`description` goes into
  // the docs, `details()` into the error).
  Settings& require(std::function<bool()> holds, const std::string& description,
                    std::function<std::string()> details);

  // Sets one setting from text. Throws pf2::Error "setting KEY = VALUE: ..." naming the expected
  // type or the allowed range, or the unknown key.
  void set(const std::string& key, const std::string& value);
  // "key=value" as given to --set.
  void setAssignment(const std::string& assignment);
  // Sets every declared key the file has, then fails on any key of the file that is not declared.
  // Errors name the file, line and key.
  void apply(const ConfigFile& config);
  // Checks every field against its range (and the rules): for values set in code, not through
  // set(). Throws pf2::Error naming the key, the value and the allowed range.
  void validate() const;

  std::vector<std::string> keys() const;
  bool has(const std::string& key) const;
  // The current value as text (as set() reads it back).
  std::string value(const std::string& key) const;
  // The allowed values as text: "[lo, hi]" for numbers, the list of names otherwise.
  std::string allowed(const std::string& key) const;
  // Markdown table: key, default (the value when declared), unit, allowed values, meaning; then
  // the rules between settings as a list.
  std::string markdown() const;

 private:
  struct Entry {
    std::string key;
    std::string unit;
    std::string allowed;  // range or values, as text
    std::string meaning;
    std::string default_value;
    std::function<void(const std::string&)> parse;
    std::function<std::string()> print;
    std::function<bool()> in_range;
  };
  Settings& add(Entry entry);
  const Entry& find(const std::string& key) const;

  std::vector<Entry> entries_;
  struct Rule {
    std::function<bool()> holds;
    std::string description;
    std::function<std::string()> details;  // may be empty: the description is the message
  };
  std::vector<Rule> rules_;
};

}  // namespace pf2
