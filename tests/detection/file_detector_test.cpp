#include "pf2/detection/file_detector.h"

#include <gtest/gtest.h>

#include "pf2/core/error.h"
#include "test_folder.h"

namespace pf2 {
namespace {

Frame frameAt(double t) {
  Frame f;
  f.timestamp = t;
  return f;
}

TEST(FileDetector, BoxesOfTheNearestStampWithin20ms) {
  const std::string dir = freshTestFolder("pf2_file_det");
  writeText(dir + "/boxes.txt",
            "# external detector\n"
            "1305031102.175304 10 20 110 220 0.9\n"
            "1305031102.175304 300 40 360 200 0.4\n"
            "1305031102.211200 12 22 112 222 0.8\r\n");
  FileDetector::Options o;
  o.path = dir + "/boxes.txt";
  FileDetector detector(o);
  Detections d = detector.detect(frameAt(1305031102.18));
  ASSERT_EQ(d.people.size(), 2u);
  EXPECT_EQ(d.timestamp, 1305031102.18);
  EXPECT_FLOAT_EQ(d.people[0].box.x_lr, 110.f);
  EXPECT_FLOAT_EQ(d.people[1].score, 0.4f);
  d = detector.detect(frameAt(1305031102.2));  // nearer to the second stamp
  ASSERT_EQ(d.people.size(), 1u);
  EXPECT_FLOAT_EQ(d.people[0].box.x_ul, 12.f);
  EXPECT_TRUE(detector.detect(frameAt(1305031102.25)).people.empty());
  EXPECT_TRUE(detector.detect(frameAt(1305031102.15)).people.empty());
}

TEST(FileDetector, WriteThenReadRoundTrip) {
  const std::string dir = freshTestFolder("pf2_file_round");
  std::vector<Detections> all(2);
  all[0].timestamp = 5.5;
  all[0].people.resize(1);
  all[0].people[0].box = PersonBox{1.25f, 2.5f, 30.75f, 40.f};
  all[0].people[0].score = 0.75f;
  all[1].timestamp = 5.533333;  // no people: no line
  writeBoxesFile(dir + "/boxes.txt", all);
  const auto read = readBoxesFile(dir + "/boxes.txt");
  ASSERT_EQ(read.size(), 1u);
  const PersonDetection& p = read.begin()->second.at(0);
  EXPECT_DOUBLE_EQ(read.begin()->first, 5.5);
  EXPECT_FLOAT_EQ(p.box.x_ul, 1.25f);
  EXPECT_FLOAT_EQ(p.box.x_lr, 30.75f);
  EXPECT_FLOAT_EQ(p.score, 0.75f);
}

TEST(FileDetector, MalformedLinesNameFileAndLine) {
  const std::string dir = freshTestFolder("pf2_file_bad");
  const std::string cases[] = {"1.0 1 2 3\n", "1.0 1 2 3 4 0.5\n\n1.0 1 2 3 4 1.5\n", "1.0 5 2 3 4 0.5\n"};
  const int lines[] = {1, 3, 1};
  for (int i = 0; i < 3; ++i) {
    const std::string path = dir + "/b" + std::to_string(i) + ".txt";
    writeText(path, cases[i]);
    try {
      readBoxesFile(path);
      ADD_FAILURE() << "no error for case " << i;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(path + ":" + std::to_string(lines[i]) + ":"), std::string::npos)
          << e.what();
    }
  }
  EXPECT_THROW(readBoxesFile(dir + "/missing.txt"), Error);
}

}  // namespace
}  // namespace pf2
