#pragma once
// "section.key value" text files for pf2_slam --config: one list of knobs, read into the stages'
// Options structs. '#' starts a comment; blank lines and CRLF are fine.
//
//   ConfigFile config = ConfigFile::load("run.cfg");
//   options.voxel_size = config.number("surface.voxel_size", options.voxel_size);
//   config.checkAllUsed();   // a misspelt key is an error, not a silent default
#include <map>
#include <set>
#include <string>

namespace pf2 {

class ConfigFile {
 public:
  ConfigFile() = default;
  // Throws pf2::Error "path:line: ..." on a malformed or duplicate line, or an unreadable file.
  static ConfigFile load(const std::string& path);

  bool has(const std::string& key) const { return values_.count(key) > 0; }
  // Each returns the fallback when the key is absent and throws pf2::Error naming the file, line
  // and key when the value does not parse. Reading a key marks it used.
  double number(const std::string& key, double fallback) const;
  int integer(const std::string& key, int fallback) const;
  bool boolean(const std::string& key, bool fallback) const;  // true/false/1/0/on/off
  std::string text(const std::string& key, const std::string& fallback) const;

  // "path:line" of a key's line, for messages ("path" alone for an absent key).
  std::string where(const std::string& key) const;

  // Throws pf2::Error naming the first key nobody read (a typo in the file).
  void checkAllUsed() const;

 private:
  struct Entry {
    std::string value;
    int line = 0;
  };
  const Entry* find(const std::string& key) const;
  [[noreturn]] void fail(const std::string& key, const std::string& expected) const;

  std::string path_;
  std::map<std::string, Entry> values_;
  mutable std::set<std::string> used_;
};

}  // namespace pf2
