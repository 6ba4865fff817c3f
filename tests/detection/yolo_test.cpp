#include "pf2/detection/yolo_detector.h"

#include <cstdint>
#include <fstream>

#include <gtest/gtest.h>

#include "pf2/core/error.h"
#include "test_folder.h"

namespace pf2 {
namespace {

// A (1, rows, cols) float tensor from a row-major list.
cv::Mat tensor(int rows, int cols, const std::vector<float>& values) {
  const int sizes[3] = {1, rows, cols};
  cv::Mat t(3, sizes, CV_32F, cv::Scalar(0));
  std::copy(values.begin(), values.end(), t.ptr<float>());
  return t;
}

TEST(YoloDecode, V5RowsScoreIsObjectnessTimesPersonClass) {
  // Two classes for brevity: rows (cx, cy, w, h, obj, person, other) in a 320x320 input.
  const cv::Mat out = tensor(3, 7, {160, 80, 40, 100, 0.9f, 0.8f, 0.1f,     // 0.72: kept
                                     50, 50, 10, 10, 0.9f, 0.5f, 0.9f,      // 0.45: person too weak
                                     100, 100, 20, 20, 0.4f, 0.99f, 0.0f}); // 0.396
  const auto c = decodeYoloOutput(out, YoloLayout::kV5, {320, 320}, {640, 480}, 0.5f);
  ASSERT_EQ(c.size(), 1u);
  EXPECT_NEAR(c[0].score, 0.72f, 1e-6);
  // Scaled by 2 in x, 1.5 in y: centre (320, 120), size 80 x 150.
  EXPECT_FLOAT_EQ(c[0].box.x, 280.f);
  EXPECT_FLOAT_EQ(c[0].box.y, 45.f);
  EXPECT_FLOAT_EQ(c[0].box.width, 80.f);
  EXPECT_FLOAT_EQ(c[0].box.height, 150.f);
}

TEST(YoloDecode, V8ColumnsHaveNoObjectness) {
  // (1, 4 + 2 classes, 3 candidates): columns are candidates.
  const cv::Mat out = tensor(6, 3, {320, 100, 10,    // cx
                                     240, 100, 10,    // cy
                                     64, 20, 4,       // w
                                     128, 40, 4,      // h
                                     0.9f, 0.51f, 0.2f,  // person
                                     0.0f, 0.9f, 0.9f}); // other class
  const auto c = decodeYoloOutput(out, YoloLayout::kV8, {640, 640}, {640, 480}, 0.5f);
  ASSERT_EQ(c.size(), 2u);
  EXPECT_FLOAT_EQ(c[0].score, 0.9f);
  EXPECT_FLOAT_EQ(c[0].box.x, 288.f);
  EXPECT_FLOAT_EQ(c[0].box.y, 132.f);  // (240 - 64) * 0.75
  EXPECT_FLOAT_EQ(c[0].box.height, 96.f);
  EXPECT_FLOAT_EQ(c[1].score, 0.51f);
}

TEST(YoloDecode, DarknetRowsAreRelativeToTheImage) {
  cv::Mat out(2, 7, CV_32F, cv::Scalar(0));
  const float row[7] = {0.5f, 0.5f, 0.25f, 0.5f, 0.95f, 0.9f, 0.0f};
  std::copy(row, row + 7, out.ptr<float>(0));
  const auto c = decodeYoloOutput(out, YoloLayout::kDarknet, {416, 416}, {640, 480}, 0.5f);
  ASSERT_EQ(c.size(), 1u);
  EXPECT_FLOAT_EQ(c[0].box.x, 240.f);
  EXPECT_FLOAT_EQ(c[0].box.width, 160.f);
  EXPECT_FLOAT_EQ(c[0].box.y, 120.f);
  EXPECT_FLOAT_EQ(c[0].score, 0.9f);
}

TEST(YoloDecode, WrongShapesThrow) {
  EXPECT_THROW(decodeYoloOutput(tensor(3, 4, std::vector<float>(12, 0)), YoloLayout::kV5, {32, 32}, {32, 32}, 0.5f),
               Error);
  EXPECT_THROW(decodeYoloOutput(tensor(3, 2, std::vector<float>(6, 0)), YoloLayout::kV8, {32, 32}, {32, 32}, 0.5f),
               Error);
  EXPECT_THROW(decodeYoloOutput(cv::Mat(), YoloLayout::kV5, {32, 32}, {32, 32}, 0.5f), Error);
}

TEST(YoloNms, KeepsTheBestOfOverlappingBoxes) {
  std::vector<YoloCandidate> c(4);
  c[0] = {cv::Rect2f(0, 0, 100, 200), 0.7f};
  c[1] = {cv::Rect2f(5, 5, 100, 200), 0.9f};    // IoU with c[0] ~0.86
  c[2] = {cv::Rect2f(300, 0, 100, 200), 0.6f};  // apart
  c[3] = {cv::Rect2f(50, 0, 100, 200), 0.8f};   // IoU with c[1] ~0.4: kept at 0.45
  const auto kept = suppressNonMaxima(c, 0.45f);
  ASSERT_EQ(kept.size(), 3u);
  EXPECT_FLOAT_EQ(kept[0].score, 0.9f);
  EXPECT_FLOAT_EQ(kept[1].score, 0.8f);
  EXPECT_FLOAT_EQ(kept[2].score, 0.6f);
  EXPECT_EQ(suppressNonMaxima(c, 0.3f).size(), 2u);
  EXPECT_TRUE(suppressNonMaxima({}, 0.5f).empty());
}

// A Darknet network written here: one 1x1 convolution (3 -> 255 channels) and a [yolo] layer with
// three 8x16 anchors on a 32x32 grid. Anchor 0 sees a person wherever the input pixel is white:
// objectness logit 20 (R + G + B) - 30, person logit +20, everything else -20.
void writeTinyDarknet(const std::string& cfg, const std::string& weights) {
  writeText(cfg,
            "[net]\nwidth=32\nheight=32\nchannels=3\n\n"
            "[convolutional]\nfilters=255\nsize=1\nstride=1\npad=0\nactivation=linear\n\n"
            "[yolo]\nmask=0,1,2\nanchors=8,16, 8,16, 8,16\nclasses=80\nnum=3\n");
  std::vector<float> bias(255, -20.f), w(255 * 3, 0.f);
  for (int a = 0; a < 3; ++a) {
    for (int k = 0; k < 4; ++k) bias[a * 85 + k] = 0.f;  // tx, ty -> cell centre; tw, th -> anchor
  }
  bias[4] = -30.f;
  for (int c = 0; c < 3; ++c) w[4 * 3 + c] = 20.f;
  bias[5] = 20.f;
  std::ofstream out(weights, std::ios::binary);
  const int32_t version[3] = {0, 2, 0};
  const uint64_t seen = 0;
  out.write(reinterpret_cast<const char*>(version), sizeof(version));
  out.write(reinterpret_cast<const char*>(&seen), sizeof(seen));
  out.write(reinterpret_cast<const char*>(bias.data()), bias.size() * sizeof(float));
  out.write(reinterpret_cast<const char*>(w.data()), w.size() * sizeof(float));
}

TEST(YoloDetector, TinyDarknetNetworkEndToEnd) {
  const std::string dir = freshTestFolder("pf2_yolo_tiny");
  YoloDetector::Options o;
  o.model = dir + "/tiny.cfg";
  o.weights = dir + "/tiny.weights";
  o.input_width = o.input_height = 32;
  writeTinyDarknet(o.model, o.weights);
  YoloDetector detector(o);
  EXPECT_EQ(detector.name(), "yolo");
  Frame frame;
  frame.timestamp = 3.0;
  frame.rgb = cv::Mat::zeros(64, 64, CV_8UC3);  // resized to 32x32: 2x2 image pixels per cell
  frame.rgb(cv::Rect(20, 40, 4, 4)).setTo(cv::Scalar(255, 255, 255));  // cells (10..11, 20..21)
  const Detections d = detector.detect(frame);
  // Four neighbouring cells fire with 8x16 (input) boxes one cell apart; NMS keeps one.
  ASSERT_EQ(d.people.size(), 1u);
  EXPECT_EQ(d.timestamp, 3.0);
  EXPECT_GT(d.people[0].score, 0.9f);
  const float cu = 0.5f * (d.people[0].box.x_ul + d.people[0].box.x_lr);
  const float cv_ = 0.5f * (d.people[0].box.y_ul + d.people[0].box.y_lr);
  EXPECT_NEAR(cu, 22.f, 2.1f);   // cell centre (10.5 or 11.5) x 2
  EXPECT_NEAR(cv_, 42.f, 2.1f);
  EXPECT_NEAR(d.people[0].box.width(), 16.f, 1e-3);
  EXPECT_NEAR(d.people[0].box.height(), 32.f, 1e-3);
  frame.rgb.setTo(0);
  EXPECT_TRUE(detector.detect(frame).people.empty());
}

TEST(YoloDetector, MissingOrBrokenFilesAreErrors) {
  const std::string dir = freshTestFolder("pf2_yolo_bad");
  YoloDetector::Options o;
  EXPECT_THROW(YoloDetector d(o), Error);  // no model
  o.model = dir + "/missing.cfg";
  EXPECT_THROW(YoloDetector d(o), Error);
  o.model = dir + "/broken.onnx";
  writeText(o.model, "not a protobuf");
  try {
    YoloDetector d(o);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("broken.onnx"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace pf2
