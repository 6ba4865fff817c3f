#include "pf2/core/atomic_file.h"

#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "pf2/core/error.h"

namespace pf2 {
namespace {

std::string readAll(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(AtomicFile, WritesAndReplaces) {
  const std::string path = testing::TempDir() + "pf2_atomic.txt";
  writeFileAtomically(path, [](std::ostream& out) { out << "first\n"; });
  EXPECT_EQ(readAll(path), "first\n");
  writeFileAtomically(path, [](std::ostream& out) { out << "second\n"; });
  EXPECT_EQ(readAll(path), "second\n");
}

TEST(AtomicFile, FailedWriterKeepsTheOldFile) {
  const std::string path = testing::TempDir() + "pf2_atomic_keep.txt";
  writeFileAtomically(path, [](std::ostream& out) { out << "whole\n"; });
  EXPECT_THROW(writeFileAtomically(path,
                                   [](std::ostream& out) {
                                     out << "half";
                                     throw Error("writer failed");
                                   }),
               Error);
  EXPECT_EQ(readAll(path), "whole\n");
  EXPECT_FALSE(std::ifstream(temporaryPathFor(path)).good());  // temporary removed
}

TEST(AtomicFile, UnwritableFolderNamesThePath) {
  const std::string path = "/nonexistent-folder-pf2/out.txt";
  try {
    writeFileAtomically(path, [](std::ostream& out) { out << "x"; });
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos);
  }
}

TEST(AtomicFile, TemporaryKeepsExtension) {
  const std::string tmp = temporaryPathFor("out/map.ply");
  EXPECT_EQ(tmp.substr(tmp.size() - 4), ".ply");
  EXPECT_EQ(tmp.substr(0, 8), "out/map.");
  EXPECT_EQ(temporaryPathFor("a.b/noext").substr(0, 9), "a.b/noext");
}

}  // namespace
}  // namespace pf2
