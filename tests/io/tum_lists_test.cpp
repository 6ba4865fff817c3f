#include "pf2/io/tum_lists.h"

#include <fstream>

#include <gtest/gtest.h>

#include "pf2/core/error.h"

namespace pf2 {
namespace {

using Pairs = std::vector<std::pair<size_t, size_t>>;

TEST(AssociateTimestamps, NearestWithinWindowNoStampTwice) {
  // depth 1.004 is within the window of rgb 1.000 and 1.010 but can be used once: it goes to the
  // closer one; 2.030 is 0.03 s from 2.000, outside the 0.02 s window.
  const std::vector<double> rgb = {1.000, 1.010, 1.050, 2.000};
  const std::vector<double> depth = {1.004, 1.049, 1.500, 2.030};
  EXPECT_EQ(associateTimestamps(rgb, depth, 0.02), (Pairs{{0, 0}, {2, 1}}));
}

TEST(AssociateTimestamps, GreedyTakesTheClosestPairFirst) {
  // b=1.012 is 0.012 from a0 and 0.002 from a1: a1 wins it, a0 falls back to b=0.995.
  const std::vector<double> a = {1.000, 1.010};
  const std::vector<double> b = {0.995, 1.012};
  EXPECT_EQ(associateTimestamps(a, b, 0.02), (Pairs{{0, 0}, {1, 1}}));
  // Without b=0.995, a0 gets nothing.
  EXPECT_EQ(associateTimestamps(a, {1.012}, 0.02), (Pairs{{1, 0}}));
}

TEST(AssociateTimestamps, UnsortedInputAndEmptyLists) {
  EXPECT_EQ(associateTimestamps({3.0, 1.0, 2.0}, {2.001, 0.999, 3.01}, 0.02),
            (Pairs{{0, 2}, {1, 1}, {2, 0}}));
  EXPECT_TRUE(associateTimestamps({}, {1.0}, 0.02).empty());
  EXPECT_TRUE(associateTimestamps({1.0}, {1.5}, 0.02).empty());
}

TEST(ReadTumList, CommentsBlankLinesCrlfAndExtraColumns) {
  const std::string path = testing::TempDir() + "pf2_rgb.txt";
  std::ofstream(path) << "# color images\r\n# timestamp filename\r\n\r\n"
                         "1305031453.359684 rgb/1305031453.359684.png\r\n"
                         "   \t\n"
                         "1305031453.391690 rgb/1305031453.391690.png extra column\n";
  const auto entries = readTumList(path);
  ASSERT_EQ(entries.size(), 2u);
  EXPECT_DOUBLE_EQ(entries[0].timestamp, 1305031453.359684);
  EXPECT_EQ(entries[0].file, "rgb/1305031453.359684.png");  // no '\r'
  EXPECT_EQ(entries[1].file, "rgb/1305031453.391690.png");
  EXPECT_EQ(entries[1].line, 6);
}

TEST(ReadTumList, MalformedLineNamesFileAndLine) {
  const std::string path = testing::TempDir() + "pf2_bad_rgb.txt";
  std::ofstream(path) << "# header\n1.0 rgb/1.png\nnot-a-stamp rgb/2.png\n";
  try {
    readTumList(path);
    FAIL() << "malformed line accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(path + ":3:"), std::string::npos) << e.what();
  }
  std::ofstream(path) << "1.0\n";  // stamp without a file
  EXPECT_THROW(readTumList(path), Error);
  EXPECT_THROW(readTumList(testing::TempDir() + "pf2_missing_list.txt"), Error);
}

// A repeated or earlier stamp would silently drop or reorder a frame: refused with both lines.
TEST(ReadTumList, StampsMustIncrease) {
  const std::string path = testing::TempDir() + "pf2_repeated.txt";
  std::ofstream(path) << "# list\n1.0 rgb/1.png\n2.0 rgb/2.png\n2.0 rgb/2b.png\n";
  try {
    readTumList(path);
    FAIL() << "a repeated timestamp was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(path + ":4: timestamp 2.000000 is not after the one on line 3"),
              std::string::npos) << e.what();
  }
  std::ofstream(path) << "5.0 a.png\n5.0 b.png\n5.0 c.png\n";
  EXPECT_THROW(readTumList(path), Error);
  std::ofstream(path) << "2.0 rgb/2.png 2.0 depth/2.png\n1.0 rgb/1.png 1.0 depth/1.png\n";
  EXPECT_THROW(readTumAssociations(path), Error);
}

TEST(ReadTumAssociations, FourColumns) {
  const std::string path = testing::TempDir() + "pf2_assoc.txt";
  std::ofstream(path) << "1.0 rgb/1.png 1.01 depth/1.png\n2.0 rgb/2.png 1.99 depth/2.png\n";
  const auto pairs = readTumAssociations(path);
  ASSERT_EQ(pairs.size(), 2u);
  EXPECT_EQ(pairs[1].depth.file, "depth/2.png");
  EXPECT_DOUBLE_EQ(pairs[1].depth.timestamp, 1.99);
  std::ofstream(path) << "1.0 rgb/1.png 1.01\n";
  EXPECT_THROW(readTumAssociations(path), Error);
}

}  // namespace
}  // namespace pf2
