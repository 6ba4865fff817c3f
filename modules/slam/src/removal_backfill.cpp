#include "pf2/slam/removal_backfill.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "pf2/core/error.h"

namespace pf2 {

namespace removal_backfill_internal {

// Points closer to a waiting camera than this are behind or at its lens.
constexpr float kMinDepth = 0.1f;

// Points of some frame x moved into a frame's image: q = A p_x + b is the pixel times the depth
// (q.z() the depth); one 3x3 product per point.
struct Projection {
  Eigen::Matrix3f A;
  Eigen::Vector3f b;
  // The nearest pixel of q in an image of `size`; false when behind the lens or out of view.
  bool pixel(const Eigen::Vector3f& q, const cv::Size& size, int* iu, int* iv) const {
    const float z = q.z();
    if (z < kMinDepth) return false;
    const float u = q.x() / z, v = q.y() / z;
    if (!(u >= -0.5f && v >= -0.5f && u < size.width - 0.5f && v < size.height - 0.5f)) return false;
    *iu = static_cast<int>(u + 0.5f);
    *iv = static_cast<int>(v + 0.5f);
    return true;
  }
};

// Another frame as seen from a frame's camera.
struct OtherView {
  Projection projection;    // from the frame's camera into the other's image
  const cv::Mat* depth;     // CV_32F, 0 = removed or none
  const cv::Mat* measured;  // CV_32F, the depth before removal (may be empty)
  const cv::Mat* hits;      // CV_8U, a later person carried there (may be empty)
  int reach = 0;            // pixels around a pixel looked at before free space is read there
};

}  // namespace removal_backfill_internal

namespace {

using removal_backfill_internal::OtherView;
using removal_backfill_internal::Projection;

// Moved points land about one every kStride pixels; a disc of this radius closes the gaps between
// them (an estimate on pf2_synth with every second pixel: 1 px left a tenth of the gain).
constexpr int kHitDilation = 2;
// A waiting frame where no more than this share of the points in its view meet its depth or its
// removed pixels did not have the people there; after kIdleFrames such frames in a row the older
// ones are not tried.
constexpr double kMinHitShare = 0.02;
constexpr int kIdleFrames = 2;
// Removed depth is looked for in other frames at one pixel of each kBlock x kBlock block (the
// looking is the costly part; one pixel of each 3 x 3 or 4 x 4 block, or every pixel, gave the same
// figures on the six pf2_synth hard cases within 0.04 points). Kept depth, most of the image, at
// one of each kKeptBlock x kKeptBlock block, found among every kKeptStep-th pixel and row.
constexpr int kBlock = 4;
constexpr int kKeptBlock = 8;
constexpr int kKeptStep = 2;

// Removed depth is given back only where at least this many times more other frames kept its
// surface than removed it: a seated person whom the other frames remove most of the time and miss
// now and then has not left (pf2_synth rpy, looking at later frames only: 0.8 points of the
// people's depth given back with no such rule, 0.24 with this one; the static depth given back 1.2
// and 0.9 points).
constexpr int kKeptOverRemoved = 2;
// Kept depth that other frames saw through is removed only where no more than this many of them
// kept its surface: a static point that one frame's error or noise moved past stays, since the
// others measured it.
constexpr int kMaxKeptViews = 1;

// Whether two depths (metres) are the same surface's: within tolerance + 1 % of b.
bool near(float a, float b, float tolerance) { return std::abs(a - b) < tolerance + 0.01f * b; }

// Into `frame`'s image from the frame x whose pose is T_w_x (identity: world points).
Projection projectionInto(const RemovalBackfill::Frame& frame, const Eigen::Isometry3d& T_w_x) {
  const CameraIntrinsics& k = frame.intrinsics;
  Eigen::Matrix3f K;
  K << static_cast<float>(k.fx), 0.f, static_cast<float>(k.cx), 0.f, static_cast<float>(k.fy),
      static_cast<float>(k.cy), 0.f, 0.f, 1.f;
  const Eigen::Isometry3f T_c_x = (frame.T_w_c->inverse() * T_w_x).cast<float>();
  return {K * T_c_x.linear(), K * T_c_x.translation()};
}

// Free space is read no nearer than this to a nearer surface (pixels), plus the farther of the two
// frames' turn from the frame before, in pixels: a real sensor's depth and its pose disagree by
// 10-25 px while it turns 2-3 degrees a frame (TUM fr1/rpy: rolling shutter, the depth image's
// own time), little when it is still.
constexpr int kFarReach = 15;

OtherView otherView(const RemovalBackfill::Frame& frame, double frame_turn, const RemovalBackfill::Frame& other,
                    double other_turn, const cv::Mat& hits) {
  const int turn_pixels = static_cast<int>(std::ceil(std::max(frame_turn, other_turn) * other.intrinsics.fx));
  return {projectionInto(other, *frame.T_w_c), &other.depth, &other.measured, &hits, kFarReach + turn_pixels};
}

enum class Seen { kNot, kKept, kRemoved, kThrough };

// The nearest depth (metres) measured around (u, v): every pixel within kEdgeReach (0 where one
// has none) and every kFarStep-th pixel and row within far_reach. Free space is only read where
// nothing nearer is close by: at a depth edge a small error of the pose or of the sensor moves the
// ray past the nearer surface, and the sensor's shadow beside a nearer surface (no depth) hides
// how near it is.
constexpr int kEdgeReach = 3;
constexpr int kFarStep = 3;
float nearestAround(const cv::Mat& depth, int u, int v, int far_reach) {
  float nearest = std::numeric_limits<float>::infinity();
  for (int y = std::max(v - kEdgeReach, 0); y <= std::min(v + kEdgeReach, depth.rows - 1); ++y) {
    const float* row = depth.ptr<float>(y);
    for (int x = std::max(u - kEdgeReach, 0); x <= std::min(u + kEdgeReach, depth.cols - 1); ++x) {
      if (!(row[x] > 0.f)) return 0.f;
      nearest = std::min(nearest, row[x]);
    }
  }
  for (int y = std::max(v - far_reach, 0); y <= std::min(v + far_reach, depth.rows - 1); y += kFarStep) {
    const float* row = depth.ptr<float>(y);
    for (int x = std::max(u - far_reach, 0); x <= std::min(u + far_reach, depth.cols - 1); x += kFarStep) {
      if (row[x] > 0.f) nearest = std::min(nearest, row[x]);
    }
  }
  return nearest;
}

// How far behind a point (metres, plus kThroughShare of its depth) another frame must have measured
// the scene around its pixel to have seen through it.
struct Margins {
  float tolerance = 0.f;  // metres, plus 1 % of the depth: the same surface
  float through = std::numeric_limits<float>::infinity();
};
constexpr float kThroughShare = 0.03f;

// What the view did with the surface at p: measured it within tolerance + 1 % of p's depth there
// and kept it (no later person carried there either), measured it there and removed it, kept what
// it measured well behind p all around its pixel (p was not there then: someone moved), or
// none of these (out of view, behind something, at a depth edge).
Seen seenThere(const OtherView& view, const Eigen::Vector3f& p, const Margins& margins) {
  const Eigen::Vector3f q = view.projection.A * p + view.projection.b;
  int iu = 0, iv = 0;
  if (!view.projection.pixel(q, view.depth->size(), &iu, &iv)) return Seen::kNot;
  const float z = q.z();
  const float near = margins.tolerance + 0.01f * z;
  const float d = view.depth->ptr<float>(iv)[iu];
  const bool carried = !view.hits->empty() && view.hits->ptr<uint8_t>(iv)[iu];
  if (d > 0.f && !carried && std::abs(d - z) < near) return Seen::kKept;
  const float behind = z + margins.through + kThroughShare * z;
  if (d > behind) {
    const float around = nearestAround(view.measured->empty() ? *view.depth : *view.measured, iu, iv, view.reach);
    return around > behind ? Seen::kThrough : Seen::kNot;
  }
  const float m = view.measured->empty() ? 0.f : view.measured->ptr<float>(iv)[iu];
  return (m > 0.f && std::abs(m - z) < near) ? Seen::kRemoved : Seen::kNot;
}

// A pixel looked for in the other frames (one per block and depth): its camera point, the block it
// answers for, and the other frames' votes so far.
struct Probe {
  Eigen::Vector3f p;
  int u0 = 0, v0 = 0;
  int kept = 0, removed = 0, through = 0;
  enum class Answer : uint8_t { kOpen, kChange, kStay } answer = Answer::kOpen;
};

// Counts the view's vote for each open removed probe and closes those the rest of the views (`rest`
// of them) cannot change: given back (kChange) when at least min_kept kept the surface and
// kKeptOverRemoved times as many kept it as removed it. One view at a time for all probes, so that
// its images are read in order (all views for each probe in turn read them all at random: 66 ns a
// look).
void voteGiveBack(const OtherView& view, int rest, const Margins& margins, int min_kept, std::vector<Probe>* probes) {
  for (Probe& probe : *probes) {
    if (probe.answer != Probe::Answer::kOpen) continue;
    const Seen seen = seenThere(view, probe.p, margins);
    probe.kept += seen == Seen::kKept;
    probe.removed += seen == Seen::kRemoved;
    if (probe.kept + rest < min_kept || probe.kept + rest < kKeptOverRemoved * probe.removed) {
      probe.answer = Probe::Answer::kStay;
    } else if (probe.kept >= min_kept && probe.kept >= kKeptOverRemoved * (probe.removed + rest)) {
      probe.answer = Probe::Answer::kChange;
    }
  }
}

// The same for a kept probe: removed (kChange) when at least min_through views saw through it and
// no more than kMaxKeptViews kept its surface.
void voteTake(const OtherView& view, int rest, const Margins& margins, int min_through, std::vector<Probe>* probes) {
  for (Probe& probe : *probes) {
    if (probe.answer != Probe::Answer::kOpen) continue;
    const Seen seen = seenThere(view, probe.p, margins);
    probe.kept += seen == Seen::kKept;
    probe.through += seen == Seen::kThrough;
    if (probe.kept > kMaxKeptViews || probe.through + rest < min_through) {
      probe.answer = Probe::Answer::kStay;
    } else if (probe.through >= min_through && probe.kept + rest <= kMaxKeptViews) {
      probe.answer = Probe::Answer::kChange;
    }
  }
}

// A frame's camera point at pixel (u, v) and depth z (metres).
Eigen::Vector3f cameraPoint(const CameraIntrinsics& k, int u, int v, float z) {
  return {static_cast<float>((u - k.cx) / k.fx) * z, static_cast<float>((v - k.cy) / k.fy) * z, z};
}

// One probe per block x block block of an image of `size` and depth in it (two at most: a person's
// outline), which answers for the block's candidates near its depth; looked for at every step-th
// pixel and row of the block. depth(u, v) is a candidate's depth (metres), 0 elsewhere; `mask`, if
// not empty, is 0 where no candidate can be (read before depth(u, v), which may cost more).
template <typename Depth>
std::vector<Probe> blockProbes(const cv::Size& size, const cv::Mat& mask, int block, int step,
                               const CameraIntrinsics& k, const Depth& depth, float tolerance) {
  std::vector<Probe> probes;
  for (int v0 = 0; v0 < size.height; v0 += block) {
    for (int u0 = 0; u0 < size.width; u0 += block) {
      std::optional<Probe> first, second;
      for (int v = v0; v < std::min(v0 + block, size.height); v += step) {
        const uint8_t* row = mask.empty() ? nullptr : mask.ptr<uint8_t>(v);
        for (int u = u0; u < std::min(u0 + block, size.width); u += step) {
          if (row && !row[u]) continue;  // most removed masks' pixels: decided before the full test
          const float z = depth(u, v);
          if (!(z > 0.f) || (first && (second || near(z, first->p.z(), tolerance)))) continue;
          (first ? second : first) = Probe{cameraPoint(k, u, v, z), u0, v0};
        }
      }
      if (first) probes.push_back(*first);
      if (second) probes.push_back(*second);
    }
  }
  return probes;
}

// Calls change(u, v, z) for each candidate of the blocks whose probe answered kChange, near its
// probe's depth.
template <typename Depth, typename Change>
void changeBlocks(const std::vector<Probe>& probes, const cv::Size& size, int block, const Depth& depth,
                  float tolerance, const Change& change) {
  for (const Probe& probe : probes) {
    if (probe.answer != Probe::Answer::kChange) continue;
    for (int v = probe.v0; v < std::min(probe.v0 + block, size.height); ++v) {
      for (int u = probe.u0; u < std::min(probe.u0 + block, size.width); ++u) {
        const float z = depth(u, v);
        if (z > 0.f && near(z, probe.p.z(), tolerance)) change(u, v, z);
      }
    }
  }
}

// Marks the disc of radius kHitDilation around (u, v) in hits: a moved point stands for the
// kStride x kStride pixels around it, and the marks are complete as soon as they are made (the
// frames a pixel is given back by read them while they wait).
void markHit(int u, int v, cv::Mat* hits) {
  static const std::vector<cv::Point> disc = [] {
    std::vector<cv::Point> offsets;
    const int size = 2 * kHitDilation + 1;
    cv::findNonZero(cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(size, size)), offsets);
    for (cv::Point& p : offsets) p -= cv::Point(kHitDilation, kHitDilation);
    return offsets;
  }();
  for (const cv::Point& d : disc) {
    const int x = u + d.x, y = v + d.y;
    if (x >= 0 && y >= 0 && x < hits->cols && y < hits->rows) hits->ptr<uint8_t>(y)[x] = 255;
  }
}

void check(bool ok, const std::string& key, const std::string& range) {
  if (!ok) throw Error("RemovalBackfill: " + key + " must lie in " + range);
}

}  // namespace

RemovalBackfill::RemovalBackfill(const Options& options) : options_(options) {
  check(options.frames >= 0 && options.frames <= 300, "frames", "[0, 300]");
  check(options.tolerance >= 0.005 && options.tolerance <= 0.5, "tolerance", "[0.005, 0.5] m");
  check(options.floor_clearance >= 0.0 && options.floor_clearance <= 1.0, "floor_clearance", "[0, 1] m");
  check(options.give_back_views >= 0 && options.give_back_views <= 10, "give_back_views", "[0, 10]");
  check(options.give_back_floor_clearance >= 0.0 && options.give_back_floor_clearance <= 1.0,
        "give_back_floor_clearance", "[0, 1] m");
  check(options.give_back_tolerance >= 0.005 && options.give_back_tolerance <= 0.5, "give_back_tolerance",
        "[0.005, 0.5] m");
  check(options.seen_through_views >= 0 && options.seen_through_views <= 10, "seen_through_views", "[0, 10]");
  check(options.seen_through_margin >= 0.02 && options.seen_through_margin <= 1.0, "seen_through_margin",
        "[0.02, 1] m");
}

void RemovalBackfill::push(Frame frame, const Points& people_w) {
  if (frame.depth.type() != CV_32F || frame.removed.type() != CV_8U || frame.depth.size() != frame.removed.size()) {
    throw Error("RemovalBackfill::push: depth must be CV_32F and removed CV_8U of the same size");
  }
  if (!frame.measured.empty() && (frame.measured.type() != CV_32F || frame.measured.size() != frame.depth.size())) {
    throw Error("RemovalBackfill::push: measured must be empty or CV_32F of the depth's size");
  }
  if (!frame.people.empty() && (frame.people.type() != CV_8U || frame.people.size() != frame.depth.size())) {
    throw Error("RemovalBackfill::push: people must be empty or CV_8U of the depth's size");
  }
  if (!people_w.empty()) {
    // Newest first; once two frames in a row had (next to) none of the people where they are now
    // (neither removed nor measured there), the people have moved since and the older frames would
    // take nothing either.
    int idle = 0;
    for (auto it = waiting_.rbegin(); it != waiting_.rend() && idle < kIdleFrames; ++it) {
      idle = carryInto(people_w, &*it) ? 0 : idle + 1;
    }
  }
  ++pushed_;
  double turn = 0.0;
  if (frame.T_w_c && last_pose_) turn = Eigen::AngleAxisd(last_pose_->linear().transpose() * frame.T_w_c->linear()).angle();
  last_pose_ = frame.T_w_c;
  waiting_.push_back({std::move(frame), cv::Mat(), turn});
  carryEarlierPeopleInto(&waiting_.back());
  if (!people_w.empty() && options_.frames > 0) earlier_people_.push_back({pushed_, people_w});
  while (!earlier_people_.empty() && earlier_people_.front().first + options_.frames <= pushed_) {
    earlier_people_.pop_front();
  }
  while (waiting_.size() > static_cast<size_t>(options_.frames)) releaseOldest();
}

void RemovalBackfill::releaseOldest() {
  Waiting& oldest = waiting_.front();
  const bool looks = looksAround() && oldest.frame.T_w_c && !oldest.frame.measured.empty();
  if (looks) {
    const std::vector<OtherView> views = viewsAround(oldest.frame, oldest.turn);
    giveBack(views, &oldest);
    takeSeenThrough(views, &oldest);
  }
  release(&oldest);
  // Every kConfirmEvery-th frame is kept, as the map got it, for the frames after it to look at.
  if (looksAround() && released_count_++ % kConfirmEvery == 0 && oldest.frame.T_w_c) {
    oldest.frame.release = nullptr;
    released_.push_back(std::move(oldest));
    if (released_.size() > static_cast<size_t>(options_.frames / kConfirmEvery)) released_.pop_front();
  }
  waiting_.pop_front();
}

bool RemovalBackfill::carriesNext() const { return options_.frames > 0 && pushed_ % kCarryEvery == 0; }

void RemovalBackfill::flush() {
  while (!waiting_.empty()) releaseOldest();
}

RemovalBackfill::Points RemovalBackfill::personPoints(
    const cv::Mat& depth, const CameraIntrinsics& k, const Eigen::Isometry3d& T_w_c,
    const Floor& floor, int stride) const {
  cv::Mat inside;
  cv::erode(depth > 0.f, inside,
            cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * kOutline + 1, 2 * kOutline + 1)));
  Points points;
  const Eigen::Isometry3f T = T_w_c.cast<float>();
  for (int v = 0; v < depth.rows; v += stride) {
    const float* d = depth.ptr<float>(v);
    const uint8_t* in = inside.ptr<uint8_t>(v);
    for (int u = 0; u < depth.cols; u += stride) {
      if (!in[u]) continue;
      const float z = d[u];
      const Eigen::Vector3f p_w = T * Eigen::Vector3f(static_cast<float>((u - k.cx) / k.fx) * z,
                                                      static_cast<float>((v - k.cy) / k.fy) * z, z);
      if (floor && floor->first.cast<float>().dot(p_w) - floor->second < options_.floor_clearance) continue;
      points.push_back(p_w);
    }
  }
  return points;
}

void RemovalBackfill::carryEarlierPeopleInto(Waiting* newest) const {
  // Newest first, stopping as carrying back does: a person seen a moment ago who has not moved
  // meets the new frame's depth, whether or not the detector found them in it again.
  int idle = 0;
  for (auto it = earlier_people_.rbegin(); it != earlier_people_.rend() && idle < kIdleFrames; ++it) {
    idle = carryInto(it->second, newest) ? 0 : idle + 1;
  }
}

bool RemovalBackfill::carryInto(const Points& people_w, Waiting* waiting) const {
  const Frame& frame = waiting->frame;
  if (!frame.T_w_c) return false;
  const Projection projection = projectionInto(frame, Eigen::Isometry3d::Identity());
  const float tolerance = static_cast<float>(options_.tolerance);
  size_t in_view = 0, met = 0;
  for (const Eigen::Vector3f& p_w : people_w) {
    const Eigen::Vector3f q = projection.A * p_w + projection.b;
    int iu = 0, iv = 0;
    if (!projection.pixel(q, frame.depth.size(), &iu, &iv)) continue;
    const float z = q.z();
    ++in_view;
    if (frame.removed.ptr<uint8_t>(iv)[iu]) {  // removed already: the person was there, found then
      ++met;
      continue;
    }
    const float d = frame.depth.ptr<float>(iv)[iu];
    if (!(d > 0.f) || std::abs(d - z) >= tolerance + 0.01f * z) continue;
    if (waiting->hits.empty()) waiting->hits = cv::Mat::zeros(frame.depth.size(), CV_8U);
    markHit(iu, iv, &waiting->hits);
    ++met;
  }
  return met > kMinHitShare * in_view;
}

std::vector<OtherView> RemovalBackfill::viewsAround(const Frame& frame, double turn) const {
  // Every kConfirmEvery-th frame released before it and waiting after it (with a pose), nearest
  // first, before and after in turn: a person's pixel is refused after a few of them.
  std::vector<OtherView> views;
  auto earlier = released_.rbegin();
  for (size_t later = kConfirmEvery; earlier != released_.rend() || later < waiting_.size(); later += kConfirmEvery) {
    if (earlier != released_.rend()) {
      views.push_back(otherView(frame, turn, earlier->frame, earlier->turn, earlier->hits));
      ++earlier;
    }
    const Waiting* next = later < waiting_.size() ? &waiting_[later] : nullptr;
    if (next && next->frame.T_w_c) views.push_back(otherView(frame, turn, next->frame, next->turn, next->hits));
  }
  return views;
}

void RemovalBackfill::giveBack(const std::vector<OtherView>& views, Waiting* oldest) const {
  Frame& frame = oldest->frame;
  if (options_.give_back_views == 0 || views.size() < static_cast<size_t>(options_.give_back_views)) return;
  // Height above the floor of a camera point p: up_c . p + up_offset.
  Eigen::Vector3f up_c = Eigen::Vector3f::Zero();
  float up_offset = std::numeric_limits<float>::infinity();
  if (frame.floor) {
    up_c = (frame.T_w_c->linear().transpose() * frame.floor->first).cast<float>();
    up_offset = static_cast<float>(frame.floor->first.dot(frame.T_w_c->translation()) - frame.floor->second);
  }
  const CameraIntrinsics& k = frame.intrinsics;
  const float clearance = static_cast<float>(options_.give_back_floor_clearance);
  // A removed pixel's depth where it may be given back, else 0.
  const auto removed = [&](int u, int v) {
    const float z = frame.measured.ptr<float>(v)[u];
    if (!frame.removed.ptr<uint8_t>(v)[u] || !(z > 0.f)) return 0.f;
    if (!oldest->hits.empty() && oldest->hits.ptr<uint8_t>(v)[u]) return 0.f;
    if (!frame.people.empty() && frame.people.ptr<uint8_t>(v)[u]) return 0.f;
    return up_c.dot(cameraPoint(k, u, v, z)) + up_offset < clearance ? 0.f : z;
  };
  Margins margins;
  margins.tolerance = static_cast<float>(options_.give_back_tolerance);
  std::vector<Probe> probes = blockProbes(frame.removed.size(), frame.removed, kBlock, 1, k, removed, margins.tolerance);
  for (size_t i = 0; i < views.size(); ++i) {
    voteGiveBack(views[i], static_cast<int>(views.size() - i - 1), margins, options_.give_back_views, &probes);
  }
  changeBlocks(probes, frame.depth.size(), kBlock, removed, margins.tolerance, [&](int u, int v, float z) {
    frame.removed.ptr<uint8_t>(v)[u] = 0;
    frame.depth.ptr<float>(v)[u] = z;
  });
}

void RemovalBackfill::takeSeenThrough(const std::vector<OtherView>& views, Waiting* oldest) const {
  Frame& frame = oldest->frame;
  if (options_.seen_through_views == 0 || views.size() < static_cast<size_t>(options_.seen_through_views)) return;
  const CameraIntrinsics& k = frame.intrinsics;
  // A kept pixel's depth, unless a later person was carried there (removed anyway), else 0.
  const auto kept = [&](int u, int v) {
    const bool carried = !oldest->hits.empty() && oldest->hits.ptr<uint8_t>(v)[u];
    return carried ? 0.f : frame.depth.ptr<float>(v)[u];
  };
  Margins margins;
  margins.tolerance = static_cast<float>(options_.give_back_tolerance);
  margins.through = static_cast<float>(options_.seen_through_margin);
  std::vector<Probe> probes = blockProbes(frame.depth.size(), cv::Mat(), kKeptBlock, kKeptStep, k, kept, margins.tolerance);
  for (size_t i = 0; i < views.size(); ++i) {
    voteTake(views[i], static_cast<int>(views.size() - i - 1), margins, options_.seen_through_views, &probes);
  }
  changeBlocks(probes, frame.depth.size(), kKeptBlock, kept, margins.tolerance, [&](int u, int v, float) {
    frame.removed.ptr<uint8_t>(v)[u] = 255;
    frame.depth.ptr<float>(v)[u] = 0.f;
  });
}

void RemovalBackfill::release(Waiting* waiting) const {
  Frame& frame = waiting->frame;
  if (!waiting->hits.empty()) {
    waiting->hits &= (frame.depth > 0.f);
    frame.depth.setTo(0.f, waiting->hits);
    frame.removed.setTo(255, waiting->hits);
  }
  if (frame.release) frame.release(frame);
}

}  // namespace pf2
