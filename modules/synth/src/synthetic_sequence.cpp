#include "pf2/synth/synthetic_sequence.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <future>
#include <map>
#include <mutex>
#include <sstream>


#include "pf2/core/atomic_file.h"
#include "pf2/core/error.h"
#include "pf2/io/image_file.h"
#include "pf2/io/trajectory_io.h"
#include "pf2/synth/people.h"
#include "hash_random.h"
#include "parallel_for.h"

namespace pf2 {

namespace {

std::string stampText(double t) {
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "%.6f", t);
  return buffer;
}

// Colour averaged along each pixel's image motion during the exposure; depth of pixels whose
// motion crosses a depth edge becomes the mixed value a real sensor reports there.
void motionBlur(const cv::Mat& bgr, const cv::Mat& depth, const cv::Mat& labels,
                const CameraIntrinsics& K, const Eigen::Isometry3d& T_w_c,
                const Eigen::Isometry3d& T_w_c_begin, const Eigen::Isometry3d& T_w_c_end,
                const std::vector<Eigen::Vector3d>& person_shift_begin,
                const std::vector<Eigen::Vector3d>& person_shift_end, cv::Mat* blurred_bgr,
                cv::Mat* mixed_depth) {
  constexpr int kSamples = 9;
  const Eigen::Isometry3d T_begin_c = T_w_c_begin.inverse() * T_w_c;
  const Eigen::Isometry3d T_end_c = T_w_c_end.inverse() * T_w_c;
  const Eigen::Matrix3d R_w_c = T_w_c.linear();
  *blurred_bgr = bgr.clone();
  *mixed_depth = depth.clone();
  synth::parallelFor(0, bgr.rows, true, [&](int v) {
    for (int u = 0; u < bgr.cols; ++u) {
      const float z = depth.at<float>(v, u);
      if (!(z > 0.0f)) continue;
      const Eigen::Vector3d p_c = K.backProject(u, v, z);
      const int label = labels.at<std::uint16_t>(v, u);
      Eigen::Vector3d shift_begin_c = Eigen::Vector3d::Zero(), shift_end_c = Eigen::Vector3d::Zero();
      if (label > 0 && label <= static_cast<int>(person_shift_begin.size())) {
        // A person's point moves with the person (translation only).
        shift_begin_c = R_w_c.transpose() * person_shift_begin[label - 1];
        shift_end_c = R_w_c.transpose() * person_shift_end[label - 1];
      }
      const Eigen::Vector3d a = T_begin_c * (p_c + shift_begin_c);
      const Eigen::Vector3d b = T_end_c * (p_c + shift_end_c);
      if (a.z() <= 0.05 || b.z() <= 0.05) continue;
      const Eigen::Vector2d pa = K.project(a), pb = K.project(b);
      if ((pb - pa).squaredNorm() < 0.25) continue;  // under half a pixel: no visible blur
      cv::Vec3f sum(0, 0, 0);
      float z_min = z, z_max = z, z_sum = 0.0f;
      int count = 0, depth_count = 0;
      for (int k = 0; k < kSamples; ++k) {
        const Eigen::Vector2d q = pa + (pb - pa) * (k / (kSamples - 1.0));
        if (q.x() < 0.0 || q.y() < 0.0 || q.x() > bgr.cols - 1.0 || q.y() > bgr.rows - 1.0) continue;
        // Colour: bilinear, so that the smear is smooth; depth: nearest pixel, as a sensor mixes.
        const int x0 = std::min(static_cast<int>(q.x()), bgr.cols - 2), y0 = std::min(static_cast<int>(q.y()), bgr.rows - 2);
        const float fx = static_cast<float>(q.x() - x0), fy = static_cast<float>(q.y() - y0);
        sum += (1 - fx) * (1 - fy) * cv::Vec3f(bgr.at<cv::Vec3b>(y0, x0)) +
               fx * (1 - fy) * cv::Vec3f(bgr.at<cv::Vec3b>(y0, x0 + 1)) +
               (1 - fx) * fy * cv::Vec3f(bgr.at<cv::Vec3b>(y0 + 1, x0)) +
               fx * fy * cv::Vec3f(bgr.at<cv::Vec3b>(y0 + 1, x0 + 1));
        ++count;
        const float zs = depth.at<float>(static_cast<int>(std::lround(q.y())), static_cast<int>(std::lround(q.x())));
        if (zs > 0.0f) {
          z_min = std::min(z_min, zs);
          z_max = std::max(z_max, zs);
          z_sum += zs;
          ++depth_count;
        }
      }
      if (count > 0) blurred_bgr->at<cv::Vec3b>(v, u) = cv::Vec3b(sum / static_cast<float>(count) + cv::Vec3f(0.5f, 0.5f, 0.5f));
      if (depth_count > 0 && z_max - z_min > 0.05f * z) mixed_depth->at<float>(v, u) = z_sum / depth_count;
    }
  });
}

const char* const kGroundTruthReadme = R"(# Ground truth of a synthetic PoseFusion2 sequence

Written by pf2_synth (docs/synth.md in the PoseFusion2 repository). The folder above is a TUM RGB-D
sequence: rgb/<stamp>.png (8-bit colour), depth/<stamp>.png (16-bit, metres x 5000, 0 = no
measurement), rgb.txt, depth.txt, groundtruth.txt (`timestamp tx ty tz qx qy qz qw`, T_w_c: camera to
world) and camera.txt (`fx fy cx cy width height` lines). Lines starting with `#` are comments.

World frame (of groundtruth.txt and every file here): the room's frame, z up, floor at z = 0, the
room spans [0, 6] x [0, 5] x [0, 3] metres; it is not the first camera frame. Camera frame: x right,
y down, z forward. Timestamps are written with 6 decimals exactly as in rgb.txt, so files join on them.

| file | content |
| --- | --- |
| masks/<stamp>.png | 16-bit single channel, same names as depth/: 0 = static scene, k >= 1 = person id k |
| boxes.txt | `timestamp id x_ul y_ul x_lr y_lr visible_fraction`, one line per visible person per frame: the tight box of the person's mask pixels (inclusive pixel coordinates); visible_fraction = visible pixels / pixels the person would cover with nothing in front and no image border, in [0, 1] |
| people.txt | `timestamp id x y z` per frame per person in the scene (visible or not): pelvis position, world frame, metres |
| bodies.txt | `timestamp id tx ty tz r0x r0y r0z ... r23x r23y r23z b0 ... b9`: body model parameters of each person per frame: root translation, 24 axis-angle joint rotations relative to the parent (SMPL order; the root rotation includes the body's world orientation), 10 shape coefficients; evaluating the body model with them gives the person's mesh in the world frame |
| joints.txt | `timestamp id j0x j0y j0z ... j23x j23y j23z`: posed 3D joints, SMPL order, world frame, metres |
| static_scene.ply | the static scene as a triangle mesh (metres, world frame) |

Ids are stable small integers (1 .. number of people). Masks and boxes describe the colour image; with
a misalignment of PX pixels (pf2_synth --misalign PX) the depth image is shifted PX pixels to the right
of them, so depth pixel (u, v) belongs to mask pixel (u - PX, v). Depth carries the Kinect-like sensor
model unless the sequence was made with --noise none.
)";

// The gt/README.md paragraph of a sequence made with close people.
std::string closeCrossingsNote(const Crowd::CloseCrossings& close) {
  char text[1024];
  std::snprintf(text, sizeof(text),
                "\nMade with close people (pf2_synth --close): one after the other, people walk across the view,\n"
                "entering at one side edge of the image and leaving at the other, the nearest point of their\n"
                "path %.2g-%.2g m from the camera centre (floor distance to the person's axis); some stop there\n"
                "for a moment facing the camera. A person covers a large part of some frames and is cut by the\n"
                "image border; away from their crossings people stay out of view or farther than %.2g m.\n",
                close.min_distance, close.max_distance, close.max_distance);
  return text;
}

// Sequences with the same seed share one scene (baking its textures takes a while).
std::shared_ptr<const StaticScene> sharedScene(std::uint64_t seed, double texels_per_metre) {
  static std::mutex mutex;
  static std::map<std::pair<std::uint64_t, double>, std::weak_ptr<const StaticScene>> cache;
  std::lock_guard<std::mutex> lock(mutex);
  auto& entry = cache[{seed, texels_per_metre}];
  std::shared_ptr<const StaticScene> scene = entry.lock();
  if (!scene) {
    StaticScene::Options scene_options;
    scene_options.seed = seed;
    scene_options.texels_per_metre = texels_per_metre;
    scene = std::make_shared<const StaticScene>(scene_options);
    entry = scene;
  }
  return scene;
}

// Loading the default body model takes a quarter of a second; sequences share it.
std::shared_ptr<const BodyModel> sharedDefaultBodyModel() {
  static std::mutex mutex;
  static std::weak_ptr<const BodyModel> cache;
  std::lock_guard<std::mutex> lock(mutex);
  std::shared_ptr<const BodyModel> model = cache.lock();
  if (!model) {
    model = std::make_shared<const BodyModel>(BodyModel::loadDefault());
    cache = model;
  }
  return model;
}

}  // namespace

SyntheticSequence::SyntheticSequence(const Options& options)
    : options_(options), rasterizer_(options.rasterizer), sensor_(options.sensor) {
  if (options.frames < 1) throw Error("frames must be at least 1");
  if (!(options.fps > 0.0)) throw Error("fps must be positive");
  if (options.people < 0 || options.people > 5) throw Error("people must be between 0 and 5");
  if (options.intrinsics.width < 8 || options.intrinsics.height < 8) throw Error("image too small");
  if (std::abs(options.sensor.misalign_px) >= options.intrinsics.width / 4) {
    throw Error("misalignment must be smaller than a quarter of the image width");
  }
  if (!(options.exposure >= 0.0 && options.exposure <= 1.0 / options.fps)) {
    throw Error("exposure must lie between 0 and one frame interval");
  }
  scene_ = sharedScene(options.seed, options.texels_per_metre);
  std::shared_ptr<const BodyModel> model;
  if (options.people > 0) model = sharedDefaultBodyModel();
  Crowd::Options crowd_options = options.crowd;
  crowd_options.people = options.people;
  crowd_options.seed = options.seed;
  crowd_options.duration = options.frames / options.fps;
  crowd_options.close.enabled = options.close_people;
  // Close crossings are planned where the camera will look; the wider half of the image decides
  // where a person is out of view.
  Crowd::CameraPath camera;
  const CameraMotion motion = options.camera;
  const double duration = crowd_options.duration;
  camera.pose_at = [motion, duration](double t) { return cameraPoseAt(motion, t, duration); };
  const CameraIntrinsics& K = options.intrinsics;
  camera.half_view_tan = std::max(K.cx, K.width - K.cx) / K.fx;
  crowd_ = std::make_unique<Crowd>(crowd_options, *scene_, model, camera);
}

SyntheticSequence::~SyntheticSequence() = default;

std::string SyntheticSequence::description() const {
  std::ostringstream text;
  text << "synthetic " << cameraMotionName(options_.camera) << ", " << options_.people << " people, "
       << options_.frames << " frames, seed " << options_.seed
       << (options_.sensor.noise ? ", kinect noise" : ", exact depth")
       << (options_.close_people ? ", close people" : "");
  return text.str();
}

double SyntheticSequence::timestamp(size_t i) const { return options_.start_time + i / options_.fps; }

Eigen::Isometry3d SyntheticSequence::pose(size_t i) const {
  return cameraPoseAt(options_.camera, i / options_.fps, options_.frames / options_.fps);
}

std::vector<BodyMesh> SyntheticSequence::bodies(size_t i) const {
  std::vector<BodyMesh> result;
  for (int k = 0; k < crowd_->size(); ++k) result.push_back(crowd_->pose(k, i / options_.fps).mesh);
  return result;
}

Frame SyntheticSequence::frame(size_t i) const { return frame(i, nullptr); }

Frame SyntheticSequence::frame(size_t i, FrameGroundTruth* truth) const {
  if (i >= size()) throw Error("frame " + std::to_string(i) + " out of range (" + std::to_string(size()) + " frames)");
  const double t = i / options_.fps;
  const CameraIntrinsics& K = options_.intrinsics;
  const Eigen::Isometry3d T_w_c = pose(i);

  std::vector<Crowd::Posed> posed(crowd_->size());
  std::vector<RenderMesh> person_meshes(crowd_->size());
  for (int k = 0; k < crowd_->size(); ++k) {
    posed[k] = crowd_->pose(k, t);
    person_meshes[k] = bodyRenderMesh(posed[k].mesh, crowd_->colors(k), static_cast<std::uint16_t>(k + 1));
  }
  std::vector<const RenderMesh*> meshes = {&scene_->mesh()};
  for (const RenderMesh& mesh : person_meshes) meshes.push_back(&mesh);
  RenderedImages images;
  rasterizer_.render(meshes, scene_->textures(), K, T_w_c, &images);

  Frame frame;
  frame.index = static_cast<int>(i);
  frame.timestamp = timestamp(i);
  frame.intrinsics = K;
  cv::Mat depth = images.depth;
  frame.rgb = images.bgr;
  if (options_.motion_blur && options_.exposure > 0.0) {
    const double half = 0.5 * options_.exposure;
    const double duration = options_.frames / options_.fps;
    std::vector<Eigen::Vector3d> shift_begin, shift_end;
    for (int k = 0; k < crowd_->size(); ++k) {
      const Eigen::Vector3d now = posed[k].mesh.joints[0];
      shift_begin.push_back(crowd_->pose(k, t - half).mesh.joints[0] - now);
      shift_end.push_back(crowd_->pose(k, t + half).mesh.joints[0] - now);
    }
    motionBlur(images.bgr, images.depth, images.labels, K, T_w_c,
               cameraPoseAt(options_.camera, t - half, duration),
               cameraPoseAt(options_.camera, t + half, duration), shift_begin, shift_end,
               &frame.rgb, &depth);
  }
  frame.depth = sensor_.apply(depth, K, synth::hashOf(options_.seed, i, 0xde9f));

  if (truth) {
    truth->timestamp = frame.timestamp;
    truth->T_w_c = T_w_c;
    truth->labels = images.labels;
    truth->exact_depth = images.depth;
    truth->people.assign(crowd_->size(), PersonGroundTruth());
    std::vector<int> min_x(crowd_->size(), K.width), max_x(crowd_->size(), -1);
    std::vector<int> min_y(crowd_->size(), K.height), max_y(crowd_->size(), -1);
    for (int v = 0; v < images.labels.rows; ++v) {
      const std::uint16_t* row = images.labels.ptr<std::uint16_t>(v);
      for (int u = 0; u < images.labels.cols; ++u) {
        if (row[u] == 0) continue;
        const int k = row[u] - 1;
        ++truth->people[k].visible_pixels;
        min_x[k] = std::min(min_x[k], u);
        max_x[k] = std::max(max_x[k], u);
        min_y[k] = std::min(min_y[k], v);
        max_y[k] = std::max(max_y[k], v);
      }
    }
    for (int k = 0; k < crowd_->size(); ++k) {
      PersonGroundTruth& person = truth->people[k];
      person.id = k + 1;
      person.body = posed[k].parameters;
      person.joints_w = posed[k].mesh.joints;
      person.pelvis_w = posed[k].mesh.joints[0];
      if (person.visible_pixels == 0) continue;
      person.box = cv::Rect(min_x[k], min_y[k], max_x[k] - min_x[k] + 1, max_y[k] - min_y[k] + 1);
      const double unoccluded = rasterizer_.unboundedCoverage(person_meshes[k], K, T_w_c);
      person.visible_fraction = std::min(1.0, person.visible_pixels / std::max(1.0, unoccluded));
    }
  }
  return frame;
}

void SyntheticSequence::writeTumFolder(const std::string& out_dir,
                                       const std::function<void(size_t)>& progress) const {
  namespace fs = std::filesystem;
  for (const char* sub : {"", "rgb", "depth", "gt", "gt/masks"}) {
    std::error_code error;
    fs::create_directories(fs::path(out_dir) / sub, error);
    if (error) throw fileError((fs::path(out_dir) / sub).string(), "cannot create folder: " + error.message());
  }
  const std::string dir = out_dir.empty() || out_dir.back() == '/' ? out_dir : out_dir + "/";
  std::ostringstream rgb_list, depth_list, boxes, people, bodies, joints;
  rgb_list << "# color images\n# file: synthetic (PoseFusion2 pf2_synth)\n# timestamp filename\n";
  depth_list << "# depth maps\n# file: synthetic (PoseFusion2 pf2_synth)\n# timestamp filename\n";
  boxes << "# timestamp id x_ul y_ul x_lr y_lr visible_fraction\n";
  people << "# timestamp id x y z\n";
  bodies << "# timestamp id tx ty tz r0x r0y r0z ... r23x r23y r23z b0 ... b9\n";
  joints << "# timestamp id j0x j0y j0z ... j23x j23y j23z\n";
  Trajectory trajectory;
  char number[64];
  const auto put = [&number](std::ostringstream& out, double value) {
    std::snprintf(number, sizeof(number), " %.6g", value);
    out << number;
  };

  // Encoding PNGs of frame i overlaps rendering frame i + 1 (the machine has two cores).
  std::future<void> pending;
  for (size_t i = 0; i < size(); ++i) {
    FrameGroundTruth truth;
    const Frame frame = this->frame(i, &truth);
    const std::string stamp = stampText(frame.timestamp);
    cv::Mat depth_png;
    frame.depth.convertTo(depth_png, CV_16U, 5000.0);
    if (pending.valid()) pending.get();
    pending = std::async(std::launch::async, [dir, stamp, rgb = frame.rgb, depth_png, labels = truth.labels]() {
      writeImageFile(dir + "rgb/" + stamp + ".png", rgb);
      writeImageFile(dir + "depth/" + stamp + ".png", depth_png);
      writeImageFile(dir + "gt/masks/" + stamp + ".png", labels);
    });
    rgb_list << stamp << " rgb/" << stamp << ".png\n";
    depth_list << stamp << " depth/" << stamp << ".png\n";
    trajectory.push_back({frame.timestamp, truth.T_w_c});
    for (const PersonGroundTruth& person : truth.people) {
      if (person.visible_pixels > 0) {
        std::snprintf(number, sizeof(number), " %.4f", person.visible_fraction);
        boxes << stamp << " " << person.id << " " << person.box.x << " " << person.box.y << " "
              << person.box.x + person.box.width - 1 << " " << person.box.y + person.box.height - 1
              << number << "\n";
      }
      people << stamp << " " << person.id;
      for (int c = 0; c < 3; ++c) put(people, person.pelvis_w[c]);
      people << "\n";
      bodies << stamp << " " << person.id;
      for (int c = 0; c < 3; ++c) put(bodies, person.body.translation[c]);
      for (const auto& r : person.body.pose) {
        for (int c = 0; c < 3; ++c) put(bodies, r[c]);
      }
      for (int b = 0; b < 10; ++b) put(bodies, b < person.body.shape.size() ? person.body.shape[b] : 0.0);
      bodies << "\n";
      joints << stamp << " " << person.id;
      for (const auto& j : person.joints_w) {
        for (int c = 0; c < 3; ++c) put(joints, j[c]);
      }
      joints << "\n";
    }
    if (progress) progress(i + 1);
  }
  if (pending.valid()) pending.get();

  const auto text = [](const std::string& path, const std::string& content) {
    writeFileAtomically(path, [&content](std::ostream& out) { out << content; });
  };
  text(dir + "rgb.txt", rgb_list.str());
  text(dir + "depth.txt", depth_list.str());
  writeTrajectory(dir + "groundtruth.txt", trajectory);
  options_.intrinsics.save(dir + "camera.txt");
  text(dir + "gt/boxes.txt", boxes.str());
  text(dir + "gt/people.txt", people.str());
  text(dir + "gt/bodies.txt", bodies.str());
  text(dir + "gt/joints.txt", joints.str());
  scene_->savePly(dir + "gt/static_scene.ply");
  std::ostringstream readme;
  readme << kGroundTruthReadme << "\nThis folder: " << description() << ", misalignment "
         << options_.sensor.misalign_px << " px" << (options_.motion_blur ? ", motion blur" : "")
         << ", " << options_.intrinsics.width << "x" << options_.intrinsics.height << " at "
         << options_.fps << " Hz.\n";
  if (options_.close_people) readme << closeCrossingsNote(options_.crowd.close);
  text(dir + "gt/README.md", readme.str());
}

}  // namespace pf2
