#pragma once
// Person removal carried back in time, for the map and the masks. A person the detector finds
// only now was often in the frames before as well: standing at the border until the camera's pan
// showed enough of them, seated before MoveNet found them, seen from above. Each frame waits
// Options::frames frames before it goes to the map; meanwhile the depth of every person found
// with a confident pose in a later frame is moved into it (with the tracked poses), and its depth
// that lies within Options::tolerance of a moved point is removed. Who stood still is removed
// where they stood; who moved since puts their points where the frame saw free space or the scene
// behind them, farther away, and removes nothing. Points near the floor (Options::floor_clearance)
// are not carried: a person's feet touch the floor where they will stand. The people found in a
// frame are carried forward as well, into the Options::frames frames after it: a person seated or
// standing still whom the detector misses for a while is removed where they stay, by the same
// rule.
//
// The wait also gives depth back: what the filter removed from a frame (a mask's spill onto the
// floor, the wall or a chair beside a person; the rules beside the masks) whose surface the frames
// around it saw, kept, at the same place (Options::give_back_views of them, within
// Options::give_back_tolerance, and twice as many as removed it there) was static: whoever stood
// there came later or has gone, and someone who stays is removed in most of those frames too. The
// frames around it are every kConfirmEvery-th of the Options::frames before it, as the map got
// them (their own removal complete), and of those after it, as they wait (people found later
// still to be carried into them). Near the floor nothing is given back (feet stand on it), nor the
// frame's own people (Frame::people): a seated person other frames miss now and then has not left.
//
// The same frames take what they saw through: depth the frame kept where
// Options::seen_through_views of them measured (and kept) the scene well behind it, all around
// the pixel, and no more than one measured that surface there, was not there a moment before or
// after: someone who moved, whom the filter missed. Whoever stays put is not found so.
//
// The tracker never waits: it has its frames' depth as the filter left it. Only the map's depth
// and the written masks are finished later. NOT thread safe.
#include <deque>
#include <functional>
#include <optional>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "pf2/core/camera_intrinsics.h"

namespace pf2 {

namespace removal_backfill_internal {
struct OtherView;  // another frame as seen from a frame's camera (removal_backfill.cpp)
}  // namespace removal_backfill_internal

class RemovalBackfill {
 public:
  // The people of every kCarryEvery-th frame are carried back, every kStride-th pixel and row of
  // them: carrying costs a point's projection per waiting frame (8 ms a frame on the Bonn crowd
  // frames with every frame's people and every second pixel, 2.3 ms with these; the six pf2_synth
  // hard cases keep 55-90 % of the gain in the people's depth, and lose less static depth).
  static constexpr int kCarryEvery = 3;
  static constexpr int kStride = 3;
  // A person's outline this many pixels wide is not carried: the selfie network's mask is blurred
  // there and takes the chair and the wall beside the person, which would go from every frame the
  // person is carried into.
  static constexpr int kOutline = 2;
  // A frame's removed depth is looked for in every kConfirmEvery-th frame before and after it only
  // (five of the thirty each way; consecutive frames see nearly the same: with every third, the
  // six pf2_synth hard cases kept within 0.06 points the same, at a third more of the cost).
  static constexpr int kConfirmEvery = 6;
  // The floor: the world's up vector and the floor's height along it (metres).
  using Floor = std::optional<std::pair<Eigen::Vector3d, double>>;
  struct Options {
    int frames = 30;               // frames a frame waits for the people found after it (and
                                   // frames after a frame its people are carried into), in
                                   // [0, 300]; 0 = off (each frame released at once)
    double tolerance = 0.05;       // metres, plus 1 % of the depth: a later person's point this
                                   // close to a waiting frame's depth removes it, in [0.005, 0.5]
    double floor_clearance = 0.05;  // metres: a person's points lower above the floor are not
                                    // carried (a foot's sole touches the floor where the foot is
                                    // not yet or no longer), in [0, 1]
    int give_back_views = 3;       // frames around it (every kConfirmEvery-th) that must have seen a
                                   // removed pixel's surface, kept, for it to be given back, in
                                   // [0, 10]; 0 = nothing given back
    double give_back_floor_clearance = 0.1;  // metres: removed depth lower above the floor is never
                                             // given back (people's feet stand on it), in [0, 1]
    double give_back_tolerance = 0.03;  // metres, plus 1 % of the depth: another frame's kept depth
                                        // this close to a removed point sees its surface, in
                                        // [0.005, 0.5]
    int seen_through_views = 1;    // frames around it (every kConfirmEvery-th) that must have seen
                                   // through a kept pixel's point (kept what they measured well
                                   // behind it) for it to be removed, if no more than one of them
                                   // kept its surface, in [0, 10]; 0 = nothing removed so
    double seen_through_margin = 0.1;  // metres, plus 3 % of the depth: another frame's depth this far
                                       // behind a point all around its pixel sees through it, in
                                       // [0.02, 1]
  };

  // A frame waiting for the map. depth and removed are filled in as later frames' people arrive,
  // so they must not share data with images someone else still reads.
  struct Frame {
    cv::Mat depth;    // CV_32F metres: the static depth for the map (0 = removed or none)
    cv::Mat removed;  // CV_8U, 255 where depth was removed as a person's
    cv::Mat measured;  // CV_32F metres: the depth before removal; empty = nothing given back
    cv::Mat people;    // CV_8U, 255 on the frame's own people (never given back); may be empty
    std::optional<Eigen::Isometry3d> T_w_c;  // none: nothing is carried into or given back to this frame
    Floor floor;                             // the floor when the frame was taken, if known
    CameraIntrinsics intrinsics;
    std::function<void(const Frame&)> release;  // called once, when the frame leaves the window
  };

  // Points of the people in one frame, world frame (metres).
  using Points = std::vector<Eigen::Vector3f>;

  RemovalBackfill() : RemovalBackfill(Options()) {}
  // Throws pf2::Error naming the option when one is out of range.
  explicit RemovalBackfill(const Options& options);

  // Carries people_w into every waiting frame, adds `frame`, carries the people of the
  // Options::frames frames before it into it, and releases (oldest first) the frames
  // that have waited Options::frames frames, giving back their removed depth that the frames
  // around them saw kept. Throws pf2::Error when frame.depth is not CV_32F, frame.removed not CV_8U of its
  // size, or frame.measured (frame.people) neither empty nor CV_32F (CV_8U) of its size.
  void push(Frame frame, const Points& people_w);
  // Releases every waiting frame, oldest first (the end of a run).
  void flush();
  size_t waiting() const { return waiting_.size(); }
  // Whether the people of the next pushed frame are carried back: on every kCarryEvery-th frame
  // only (people move little in a tenth of a second, and carrying is the costly part), never when
  // off. The caller need not find their points otherwise.
  bool carriesNext() const;

  // Every `stride`-th pixel and row of people_depth (CV_32F metres, 0 = not a person's) as world
  // points, leaving out the kOutline pixels inside its outline and those within floor_clearance
  // of the floor (up_w . p - floor_height below it, `floor` = (up_w, floor_height)) when the
  // floor is known.
  Points personPoints(const cv::Mat& people_depth, const CameraIntrinsics& intrinsics, const Eigen::Isometry3d& T_w_c,
                      const Floor& floor, int stride = kStride) const;

  const Options& options() const { return options_; }

 private:
  struct Waiting {
    Frame frame;
    cv::Mat hits;  // CV_8U, 255 within 2 px of where a later person's point met its depth
    double turn = 0.0;  // radians the camera turned since the frame pushed before it (0 if unknown)
  };
  // Marks the waiting frame's depth the points meet; true when more than a few of the points in
  // its view meet its depth or its removed pixels.
  bool carryInto(const Points& people_w, Waiting* waiting) const;
  // Carries the people of the frames pushed before it (earlier_people_) into the newest waiting
  // frame: a seated or standing person the detector misses in it for a while.
  void carryEarlierPeopleInto(Waiting* newest) const;
  using OtherView = removal_backfill_internal::OtherView;
  // Every kConfirmEvery-th frame around `frame` (released before it, waiting after it), nearest
  // first, as seen from its camera; `turn` is the frame's Waiting::turn.
  std::vector<OtherView> viewsAround(const Frame& frame, double turn) const;
  // Gives back the oldest waiting frame's removed depth that Options::give_back_views of the frames
  // around it saw kept, except its own people, near the floor and where a later person was
  // carried.
  void giveBack(const std::vector<OtherView>& views, Waiting* oldest) const;
  // Removes the oldest waiting frame's kept depth that Options::seen_through_views of the frames
  // around it saw through, and no more than one saw there: someone who has moved.
  void takeSeenThrough(const std::vector<OtherView>& views, Waiting* oldest) const;
  // Whether frames look at the frames around them (giving back or taking what others saw through).
  bool looksAround() const { return options_.give_back_views > 0 || options_.seen_through_views > 0; }
  void release(Waiting* waiting) const;
  // Gives back, releases and drops the oldest waiting frame, keeping it for the frames after it to
  // look at when it is every kConfirmEvery-th.
  void releaseOldest();

  Options options_;
  std::deque<Waiting> waiting_;
  // The people carried back by the frames of the last Options::frames pushed, with the number of
  // frames pushed when they came (1 = the first), oldest first.
  std::deque<std::pair<long, Points>> earlier_people_;
  std::deque<Waiting> released_;  // every kConfirmEvery-th frame released, the newest frames / kConfirmEvery
  long pushed_ = 0;               // frames pushed so far
  long released_count_ = 0;       // frames released so far
  std::optional<Eigen::Isometry3d> last_pose_;  // the pose of the frame pushed last, if it had one
};

}  // namespace pf2
