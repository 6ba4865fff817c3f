// Writes a tiny pf2_synth-like sequence for the pf2_detect command-line test: 3 frames of 64x48,
// a wall at 3.02 m and a person (12 x 24 px at 1.52 m) walking right by 4 px per frame, with
// gt/boxes.txt and gt/masks/ as pf2_synth writes them.
#include <sys/stat.h>

#include <cstdio>
#include <fstream>
#include <string>

#include <opencv2/imgcodecs.hpp>

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: make_detect_fixture DIR\n");
    return 1;
  }
  const std::string dir = argv[1];
  for (const char* sub : {"", "/rgb", "/depth", "/gt", "/gt/masks"}) ::mkdir((dir + sub).c_str(), 0755);
  std::ofstream rgb(dir + "/rgb.txt"), depth(dir + "/depth.txt"), boxes(dir + "/gt/boxes.txt"),
      poses(dir + "/groundtruth.txt"), camera(dir + "/camera.txt");
  camera << "fx 60\nfy 60\ncx 32\ncy 24\nwidth 64\nheight 48\n";
  for (int i = 0; i < 3; ++i) {
    char stamp[32];
    std::snprintf(stamp, sizeof(stamp), "%.6f", 100.0 + i / 30.0);
    const cv::Rect person(10 + 4 * i, 12, 12, 24);
    cv::Mat d(48, 64, CV_16U, cv::Scalar(15100));  // 3.02 m
    d(person).setTo(7600);                          // 1.52 m
    cv::Mat ids = cv::Mat::zeros(48, 64, CV_16U);
    ids(person).setTo(1);
    cv::Mat colour(48, 64, CV_8UC3, cv::Scalar(200, 200, 200));
    colour(person).setTo(cv::Scalar(40, 40, 40));
    cv::imwrite(dir + "/rgb/" + stamp + ".png", colour);
    cv::imwrite(dir + "/depth/" + stamp + ".png", d);
    cv::imwrite(dir + "/gt/masks/" + stamp + ".png", ids);
    rgb << stamp << " rgb/" << stamp << ".png\n";
    depth << stamp << " depth/" << stamp << ".png\n";
    poses << stamp << " 0 0 0 0 0 0 1\n";
    boxes << stamp << " 1 " << person.x << " " << person.y << " " << person.x + person.width - 1 << " "
          << person.y + person.height - 1 << " 1.0\n";  // inclusive corners, as pf2_synth
  }
  return 0;
}
