#include "pf2/humans/human_track.h"

#include <fstream>

#include <gtest/gtest.h>

#include "pf2/core/error.h"

namespace pf2 {
namespace {

TEST(HumanTrackIo, WritesSortedLinesAndReadsThemBack) {
  std::vector<HumanTrack> tracks(2);
  tracks[0].id = 2;
  tracks[0].points = {{10.0, {1, 2, 3}}, {10.1, {1.5, 2, 3}}};
  tracks[1].id = 1;
  tracks[1].points = {{10.1, {-0.25, 0.125, 4}}};
  const std::string path = testing::TempDir() + "pf2_humans.txt";
  writeHumanTracks(path, tracks);
  std::ifstream in(path);
  std::string header, line1, line2, line3;
  std::getline(in, header);
  std::getline(in, line1);
  std::getline(in, line2);
  std::getline(in, line3);
  EXPECT_EQ(header[0], '#');
  EXPECT_EQ(line1, "10.000000 2 1.000000 2.000000 3.000000");
  EXPECT_EQ(line2, "10.100000 1 -0.250000 0.125000 4.000000");
  EXPECT_EQ(line3, "10.100000 2 1.500000 2.000000 3.000000");
  const std::vector<HumanTrack> read = readHumanTracks(path);
  ASSERT_EQ(read.size(), 2u);
  EXPECT_EQ(read[0].id, 1);
  EXPECT_EQ(read[1].id, 2);
  ASSERT_EQ(read[1].points.size(), 2u);
  EXPECT_DOUBLE_EQ(read[1].points[1].timestamp, 10.1);
  EXPECT_TRUE(read[1].points[1].p_w.isApprox(Eigen::Vector3d(1.5, 2, 3)));
}

TEST(HumanTrackIo, BadLinesNameFileAndLine) {
  const std::string path = testing::TempDir() + "pf2_humans_bad.txt";
  {
    std::ofstream out(path);
    out << "# comment\r\n1.0 1 0 0 0\n\n2.0 1 0 nan 0\n";
  }
  try {
    readHumanTracks(path);
    FAIL() << "a NaN coordinate was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(path + ":4:"), std::string::npos) << e.what();
  }
  {
    std::ofstream out(path);
    out << "1.0 1 0 0\n";
  }
  EXPECT_THROW(readHumanTracks(path), Error);
  EXPECT_THROW(readHumanTracks(testing::TempDir() + "no_such_humans.txt"), Error);
}

}  // namespace
}  // namespace pf2
