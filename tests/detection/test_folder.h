#pragma once
// Small helpers shared by the detection tests.
#include <sys/stat.h>

#include <cstdlib>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

namespace pf2 {

inline std::string freshTestFolder(const std::string& name) {
  const std::string dir = testing::TempDir() + name;
  std::system(("rm -rf '" + dir + "'").c_str());
  ::mkdir(dir.c_str(), 0755);
  return dir;
}

inline void writeText(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

}  // namespace pf2
