#pragma once
// The small command-line parser every pf2_* app uses, so that all of them read options the same
// way: "--name value", "--flag", positionals, "-h"/"--help". Errors throw pf2::Error naming the
// option. Take the options first, then positionals(), which rejects anything left unread.
#include <optional>
#include <string>
#include <vector>

namespace pf2 {

class CommandLine {
 public:
  CommandLine(int argc, const char* const* argv);

  bool helpRequested() const;
  // True if --name is present and not yet consumed (it stays unconsumed).
  bool has(const std::string& name) const;
  // True if --name is present (it is consumed).
  bool flag(const std::string& name);
  // The argument after the last --name (all consumed); nullopt when absent; throws when --name
  // is last.
  std::optional<std::string> value(const std::string& name);
  std::string value(const std::string& name, const std::string& fallback);
  // The arguments of every --name, in order, consumed (a repeatable option such as --set).
  std::vector<std::string> values(const std::string& name);
  double number(const std::string& name, double fallback);
  int integer(const std::string& name, int fallback);
  // Remaining arguments; throws on an unknown option (anything left starting with '-').
  std::vector<std::string> positionals();

 private:
  std::vector<std::string> args_;
  std::vector<bool> used_;
};

// Calls keepFreedImageMemory(), then runs body(); on pf2::Error or std::exception prints "<program>: error: <what>" to stderr and
// returns 1. Apps return its result from main.
int runApp(const char* program, int (*body)(int, char**), int argc, char** argv);

// Makes freed large blocks (images) stay mapped for reuse instead of returning to the kernel, so a
// per-frame pipeline does not page-fault on every new image. runApp calls it; benchmarks and other
// long-running hosts may call it first thing too. Process-wide; call before starting threads.
void keepFreedImageMemory();

}  // namespace pf2
