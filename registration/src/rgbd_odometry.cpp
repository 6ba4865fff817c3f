#include "pf2/registration/rgbd_odometry.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <mutex>
#include <numeric>
#include <vector>

#include <Eigen/Eigenvalues>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "pf2/core/error.h"

namespace pf2 {
namespace {

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;

// Pyramid level l of cv::pyrDown samples input pixel 2i at output pixel i, so pixel coordinates
// (and the principal point) halve exactly.
CameraIntrinsics levelIntrinsics(const CameraIntrinsics& k, int level) {
  CameraIntrinsics out = k;
  const double s = 1.0 / (1 << level);
  out.fx *= s;
  out.fy *= s;
  out.cx *= s;
  out.cy *= s;
  out.width = (k.width + (1 << level) - 1) >> level;
  out.height = (k.height + (1 << level) - 1) >> level;
  return out;
}

// Halves a depth map around even pixels (as pyrDown does for intensity): the mean of the 3x3
// neighbours that lie on the same surface as the centre; no centre depth -> 0. Averaging across a
// depth edge would invent points in mid-air, hence the band.
cv::Mat downsampleDepth(const cv::Mat& depth, int rows, int cols) {
  cv::Mat out(rows, cols, CV_32F, cv::Scalar(0));
  for (int v = 0; v < rows; ++v) {
    float* dst = out.ptr<float>(v);
    const int v0 = 2 * v;
    for (int u = 0; u < cols; ++u) {
      const int u0 = 2 * u;
      if (v0 >= depth.rows || u0 >= depth.cols) continue;
      const float zc = depth.at<float>(v0, u0);
      if (!(zc > 0.0f)) continue;
      const float band = 0.03f * zc;
      float sum = 0.0f;
      int n = 0;
      for (int dv = -1; dv <= 1; ++dv) {
        const int vv = v0 + dv;
        if (vv < 0 || vv >= depth.rows) continue;
        const float* row = depth.ptr<float>(vv);
        for (int du = -1; du <= 1; ++du) {
          const int uu = u0 + du;
          if (uu < 0 || uu >= depth.cols) continue;
          const float z = row[uu];
          if (z > 0.0f && std::fabs(z - zc) < band) {
            sum += z;
            ++n;
          }
        }
      }
      dst[u] = sum / n;
    }
  }
  return out;
}

// Unit normals from neighbouring points `step` pixels away; one-sided differences at holes,
// nothing across depth jumps larger than max_jump (relative to depth).
cv::Mat computeNormals(const cv::Mat& depth, const CameraIntrinsics& k, int step, double max_jump) {
  cv::Mat normals(depth.size(), CV_32FC3, cv::Scalar(0, 0, 0));
  auto point = [&](int u, int v, Eigen::Vector3f* p) {
    if (u < 0 || v < 0 || u >= depth.cols || v >= depth.rows) return false;
    const float z = depth.at<float>(v, u);
    if (!(z > 0.0f)) return false;
    *p = Eigen::Vector3f(static_cast<float>((u - k.cx) * z / k.fx),
                         static_cast<float>((v - k.cy) * z / k.fy), z);
    return true;
  };
  cv::parallel_for_(cv::Range(0, depth.rows), [&](const cv::Range& range) {
    for (int v = range.start; v < range.end; ++v) {
      cv::Vec3f* dst = normals.ptr<cv::Vec3f>(v);
      for (int u = 0; u < depth.cols; ++u) {
        Eigen::Vector3f pc;
        if (!point(u, v, &pc)) continue;
        const float jump = static_cast<float>(max_jump * step) * pc.z();
        auto near = [&](int uu, int vv, Eigen::Vector3f* p) {
          return point(uu, vv, p) && std::fabs(p->z() - pc.z()) < jump;
        };
        Eigen::Vector3f a, b, dx, dy;
        const bool right = near(u + step, v, &a), left = near(u - step, v, &b);
        if (right && left) dx = a - b;
        else if (right) dx = a - pc;
        else if (left) dx = pc - b;
        else continue;
        const bool down = near(u, v + step, &a), up = near(u, v - step, &b);
        if (down && up) dy = a - b;
        else if (down) dy = a - pc;
        else if (up) dy = pc - b;
        else continue;
        Eigen::Vector3f n = dx.cross(dy);
        const float norm = n.norm();
        if (!(norm > 0.0f)) continue;
        n /= norm;
        if (n.dot(pc) > 0.0f) n = -n;  // face the camera
        dst[u] = cv::Vec3f(n.x(), n.y(), n.z());
      }
    }
  });
  return normals;
}

inline float bilinear(const cv::Mat& image, float u, float v) {
  const int u0 = static_cast<int>(u), v0 = static_cast<int>(v);
  const float a = u - u0, b = v - v0;
  const float* r0 = image.ptr<float>(v0) + u0;
  const float* r1 = image.ptr<float>(v0 + 1) + u0;
  return (1 - b) * ((1 - a) * r0[0] + a * r0[1]) + b * ((1 - a) * r1[0] + a * r1[1]);
}

inline double huberWeight(double e, double k) {
  const double a = std::fabs(e);
  return a <= k ? 1.0 : k / a;
}

// x_{k+1} = exp(delta) x_k with delta = (translation, rotation vector): the left perturbation
// the Jacobians below are taken for.
Eigen::Isometry3d applyUpdate(const Vector6d& delta, const Eigen::Isometry3d& T) {
  Eigen::Isometry3d D = Eigen::Isometry3d::Identity();
  const Eigen::Vector3d phi = delta.tail<3>();
  const double angle = phi.norm();
  if (angle > 1e-12) D.linear() = Eigen::AngleAxisd(angle, phi / angle).toRotationMatrix();
  D.translation() = delta.head<3>();
  Eigen::Isometry3d out = D * T;
  // Re-orthonormalise so rounding never accumulates into a non-rotation.
  out.linear() = Eigen::Quaterniond(out.rotation()).normalized().toRotationMatrix();
  return out;
}

// Current-frame samples of one level, structure of arrays for a tight inner loop.
struct Samples {
  std::vector<Eigen::Vector3f> points;  // p_cur
  std::vector<float> intensity;         // I_cur at the sample
};

// A regular grid over the level, its step chosen so that about max_points samples have depth:
// beyond ~10^4 points the pose hardly improves while the cost grows linearly.
Samples sampleLevel(const OdometryLevel& level, int max_points) {
  Samples s;
  const CameraIntrinsics& k = level.intrinsics;
  const int valid = cv::countNonZero(level.depth);
  const int stride =
      std::max(1, static_cast<int>(std::ceil(std::sqrt(double(valid) / std::max(1, max_points)))));
  s.points.reserve(valid / (stride * stride) + level.depth.cols);
  s.intensity.reserve(s.points.capacity());
  for (int v = 0; v < level.depth.rows; v += stride) {
    const float* z_row = level.depth.ptr<float>(v);
    const float* i_row = level.intensity.ptr<float>(v);
    for (int u = 0; u < level.depth.cols; u += stride) {
      const float z = z_row[u];
      if (!(z > 0.0f)) continue;
      s.points.emplace_back(static_cast<float>((u - k.cx) * z / k.fx),
                            static_cast<float>((v - k.cy) * z / k.fy), z);
      s.intensity.push_back(i_row[u]);
    }
  }
  return s;
}

// Float sums per stripe (a few thousand points) keep the inner loop vectorised; stripes are
// added up in double.
struct StripeSums {
  Eigen::Matrix<float, 6, 6> H = Eigen::Matrix<float, 6, 6>::Zero();
  Eigen::Matrix<float, 6, 1> b = Eigen::Matrix<float, 6, 1>::Zero();
};

// Histogram of |photometric residual| for the measured noise: bins of 1/400 up to 0.2 (the last
// bin holds everything larger).
constexpr int kScaleBins = 80;
constexpr float kScaleBinWidth = 0.0025f;

struct Accumulator {
  Matrix6d H = Matrix6d::Zero();
  Vector6d b = Vector6d::Zero();
  int associated = 0;
  int inliers = 0;
  double geometric_sq = 0.0;
  double photometric_sq = 0.0;
  // Intensity pairs (I_cur, I_ref) of the inliers, for the brightness fit.
  double sum_cur = 0.0, sum_ref = 0.0, sum_cur_sq = 0.0, sum_cur_ref = 0.0;
  std::array<int, kScaleBins> photometric_histogram{};  // of the associated points

  void addPhotometric(float r_i) {
    ++photometric_histogram[std::min(kScaleBins - 1, static_cast<int>(std::fabs(r_i) / kScaleBinWidth))];
  }
  void addInlier(float r_g, float r_i, float i_cur, float i_ref) {
    ++inliers;
    geometric_sq += r_g * r_g;
    photometric_sq += r_i * r_i;
    sum_cur += i_cur;
    sum_ref += i_ref;
    sum_cur_sq += i_cur * i_cur;
    sum_cur_ref += i_cur * i_ref;
  }

  void add(const Accumulator& o) {
    for (int k = 0; k < kScaleBins; ++k) photometric_histogram[k] += o.photometric_histogram[k];
    H += o.H;
    b += o.b;
    associated += o.associated;
    inliers += o.inliers;
    geometric_sq += o.geometric_sq;
    photometric_sq += o.photometric_sq;
    sum_cur += o.sum_cur;
    sum_ref += o.sum_ref;
    sum_cur_sq += o.sum_cur_sq;
    sum_cur_ref += o.sum_cur_ref;
  }
};

// Auto exposure and white balance change the brightness of a whole frame when a person in a
// white or dark sweater fills the view; uncompensated, the photometric term then pulls the pose
// tens of centimetres away. I_ref ~ gain * I_cur + bias, fitted by least squares to the inliers'
// intensity pairs of the last iteration (alternating with the pose, as in direct sparse odometry's
// affine brightness model); the gain is kept to [0.5, 2] and left alone on too few pairs.
struct Brightness {
  float gain = 1.0f, bias = 0.0f;
  void fit(const Accumulator& a) {
    if (a.inliers < 100) return;
    const double n = a.inliers;
    const double var = a.sum_cur_sq / n - (a.sum_cur / n) * (a.sum_cur / n);
    if (!(var > 1e-6)) return;
    const double cov = a.sum_cur_ref / n - (a.sum_cur / n) * (a.sum_ref / n);
    gain = static_cast<float>(std::clamp(cov / var, 0.5, 2.0));
    bias = static_cast<float>(a.sum_ref / n - gain * a.sum_cur / n);
  }
};

// 1.4826 x the median absolute photometric residual (a normal distribution's sigma), clamped to
// [lo, hi]; `hi` when fewer than 100 points were associated.
double measuredIntensitySigma(const Accumulator& a, double lo, double hi) {
  const int total = std::accumulate(a.photometric_histogram.begin(), a.photometric_histogram.end(), 0);
  if (total < 100) return hi;
  int seen = 0, k = 0;
  while (k < kScaleBins - 1 && (seen += a.photometric_histogram[k]) < total / 2) ++k;
  return std::clamp(1.4826 * (k + 0.5) * kScaleBinWidth, lo, hi);
}

// Adds the Gaussian prior r = log(T T_prior^-1) (to first order: translation of the error and its
// rotation vector; the Jacobian under the left perturbation is the identity) to the normal
// equations.
void addMotionPriorTerm(const Eigen::Isometry3d& T, const Eigen::Isometry3d& T_prior, double sigma_t,
                        double sigma_r, Matrix6d* H, Vector6d* b) {
  const Eigen::Isometry3d E = T * T_prior.inverse();
  const Eigen::AngleAxisd rotation(E.rotation());
  Vector6d r;
  r.head<3>() = E.translation();
  r.tail<3>() = rotation.angle() * rotation.axis();
  Vector6d w;
  w.head<3>().setConstant(sigma_t > 0.0 ? 1.0 / (sigma_t * sigma_t) : 0.0);
  w.tail<3>().setConstant(sigma_r > 0.0 ? 1.0 / (sigma_r * sigma_r) : 0.0);
  H->diagonal() += w;
  *b += w.cwiseProduct(r);
}

// One Gauss-Newton iteration's normal equations (and statistics) over the samples at pose T.
Accumulator accumulate(const RgbdOdometry::Options& options, const OdometryLevel& ref,
                       const Samples& samples, const Eigen::Isometry3d& T, const Brightness& brightness,
                       double sigma_i) {
  const double lambda = options.photometric_weight;
  const double inv_sigma_i2 = 1.0 / (sigma_i * sigma_i);
  const CameraIntrinsics& k = ref.intrinsics;
  const float fx = static_cast<float>(k.fx), fy = static_cast<float>(k.fy);
  const float cx = static_cast<float>(k.cx), cy = static_cast<float>(k.cy);
  const int W = ref.depth.cols, H = ref.depth.rows;
  const Eigen::Matrix3f R = T.rotation().cast<float>();
  const Eigen::Vector3f tr = T.translation().cast<float>();
  const int n = static_cast<int>(samples.points.size());
  const auto sumRange = [&](int begin, int end) {
    Accumulator acc;
    StripeSums sums;
    Eigen::Matrix<float, 6, 1> J;
    for (int i = begin; i < end; ++i) {
      const Eigen::Vector3f q = R * samples.points[i] + tr;
      if (q.z() < options.min_depth) continue;
      const float inv_z = 1.0f / q.z();
      const float u = fx * q.x() * inv_z + cx, v = fy * q.y() * inv_z + cy;
      if (!(u >= 0.0f && v >= 0.0f && u < W - 1 && v < H - 1)) continue;
      const int ui = static_cast<int>(u + 0.5f), vi = static_cast<int>(v + 0.5f);
      const float z_ref = ref.depth.at<float>(vi, ui);
      if (!(z_ref > 0.0f) || std::fabs(z_ref - q.z()) > options.max_depth_difference * q.z()) continue;
      const cv::Vec3f& nv = ref.normals.at<cv::Vec3f>(vi, ui);
      if (nv[0] == 0.0f && nv[1] == 0.0f && nv[2] == 0.0f) continue;
      ++acc.associated;
      const Eigen::Vector3f nrm(nv[0], nv[1], nv[2]);
      const Eigen::Vector3f p_ref((ui - cx) * z_ref / fx, (vi - cy) * z_ref / fy, z_ref);

      // Point-to-plane: r = n . (q - p_ref), J = [n, q x n].
      const float r_g = nrm.dot(q - p_ref);
      const float z_noise = std::max(q.z(), static_cast<float>(options.depth_sigma_floor_depth));
      const float sigma_g = static_cast<float>(options.depth_sigma) * z_noise * z_noise;
      const float w_g = static_cast<float>(huberWeight(r_g / sigma_g, options.huber_k)) / (sigma_g * sigma_g);
      J.head<3>() = nrm;
      J.tail<3>() = q.cross(nrm);
      sums.H.noalias() += (w_g * J) * J.transpose();
      sums.b.noalias() += (w_g * r_g) * J;

      // Photometric: r = I_ref(pi(q)) - (gain I_cur + bias), J = dI/du * du/dq * [I, -[q]x].
      const float i_ref = bilinear(ref.intensity, u, v);
      const float r_i = i_ref - (brightness.gain * samples.intensity[i] + brightness.bias);
      if (lambda > 0.0) {
        const float gx = bilinear(ref.gradient_x, u, v) * fx * inv_z;
        const float gy = bilinear(ref.gradient_y, u, v) * fy * inv_z;
        const Eigen::Vector3f g(gx, gy, -(gx * q.x() + gy * q.y()) * inv_z);
        const float w_i =
            static_cast<float>(lambda * inv_sigma_i2 * huberWeight(r_i / sigma_i, options.photometric_huber_k));
        J.head<3>() = g;
        J.tail<3>() = q.cross(g);
        sums.H.noalias() += (w_i * J) * J.transpose();
        sums.b.noalias() += (w_i * r_i) * J;
      }
      acc.addPhotometric(r_i);
      if (std::fabs(r_g) < options.inlier_distance) acc.addInlier(r_g, r_i, samples.intensity[i], i_ref);
    }
    acc.H = sums.H.cast<double>();
    acc.b = sums.b.cast<double>();
    return acc;
  };
  // Fixed chunks, summed in their order: the sums do not depend on which thread ran which chunk,
  // so a run repeats exactly (map.synchronous with a synchronous back end).
  constexpr int kChunk = 2000;
  const int chunks = std::max(1, (n + kChunk - 1) / kChunk);
  std::vector<Accumulator> parts(chunks);
  cv::parallel_for_(cv::Range(0, chunks), [&](const cv::Range& range) {
    for (int c = range.start; c < range.end; ++c) parts[c] = sumRange(c * kChunk, std::min(n, (c + 1) * kChunk));
  }, chunks);
  Accumulator total;
  for (const Accumulator& part : parts) total.add(part);
  return total;
}


// The figures of the last iteration and the Options' verdict on them.
DenseAlignment verdict(const RgbdOdometry::Options& options, const Eigen::Isometry3d& T,
                       const Eigen::Isometry3d& T_start, const Accumulator& last, int samples) {
  DenseAlignment result;
  result.T_ref_cur = T;
  result.sampled_points = samples;
  result.associated_points = last.associated;
  result.inlier_points = last.inliers;
  result.inlier_ratio = samples > 0 ? double(last.inliers) / samples : 0.0;
  if (last.inliers > 0) {
    result.geometric_rmse = std::sqrt(last.geometric_sq / last.inliers);
    result.photometric_rmse = std::sqrt(last.photometric_sq / last.inliers);
  }
  const Eigen::SelfAdjointEigenSolver<Matrix6d> eig(last.H, Eigen::EigenvaluesOnly);
  const double lo = eig.eigenvalues()(0), hi = eig.eigenvalues()(5);
  result.hessian_condition = lo > 0.0 ? hi / lo : std::numeric_limits<double>::infinity();
  const double moved = (T.translation() - T_start.translation()).norm();
  result.valid = T.matrix().allFinite() && result.inlier_points >= options.min_inliers &&
                 result.inlier_ratio >= options.min_inlier_ratio &&
                 result.hessian_condition <= options.max_condition &&
                 moved <= options.max_motion_from_prior;
  return result;
}

}  // namespace

struct RgbdOdometry::UndistortMaps {
  std::mutex mutex;
  cv::Size size;
  CameraIntrinsics intrinsics;
  cv::Mat map_x, map_y;
};

RgbdOdometry::RgbdOdometry() : RgbdOdometry(Options()) {}
RgbdOdometry::RgbdOdometry(const Options& options)
    : options_(options), features_(options.features),
      undistort_(std::make_shared<UndistortMaps>()) {
  if (!options_.distortion.empty() && options_.distortion.size() != 4 &&
      options_.distortion.size() != 5 && options_.distortion.size() != 8)
    throw Error("RgbdOdometry: distortion needs 4, 5 or 8 coefficients");
  if (options_.pyramid_levels < 1 || options_.finest_level < 0 ||
      options_.finest_level >= options_.pyramid_levels || options_.max_points_per_level < 6)
    throw Error("RgbdOdometry: pyramid_levels, finest_level or max_points_per_level out of range");
}

OdometryFrame RgbdOdometry::prepare(const Frame& frame, const cv::Mat& person_mask) const {
  if (frame.rgb.type() != CV_8UC3 || frame.depth.type() != CV_32F)
    throw Error("RgbdOdometry::prepare: frame " + std::to_string(frame.index) +
                " needs CV_8UC3 colour and CV_32F depth");
  if (frame.rgb.size() != frame.depth.size())
    throw Error("RgbdOdometry::prepare: frame " + std::to_string(frame.index) +
                ": colour and depth differ in size");
  if (!person_mask.empty() &&
      (person_mask.type() != CV_8U || person_mask.size() != frame.depth.size()))
    throw Error("RgbdOdometry::prepare: frame " + std::to_string(frame.index) +
                ": person mask must be CV_8U of the frame's size");

  cv::Mat gray;
  cv::cvtColor(frame.rgb, gray, cv::COLOR_BGR2GRAY);
  if (options_.distortion.empty())
    return prepareGray(gray, frame.depth, frame.intrinsics, frame.timestamp, frame.index, person_mask);

  cv::Mat map_x, map_y;
  {
    std::lock_guard<std::mutex> lock(undistort_->mutex);
    const CameraIntrinsics& k = frame.intrinsics;
    const CameraIntrinsics& c = undistort_->intrinsics;
    if (undistort_->map_x.empty() || undistort_->size != gray.size() || c.fx != k.fx ||
        c.fy != k.fy || c.cx != k.cx || c.cy != k.cy) {
      const cv::Matx33d K(k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1);
      // Fixed-point maps remap about twice as fast as float ones.
      cv::initUndistortRectifyMap(K, options_.distortion, cv::noArray(), K, gray.size(), CV_16SC2,
                                  undistort_->map_x, undistort_->map_y);
      undistort_->size = gray.size();
      undistort_->intrinsics = k;
    }
    map_x = undistort_->map_x;
    map_y = undistort_->map_y;
  }
  // Depth and mask by nearest neighbour: interpolating across an edge invents surfaces.
  cv::Mat gray_r, depth_r, mask_r;
  cv::remap(gray, gray_r, map_x, map_y, cv::INTER_LINEAR);
  cv::remap(frame.depth, depth_r, map_x, map_y, cv::INTER_NEAREST, cv::BORDER_CONSTANT, 0);
  if (!person_mask.empty())
    cv::remap(person_mask, mask_r, map_x, map_y, cv::INTER_NEAREST, cv::BORDER_CONSTANT, 0);
  return prepareGray(gray_r, depth_r, frame.intrinsics, frame.timestamp, frame.index, mask_r);
}

OdometryFrame RgbdOdometry::prepare(const Keyframe& keyframe) const {
  cv::Mat depth;
  keyframe.depth.convertTo(depth, CV_32F, 1.0 / Keyframe::kDepthUnitsPerMetre);
  OdometryFrame out = prepareGray(keyframe.gray, depth, keyframe.intrinsics, keyframe.timestamp,
                                  keyframe.frame_index, cv::Mat());
  out.keypoints = keyframe.keypoints;
  out.descriptors = keyframe.descriptors;
  out.keypoint_points = keyframe.keypoint_points;
  out.has_features = true;
  makeReference(&out);
  return out;
}

OdometryFrame RgbdOdometry::prepareGray(const cv::Mat& gray, const cv::Mat& depth_m,
                                        const CameraIntrinsics& intrinsics, double timestamp,
                                        int index, const cv::Mat& person_mask) const {
  OdometryFrame out;
  out.timestamp = timestamp;
  out.index = index;
  out.gray = gray;
  cv::Mat depth = depth_m.clone();
  const float lo = static_cast<float>(options_.min_depth), hi = static_cast<float>(options_.max_depth);
  for (int v = 0; v < depth.rows; ++v) {
    float* row = depth.ptr<float>(v);
    for (int u = 0; u < depth.cols; ++u)
      if (!(row[u] >= lo && row[u] <= hi)) row[u] = 0.0f;  // also NaN
  }
  if (!person_mask.empty()) {
    // Dilated into an image of its own: into a header of person_mask it would grow the caller's mask.
    cv::Mat grown;
    if (options_.person_mask_dilation > 0) {
      const int r = options_.person_mask_dilation;
      cv::dilate(person_mask, grown,
                 cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * r + 1, 2 * r + 1)));
    } else {
      grown = person_mask;
    }
    depth.setTo(0.0f, grown > 0);
  }
  out.feature_mask = depth > 0.0f;
  out.valid_depth_pixels = cv::countNonZero(out.feature_mask);

  CameraIntrinsics k0 = intrinsics;
  k0.width = depth.cols;
  k0.height = depth.rows;
  out.levels.resize(options_.pyramid_levels);
  out.levels[0].intrinsics = k0;
  out.gray.convertTo(out.levels[0].intensity, CV_32F, 1.0 / 255.0);
  out.levels[0].depth = depth;
  for (int l = 1; l < options_.pyramid_levels; ++l) {
    OdometryLevel& level = out.levels[l];
    cv::pyrDown(out.levels[l - 1].intensity, level.intensity);
    level.intrinsics = levelIntrinsics(k0, l);
    level.depth = downsampleDepth(out.levels[l - 1].depth, level.intensity.rows, level.intensity.cols);
  }
  return out;
}

void RgbdOdometry::makeReference(OdometryFrame* frame) const {
  if (frame->is_reference) return;
  for (size_t l = 0; l < frame->levels.size(); ++l) {
    OdometryLevel& level = frame->levels[l];
    // Sobel 3x3 / 8: a smoothed central difference, in intensity per pixel.
    cv::Sobel(level.intensity, level.gradient_x, CV_32F, 1, 0, 3, 1.0 / 8.0);
    cv::Sobel(level.intensity, level.gradient_y, CV_32F, 0, 1, 3, 1.0 / 8.0);
    // Full-resolution depth is noisy pixel to pixel: take normals over two pixels there.
    level.normals = computeNormals(level.depth, level.intrinsics, l == 0 ? 2 : 1,
                                   options_.max_normal_depth_jump);
  }
  features_.extract(frame);
  frame->is_reference = true;
}

DenseAlignment RgbdOdometry::refine(const OdometryFrame& reference, const OdometryFrame& current,
                                    const Eigen::Isometry3d& T_ref_cur_guess,
                                    const Eigen::Isometry3d* T_ref_cur_prior) const {
  if (!reference.is_reference) throw Error("RgbdOdometry::refine: reference frame lacks gradients");
  if (reference.levels.size() != current.levels.size() ||
      static_cast<int>(reference.levels.size()) != options_.pyramid_levels)
    throw Error("RgbdOdometry::refine: frames prepared with other pyramid options");

  int iterations_run = 0;
  Eigen::Isometry3d T = T_ref_cur_guess;
  const int coarsest = options_.pyramid_levels - 1;
  Accumulator last;
  Brightness brightness;
  int last_samples = 0;
  for (int l = coarsest; l >= options_.finest_level; --l) {
    const Samples samples = sampleLevel(current.levels[l], options_.max_points_per_level);
    const int span = std::max(1, coarsest - options_.finest_level);
    const double t = coarsest == options_.finest_level ? 1.0 : double(coarsest - l) / span;
    const int iterations = static_cast<int>(std::lround(
        options_.iterations_coarse + t * (options_.iterations_fine - options_.iterations_coarse)));
    // Each level starts from the configured noise; later iterations use the measured one.
    double sigma_i = options_.intensity_sigma;
    for (int it = 0; it < iterations; ++it) {
      Accumulator total = accumulate(options_, reference.levels[l], samples, T, brightness, sigma_i);
      ++iterations_run;
      last = total;
      last_samples = static_cast<int>(samples.points.size());
      if (options_.photometric_weight > 0.0) brightness.fit(total);
      if (options_.min_intensity_sigma > 0.0)
        sigma_i = measuredIntensitySigma(total, options_.min_intensity_sigma, options_.intensity_sigma);
      if (total.associated < 6) break;
      if (T_ref_cur_prior) {
        addMotionPriorTerm(T, *T_ref_cur_prior, options_.prior_sigma_translation,
                           options_.prior_sigma_rotation, &total.H, &total.b);
      }
      const Vector6d delta = total.H.ldlt().solve(-total.b);
      if (!delta.allFinite()) break;
      T = applyUpdate(delta, T);
      if (delta.head<3>().norm() < options_.convergence_step &&
          delta.tail<3>().norm() < options_.convergence_step)
        break;
    }
  }
  DenseAlignment result = verdict(options_, T, T_ref_cur_guess, last, last_samples);
  result.iterations = iterations_run;
  return result;
}


OdometryResult RgbdOdometry::estimate(const OdometryFrame& reference, OdometryFrame* current,
                                      const Eigen::Isometry3d& T_ref_cur_guess) const {
  if (!reference.is_reference) throw Error("RgbdOdometry::estimate: reference not made a reference");
  OdometryResult result;
  Eigen::Isometry3d start = T_ref_cur_guess;
  if (options_.features_every_frame) {
    features_.extract(current);
    result.used_features = true;
    result.sparse = features_.align(reference, *current);
    if (result.sparse.valid) start = result.sparse.T_ref_cur;
  }
  result.dense = refine(reference, *current, start, &T_ref_cur_guess);
  if (!result.dense.valid && !result.used_features) {
    // The prior was not good enough (fast motion): start again from the features' pose.
    features_.extract(current);
    result.used_features = true;
    result.sparse = features_.align(reference, *current);
    if (result.sparse.valid) {
      const DenseAlignment retry = refine(reference, *current, result.sparse.T_ref_cur, &T_ref_cur_guess);
      if (retry.valid || retry.inlier_ratio > result.dense.inlier_ratio) result.dense = retry;
    }
  }
  result.valid = result.dense.valid;
  result.T_ref_cur = result.dense.T_ref_cur;
  return result;
}

OdometryResult RgbdOdometry::estimateWithoutPrior(const OdometryFrame& reference,
                                                  OdometryFrame* current) const {
  if (!reference.is_reference)
    throw Error("RgbdOdometry::estimateWithoutPrior: reference not made a reference");
  features_.extract(current);
  OdometryResult result;
  result.used_features = true;
  result.sparse = features_.align(reference, *current);
  if (!result.sparse.valid) return result;
  result.dense = refine(reference, *current, result.sparse.T_ref_cur);
  result.valid = result.dense.valid;
  result.T_ref_cur = result.dense.T_ref_cur;
  return result;
}

}  // namespace pf2
