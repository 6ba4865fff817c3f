#include "pf2/core/atomic_file.h"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>

#include "pf2/core/error.h"

namespace pf2 {

std::string temporaryPathFor(const std::string& path) {
  const std::string tag = ".tmp" + std::to_string(::getpid());
  const auto slash = path.find_last_of('/');
  const auto dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return path + tag;
  return path.substr(0, dot) + tag + path.substr(dot);
}

void commitTemporaryFile(const std::string& temporary_path, const std::string& path) {
  if (std::rename(temporary_path.c_str(), path.c_str()) != 0) {
    const std::string reason = std::strerror(errno);
    std::remove(temporary_path.c_str());
    throw fileError(path, "cannot move " + temporary_path + " into place: " + reason);
  }
}

void writeFileAtomically(const std::string& path,
                         const std::function<void(std::ostream&)>& write) {
  const std::string temporary_path = temporaryPathFor(path);
  {
    std::ofstream out(temporary_path, std::ios::binary | std::ios::trunc);
    if (!out) throw fileError(path, std::string("cannot open for writing: ") + std::strerror(errno));
    try {
      write(out);
    } catch (...) {
      out.close();
      std::remove(temporary_path.c_str());
      throw;
    }
    out.flush();
    if (!out) {
      out.close();
      std::remove(temporary_path.c_str());
      throw fileError(path, "write failed (disk full?)");
    }
  }
  commitTemporaryFile(temporary_path, path);
}

}  // namespace pf2
