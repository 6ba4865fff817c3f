#include "pf2/detection/learned_models.h"

#include <sys/stat.h>

#include <cstdlib>

namespace pf2 {

std::string humanModelsDir() {
  std::string root;
  if (const char* dir = std::getenv("PF2_MODEL_DIR"); dir && *dir) {
    root = dir;
  } else {
    const char* home = std::getenv("HOME");
    root = std::string(home ? home : ".") + "/.cache/posefusion2/models";
  }
  return root + "/human-models-3.0.4/models";
}

std::string humanModelPath(const std::string& name) { return humanModelsDir() + "/" + name + ".json"; }

bool humanModelAvailable(const std::string& name) {
  struct stat info;
  return ::stat(humanModelPath(name).c_str(), &info) == 0 && S_ISREG(info.st_mode);
}

}  // namespace pf2
