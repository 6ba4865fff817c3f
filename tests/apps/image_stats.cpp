// image_stats FILE: pixel statistics of an image for the app tests, one "key value" per line:
// width, height, distinct (colours, counted up to 4096), and the fractions of pixels whose red,
// green or blue channel dominates (exceeds 60 and 1.5 times both others, so that anti-aliased line
// edges count too). A test can then check that a rendering is not blank and that the coloured
// things it drew are there.
#include <opencv2/imgcodecs.hpp>

#include <cstdio>
#include <set>

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "Usage: image_stats FILE\n");
    return 2;
  }
  const cv::Mat image = cv::imread(argv[1], cv::IMREAD_COLOR);
  if (image.empty()) {
    std::fprintf(stderr, "image_stats: error: %s: cannot read the image\n", argv[1]);
    return 1;
  }
  std::set<int> colours;
  long dominant[3] = {0, 0, 0};  // red, green, blue
  for (int y = 0; y < image.rows; ++y) {
    for (int x = 0; x < image.cols; ++x) {
      const cv::Vec3b bgr = image.at<cv::Vec3b>(y, x);
      const int rgb[3] = {bgr[2], bgr[1], bgr[0]};
      if (colours.size() < 4096) colours.insert(rgb[0] << 16 | rgb[1] << 8 | rgb[2]);
      for (int c = 0; c < 3; ++c) {
        if (rgb[c] > 60 && 2 * rgb[c] > 3 * rgb[(c + 1) % 3] && 2 * rgb[c] > 3 * rgb[(c + 2) % 3]) ++dominant[c];
      }
    }
  }
  const double pixels = static_cast<double>(image.total());
  std::printf("width %d\nheight %d\ndistinct %zu\n", image.cols, image.rows, colours.size());
  std::printf("red %.6f\ngreen %.6f\nblue %.6f\n", dominant[0] / pixels, dominant[1] / pixels,
              dominant[2] / pixels);
  return 0;
}
