#pragma once
// The one exception type of the project. Readers throw it with the file (and line, when there is
// one) already in the message, so an app can print e.what() as its single error line.
#include <stdexcept>
#include <string>

namespace pf2 {

class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message) : std::runtime_error(message) {}
};

// "path:line: message" — the form compilers use, which editors and people both read.
inline Error fileError(const std::string& path, int line, const std::string& message) {
  return Error(path + ":" + std::to_string(line) + ": " + message);
}
inline Error fileError(const std::string& path, const std::string& message) {
  return Error(path + ": " + message);
}

}  // namespace pf2
