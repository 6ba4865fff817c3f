#include "pf2/core/camera_intrinsics.h"

#include <cstdio>
#include <fstream>

#include <gtest/gtest.h>

#include "pf2/core/error.h"

namespace pf2 {
namespace {

TEST(CameraIntrinsics, PresetsAreTheBenchmarkValues) {
  const CameraIntrinsics fr1 = CameraIntrinsics::preset("fr1");
  EXPECT_DOUBLE_EQ(fr1.fx, 517.3);
  EXPECT_DOUBLE_EQ(fr1.cy, 255.3);
  EXPECT_DOUBLE_EQ(CameraIntrinsics::preset("fr2").fx, 520.9);
  EXPECT_DOUBLE_EQ(CameraIntrinsics::preset("fr3").fy, 539.2);
  EXPECT_THROW(CameraIntrinsics::preset("fr4"), Error);
}

TEST(CameraIntrinsics, BonnPresetIsTheDatasetsValues) {
  const CameraIntrinsics bonn = CameraIntrinsics::preset("bonn");
  EXPECT_DOUBLE_EQ(bonn.fx, 542.822841);
  EXPECT_DOUBLE_EQ(bonn.fy, 542.576870);
  EXPECT_DOUBLE_EQ(bonn.cx, 315.593520);
  EXPECT_DOUBLE_EQ(bonn.cy, 237.756098);
  EXPECT_EQ(bonn.width, 640);
  EXPECT_EQ(bonn.height, 480);
  try {
    CameraIntrinsics::preset("fr4");
    FAIL() << "unknown preset accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("bonn"), std::string::npos) << e.what();
  }
}

TEST(CameraIntrinsics, ProjectInvertsBackProject) {
  const CameraIntrinsics k = CameraIntrinsics::tumFreiburg3();
  const Eigen::Vector3d p = k.backProject(100.5, 400.25, 2.5);
  EXPECT_NEAR(p.z(), 2.5, 1e-12);
  const Eigen::Vector2d uv = k.project(p);
  EXPECT_NEAR(uv.x(), 100.5, 1e-9);
  EXPECT_NEAR(uv.y(), 400.25, 1e-9);
}

TEST(CameraIntrinsics, SaveLoadRoundTripAndErrors) {
  const std::string path = testing::TempDir() + "pf2_camera.txt";
  CameraIntrinsics k = CameraIntrinsics::tumFreiburg2();
  k.width = 400;
  k.save(path);
  const CameraIntrinsics loaded = CameraIntrinsics::load(path);
  EXPECT_DOUBLE_EQ(loaded.fx, k.fx);
  EXPECT_DOUBLE_EQ(loaded.cy, k.cy);
  EXPECT_EQ(loaded.width, 400);

  std::ofstream(path) << "fx 500\nfy 500\r\ncx 1 2\n";
  try {
    CameraIntrinsics::load(path);
    FAIL() << "malformed line accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(path + ":3:"), std::string::npos) << e.what();
  }
  std::ofstream(path) << "# no height\nfx 500\nfy 500\ncx 1\ncy 2\nwidth 640\n";
  EXPECT_THROW(CameraIntrinsics::load(path), Error);
  // A key twice, an impossible focal length, a principal point outside the image: refused with
  // the line and the allowed range.
  const auto refused = [&](const std::string& text, const std::string& expected) {
    std::ofstream(path) << text;
    try {
      CameraIntrinsics::load(path);
      ADD_FAILURE() << "accepted: " << text;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  };
  const std::string rest = "cx 319.5\ncy 239.5\nwidth 640\nheight 480\n";
  refused("fx 500\nfx 510\nfy 500\n" + rest, ":2: key 'fx' set twice (first on line 1)");
  refused("fx 1e-9\nfy 500\n" + rest, ":1: fx = 1e-09: outside its range [10, 100000]");
  refused("fx 500\nfy 500\ncx 5000\ncy 239.5\nwidth 640\nheight 480\n", ":3: cx = 5000: outside its range [0, 639]");
  refused("fx 500\nfy 500\ncx 319.5\ncy -300\nwidth 640\nheight 480\n", ":4: cy = -300: outside its range [0, 479]");
  refused("fx nan\nfy 500\n" + rest, ":1: expected 'key value' with a finite number");
  std::remove(path.c_str());
  EXPECT_THROW(CameraIntrinsics::load(path), Error);
}

}  // namespace
}  // namespace pf2
