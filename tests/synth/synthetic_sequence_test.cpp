#include "pf2/synth/synthetic_sequence.h"

#include <sys/stat.h>

#include <cstdio>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "mesh_distance.h"
#include "pf2/core/error.h"
#include "pf2/io/tum_sequence.h"

namespace pf2 {
namespace {

// Small and fast: 320 x 240, coarse textures, exact depth unless a test asks for noise.
SyntheticSequence::Options smallOptions(int frames, int people) {
  SyntheticSequence::Options options;
  options.frames = frames;
  options.people = people;
  options.intrinsics = CameraIntrinsics::tumFreiburg3().scaled(0.5);
  options.sensor.noise = false;
  options.texels_per_metre = 32;  // coarse textures bake fast; geometry is what these tests check
  return options;
}

// All tests use seed 1: keep its scene alive so that it is built once.
class KeepScene : public testing::Environment {
 public:
  void SetUp() override { sequence_ = std::make_unique<SyntheticSequence>(smallOptions(1, 0)); }
  void TearDown() override { sequence_.reset(); }

 private:
  std::unique_ptr<SyntheticSequence> sequence_;
};
testing::Environment* const keep_scene = testing::AddGlobalTestEnvironment(new KeepScene);

std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

TEST(SyntheticSequence, StaticPixelsBackProjectOntoTheSceneMesh) {
  SyntheticSequence::Options options = smallOptions(90, 3);
  options.camera = CameraMotion::kHalfsphere;
  const SyntheticSequence sequence(options);
  const test::MeshDistance scene(sequence.scene().mesh().vertices, sequence.scene().mesh().triangles);
  for (const size_t i : {0, 45, 89}) {
    FrameGroundTruth truth;
    const Frame frame = sequence.frame(i, &truth);
    std::vector<double> distances;
    for (int v = 1; v < frame.depth.rows; v += 4) {
      for (int u = 1; u < frame.depth.cols; u += 4) {
        const float z = frame.depth.at<float>(v, u);
        if (z == 0.0f || truth.labels.at<std::uint16_t>(v, u) != 0) continue;
        const Eigen::Vector3d p_w = truth.T_w_c * frame.intrinsics.backProject(u, v, z);
        distances.push_back(scene.distance(p_w));
      }
    }
    ASSERT_GT(distances.size(), 2000u);
    EXPECT_LT(test::median(distances), 0.002) << "frame " << i;
    std::sort(distances.begin(), distances.end());
    EXPECT_LT(distances[distances.size() * 95 / 100], 0.005) << "frame " << i;
  }
}

TEST(SyntheticSequence, PersonPixelsBackProjectOntoTheirBody) {
  const SyntheticSequence sequence(smallOptions(200, 3));
  int people_checked = 0;
  for (const size_t i : {0, 100, 199}) {
    FrameGroundTruth truth;
    const Frame frame = sequence.frame(i, &truth);
    const std::vector<BodyMesh> bodies = sequence.bodies(i);
    ASSERT_EQ(bodies.size(), 3u);
    for (const PersonGroundTruth& person : truth.people) {
      if (person.visible_pixels < 200) continue;
      const BodyMesh& body = bodies[person.id - 1];
      // Ground-truth joints are those of the mesh.
      EXPECT_LT((body.joints[0] - person.pelvis_w).norm(), 1e-9);
      const test::MeshDistance mesh(body.vertices, body.triangles);
      std::vector<double> distances;
      for (int v = person.box.y; v < person.box.y + person.box.height; v += 2) {
        for (int u = person.box.x; u < person.box.x + person.box.width; u += 2) {
          const float z = frame.depth.at<float>(v, u);
          if (z == 0.0f || truth.labels.at<std::uint16_t>(v, u) != person.id) continue;
          distances.push_back(mesh.distance(truth.T_w_c * frame.intrinsics.backProject(u, v, z)));
        }
      }
      ASSERT_GT(distances.size(), 20u);
      EXPECT_LT(test::median(distances), 0.002) << "frame " << i << " person " << person.id;
      ++people_checked;
    }
  }
  EXPECT_GE(people_checked, 2);
}

TEST(SyntheticSequence, GroundTruthBoxesAndFractionsMatchTheLabels) {
  const SyntheticSequence sequence(smallOptions(300, 5));
  int visible = 0, partly_hidden = 0;
  for (size_t i = 0; i < 300; i += 30) {
    FrameGroundTruth truth;
    sequence.frame(i, &truth);
    ASSERT_EQ(truth.people.size(), 5u);
    std::map<int, int> counts;
    for (int v = 0; v < truth.labels.rows; ++v) {
      for (int u = 0; u < truth.labels.cols; ++u) {
        const int id = truth.labels.at<std::uint16_t>(v, u);
        ASSERT_LE(id, 5);
        if (id == 0) continue;
        ++counts[id];
        ASSERT_TRUE(truth.people[id - 1].box.contains({u, v}));
      }
    }
    for (const PersonGroundTruth& person : truth.people) {
      EXPECT_EQ(person.visible_pixels, counts[person.id]);
      EXPECT_GE(person.visible_fraction, 0.0);
      EXPECT_LE(person.visible_fraction, 1.0);
      if (person.visible_pixels == 0) {
        EXPECT_TRUE(person.box.empty());
        continue;
      }
      ++visible;
      EXPECT_GT(person.visible_fraction, 0.0);
      if (person.visible_fraction < 0.9) ++partly_hidden;
      // Pelvis on the floor plan, at a standing or sitting height.
      EXPECT_GT(person.pelvis_w.z(), 0.4);
      EXPECT_LT(person.pelvis_w.z(), 1.3);
    }
  }
  EXPECT_GT(visible, 10);
  EXPECT_GT(partly_hidden, 0);
}

TEST(SyntheticSequence, PeopleMoveLeaveAndEnterTheView) {
  const SyntheticSequence sequence(smallOptions(300, 3));
  std::vector<bool> ever_visible(3, false), ever_hidden(3, false);
  std::vector<Eigen::Vector3d> first(3);
  double walked = 0.0;
  for (size_t i = 0; i < 300; i += 10) {
    FrameGroundTruth truth;
    sequence.frame(i, &truth);
    for (int k = 0; k < 3; ++k) {
      const PersonGroundTruth& person = truth.people[k];
      (person.visible_pixels > 0 ? ever_visible : ever_hidden)[k] = true;
      if (i == 0) first[k] = person.pelvis_w;
      walked = std::max(walked, (person.pelvis_w - first[k]).norm());
    }
  }
  int comes_and_goes = 0;
  for (int k = 0; k < 3; ++k) comes_and_goes += ever_visible[k] && ever_hidden[k];
  EXPECT_GE(comes_and_goes, 1);
  EXPECT_GT(walked, 1.0);
}

TEST(SyntheticSequence, WrittenFolderReadsBackAsTumSequence) {
  SyntheticSequence::Options options = smallOptions(4, 2);
  options.sensor.noise = true;
  const SyntheticSequence sequence(options);
  const std::string dir = testing::TempDir() + "pf2_synth_readback";
  sequence.writeTumFolder(dir);
  const TumSequence tum(dir);
  ASSERT_EQ(tum.size(), 4u);
  EXPECT_EQ(tum.intrinsics().width, 320);
  EXPECT_DOUBLE_EQ(tum.intrinsics().fx, options.intrinsics.fx);
  const Trajectory ground_truth = tum.groundTruth();
  ASSERT_EQ(ground_truth.size(), 4u);
  for (size_t i = 0; i < 4; ++i) {
    FrameGroundTruth truth;
    const Frame expected = sequence.frame(i, &truth);
    const Frame frame = tum.frame(i);
    EXPECT_NEAR(frame.timestamp, expected.timestamp, 1e-6);
    EXPECT_EQ(cv::norm(frame.rgb, expected.rgb, cv::NORM_INF), 0.0);
    EXPECT_LE(cv::norm(frame.depth, expected.depth, cv::NORM_INF), 0.5 / 5000.0 + 1e-6);
    EXPECT_LT((ground_truth[i].T_w_c.translation() - truth.T_w_c.translation()).norm(), 1e-6);
    char stamp[64];
    std::snprintf(stamp, sizeof(stamp), "%.6f", expected.timestamp);
    const cv::Mat mask = cv::imread(dir + "/gt/masks/" + stamp + ".png", cv::IMREAD_UNCHANGED);
    ASSERT_EQ(mask.type(), CV_16UC1);
    EXPECT_EQ(cv::norm(mask, truth.labels, cv::NORM_INF), 0.0);
  }
  // Every ground-truth file has a header and one line per person per frame (boxes: visible only).
  for (const char* name : {"people.txt", "bodies.txt", "joints.txt"}) {
    std::istringstream lines(readFile(dir + "/gt/" + name));
    std::string line;
    int rows = 0;
    size_t columns = 0;
    while (std::getline(lines, line)) {
      if (line.empty() || line[0] == '#') continue;
      std::istringstream fields(line);
      columns = std::distance(std::istream_iterator<std::string>(fields), std::istream_iterator<std::string>());
      ++rows;
    }
    EXPECT_EQ(rows, 8) << name;
    const size_t expected_columns = std::string(name) == "people.txt" ? 5 : std::string(name) == "bodies.txt" ? 2 + 3 + 72 + 10 : 2 + 72;
    EXPECT_EQ(columns, expected_columns) << name;
  }
  const std::string ply = readFile(dir + "/gt/static_scene.ply");
  EXPECT_EQ(ply.rfind("ply\nformat ascii 1.0", 0), 0u);
  EXPECT_NE(readFile(dir + "/gt/README.md").find("boxes.txt"), std::string::npos);
}

TEST(SyntheticSequence, SameSeedSameBytesOtherSeedOtherScene) {
  SyntheticSequence::Options options = smallOptions(3, 2);
  options.sensor.noise = true;
  const std::string a = testing::TempDir() + "pf2_synth_seed_a", b = testing::TempDir() + "pf2_synth_seed_b";
  SyntheticSequence(options).writeTumFolder(a);
  SyntheticSequence(options).writeTumFolder(b);
  const TumSequence tum(a);
  for (size_t i = 0; i < tum.size(); ++i) {
    for (const std::string& file : {tum.files(i).rgb.file, tum.files(i).depth.file}) {
      EXPECT_EQ(readFile(a + "/" + file), readFile(b + "/" + file)) << file;
    }
  }
  for (const char* file : {"groundtruth.txt", "gt/boxes.txt", "gt/bodies.txt", "gt/static_scene.ply"}) {
    EXPECT_EQ(readFile(a + "/" + file), readFile(b + "/" + file)) << file;
  }
  options.seed = 2;
  const Frame other = SyntheticSequence(options).frame(0);
  const Frame first = tum.frame(0);
  EXPECT_GT(cv::norm(other.rgb, first.rgb, cv::NORM_L1) / other.rgb.total(), 5.0);
}

TEST(SyntheticSequence, MotionBlurSmearsColourWhenTheCameraMoves) {
  SyntheticSequence::Options options = smallOptions(90, 0);
  options.camera = CameraMotion::kRpy;
  const SyntheticSequence sharp(options);
  options.motion_blur = true;
  const SyntheticSequence blurred(options);
  // At t = 2 s the camera rolls fastest (0.7 rad/s); gradients get weaker under blur.
  const auto gradient = [](const cv::Mat& bgr) {
    cv::Mat gray, dx;
    cv::cvtColor(bgr, gray, cv::COLOR_BGR2GRAY);
    cv::Sobel(gray, dx, CV_32F, 1, 0);
    return cv::norm(dx, cv::NORM_L1);
  };
  EXPECT_LT(gradient(blurred.frame(60).rgb), 0.85 * gradient(sharp.frame(60).rgb));
  // Standing still (t = 0) there is nothing to smear.
  EXPECT_EQ(cv::norm(blurred.frame(0).rgb, sharp.frame(0).rgb, cv::NORM_INF), 0.0);
}

// FNV-1a over bytes: a fingerprint of generated output.
std::uint64_t fingerprint(const void* data, size_t size, std::uint64_t hash = 1469598103934665603ULL) {
  const auto* bytes = static_cast<const unsigned char*>(data);
  for (size_t i = 0; i < size; ++i) hash = (hash ^ bytes[i]) * 1099511628211ULL;
  return hash;
}

std::uint64_t fingerprint(const cv::Mat& image, std::uint64_t hash) {
  return fingerprint(image.data, image.total() * image.elemSize(), hash);
}

// Labels, colour and depth of frames 0, 100 and 299 and every person's pelvis every 10th frame (to
// 0.1 mm) of a 300-frame sequence.
std::uint64_t sequenceFingerprint(const SyntheticSequence& sequence) {
  std::uint64_t hash = fingerprint(nullptr, 0);
  for (const size_t i : {0, 100, 299}) {
    FrameGroundTruth truth;
    const Frame frame = sequence.frame(i, &truth);
    hash = fingerprint(frame.depth, fingerprint(frame.rgb, fingerprint(truth.labels, hash)));
  }
  for (size_t i = 0; i < sequence.size(); i += 10) {
    for (const BodyMesh& body : sequence.bodies(i)) {
      char text[96];
      const Eigen::Vector3d& pelvis = body.joints[0];
      const int n = std::snprintf(text, sizeof(text), "%.4f %.4f %.4f\n", pelvis.x(), pelvis.y(), pelvis.z());
      hash = fingerprint(text, static_cast<size_t>(n), hash);
    }
  }
  return hash;
}

// Sequences made without close people and with people free to walk through each other
// (crowd.min_separation 0) are those of the code before either option existed: these
// fingerprints were taken from that code (GCC 12, x86-64). Floating-point results of another
// compiler or maths library may differ; then regenerate them from a build of that older code.
TEST(SyntheticSequence, WithoutClosePeopleOrSeparationTheOutputIsUnchanged) {
  SyntheticSequence::Options options = smallOptions(300, 3);
  options.crowd.min_separation = 0.0;
  EXPECT_EQ(sequenceFingerprint(SyntheticSequence(options)), 0x6d82f5eb5cef14c4ULL) << "seed 1, 3 people, xyz";
  options = smallOptions(300, 5);
  options.crowd.min_separation = 0.0;
  options.seed = 2;
  options.camera = CameraMotion::kLoop;
  options.sensor.noise = true;
  options.motion_blur = true;
  EXPECT_EQ(sequenceFingerprint(SyntheticSequence(options)), 0xa163405c29701bf9ULL)
      << "seed 2, 5 people, loop, noise, blur";
}

// The smallest floor distance between two people's pelvises over every frame of `sequence`, metres.
double nearestPelvises(const SyntheticSequence& sequence) {
  double nearest = 1e9;
  for (size_t i = 0; i < sequence.size(); ++i) {
    const std::vector<BodyMesh> bodies = sequence.bodies(i);
    for (size_t a = 0; a < bodies.size(); ++a) {
      for (size_t b = a + 1; b < bodies.size(); ++b) {
        nearest = std::min(nearest, (bodies[a].joints[0] - bodies[b].joints[0]).head<2>().norm());
      }
    }
  }
  return nearest;
}

// People do not walk through each other: three people on seeds 1-8 keep crowd.min_separation
// (0.6 m) between their pelvises, up to how the gait sways the pelvis; free to (min_separation 0),
// people of these seeds come within 0.3 m of each other. (Close crossings and the walks to them
// are not kept apart: see Crowd::Options.)
TEST(SyntheticSequence, PeopleKeepTheirSeparation) {
  double nearest_free = 1e9;
  for (std::uint64_t seed = 1; seed <= 8; ++seed) {
    SyntheticSequence::Options options = smallOptions(300, 3);
    options.seed = seed;
    const double nearest = nearestPelvises(SyntheticSequence(options));
    std::printf("seed %d: nearest pelvises %.3f m\n", static_cast<int>(seed), nearest);
    EXPECT_GE(nearest, 0.55) << "seed " << seed;
    options.crowd.min_separation = 0.0;
    nearest_free = std::min(nearest_free, nearestPelvises(SyntheticSequence(options)));
  }
  EXPECT_LT(nearest_free, 0.3);
}

// What close people do to the view, measured on the ground-truth labels of every `step`-th frame.
struct CloseViewStats {
  double largest_person = 0.0;  // largest fraction of the image one person covers in one frame
  bool cut_at_side = false;     // a person covering at least 5 % touches the left or right border
  double mean_static = 0.0;     // mean over frames of the fraction of static pixels
  double min_static = 1.0;
  int longest_covered_run = 0;  // frames in a row (of those measured) with under 10 % static pixels
};

CloseViewStats measureCloseView(const SyntheticSequence& sequence, size_t step) {
  CloseViewStats stats;
  int frames = 0, run = 0;
  for (size_t i = 0; i < sequence.size(); i += step) {
    FrameGroundTruth truth;
    sequence.frame(i, &truth);
    const cv::Mat& labels = truth.labels;
    const double pixels = static_cast<double>(labels.total());
    for (const PersonGroundTruth& person : truth.people) {
      const double covered = person.visible_pixels / pixels;
      stats.largest_person = std::max(stats.largest_person, covered);
      const bool at_side = person.visible_pixels > 0 &&
                           (person.box.x == 0 || person.box.x + person.box.width == labels.cols);
      if (covered >= 0.05 && at_side) stats.cut_at_side = true;
    }
    const double static_fraction = cv::countNonZero(labels == 0) / pixels;
    stats.mean_static += static_fraction;
    stats.min_static = std::min(stats.min_static, static_fraction);
    run = static_fraction < 0.1 ? run + 1 : 0;
    stats.longest_covered_run = std::max(stats.longest_covered_run, run);
    ++frames;
  }
  stats.mean_static /= std::max(1, frames);
  return stats;
}

TEST(SyntheticSequence, ClosePeopleFillMuchOfTheViewAreCutAtTheSidesAndLeaveTheRoomVisible) {
  for (const CameraMotion camera : {CameraMotion::kStatic, CameraMotion::kXyz, CameraMotion::kHalfsphere,
                                    CameraMotion::kRpy, CameraMotion::kLoop}) {
    SyntheticSequence::Options options = smallOptions(150, 3);
    options.camera = camera;
    options.close_people = true;
    const CloseViewStats stats = measureCloseView(SyntheticSequence(options), 3);
    std::printf("close people, camera %-10s largest person %.3f, cut at a side %s, static mean %.3f min %.3f, "
                "longest run under 10 %% static %d\n",
                cameraMotionName(camera), stats.largest_person, stats.cut_at_side ? "yes" : "no", stats.mean_static,
                stats.min_static, stats.longest_covered_run);
    EXPECT_GE(stats.largest_person, 0.25) << cameraMotionName(camera);
    EXPECT_TRUE(stats.cut_at_side) << cameraMotionName(camera);
    EXPECT_GE(stats.mean_static, 0.35) << cameraMotionName(camera);
    EXPECT_LE(stats.longest_covered_run, 3) << cameraMotionName(camera);
  }
}

TEST(SyntheticSequence, ClosePeopleAreDeterministicAndRecorded) {
  SyntheticSequence::Options options = smallOptions(60, 2);
  options.close_people = true;
  options.sensor.noise = true;
  const SyntheticSequence a(options), b(options);
  options.close_people = false;
  const SyntheticSequence plain(options);
  FrameGroundTruth truth_a, truth_b, truth_plain;
  const Frame frame_a = a.frame(40, &truth_a), frame_b = b.frame(40, &truth_b);
  plain.frame(40, &truth_plain);
  EXPECT_EQ(cv::norm(frame_a.rgb, frame_b.rgb, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(frame_a.depth, frame_b.depth, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(truth_a.labels, truth_b.labels, cv::NORM_INF), 0.0);
  EXPECT_GT(cv::norm(truth_a.labels, truth_plain.labels, cv::NORM_L1), 0.0);
  EXPECT_NE(a.description().find("close people"), std::string::npos);
  EXPECT_EQ(plain.description().find("close"), std::string::npos);

  options = smallOptions(2, 1);
  options.close_people = true;
  const std::string dir = testing::TempDir() + "pf2_synth_close";
  SyntheticSequence(options).writeTumFolder(dir);
  EXPECT_NE(readFile(dir + "/gt/README.md").find("Made with close people"), std::string::npos);
}

TEST(SyntheticSequence, RejectsBadOptions) {
  SyntheticSequence::Options options = smallOptions(0, 0);
  EXPECT_THROW(SyntheticSequence{options}, Error);
  options = smallOptions(10, 6);
  EXPECT_THROW(SyntheticSequence{options}, Error);
  options = smallOptions(10, 0);
  options.sensor.misalign_px = 200;
  EXPECT_THROW(SyntheticSequence{options}, Error);
  options = smallOptions(10, 1);
  options.close_people = true;
  options.crowd.close.min_distance = 0.2;
  EXPECT_THROW(SyntheticSequence{options}, Error);
  options.crowd.close.min_distance = 0.7;
  options.crowd.close.max_bend = 1.0;
  EXPECT_THROW(SyntheticSequence{options}, Error);
  options = smallOptions(10, 2);
  options.crowd.min_separation = -0.1;
  EXPECT_THROW(SyntheticSequence{options}, Error);
  options.crowd.min_separation = 2.5;
  EXPECT_THROW(SyntheticSequence{options}, Error);
  const SyntheticSequence sequence(smallOptions(2, 0));
  EXPECT_THROW(sequence.frame(2), Error);
  EXPECT_THROW(sequence.writeTumFolder("/proc/pf2_cannot_write_here"), Error);
}

}  // namespace
}  // namespace pf2
