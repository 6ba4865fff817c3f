#include "pf2/humans/human_tracker.h"

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include "pf2/core/error.h"

namespace pf2 {
namespace {

constexpr double kRate = 30.0;

HumanTracker::Options withAssociation(HumanTracker::Association association) {
  HumanTracker::Options options;
  options.association = association;
  return options;
}

// Two people walking towards each other along world x at 1.2 m/s (4 cm per frame), 3 cm apart
// sideways; they pass at x = 0 between frames 24 and 25. Returns, per frame, the id given to
// person A and to person B.
std::vector<std::pair<int, int>> trackCrossing(HumanTracker* tracker) {
  std::vector<std::pair<int, int>> ids;
  for (int i = 0; i < 50; ++i) {
    const double x = -0.98 + 0.04 * i;
    const std::vector<Eigen::Vector3d> centres{{x, 0.0, 1.0}, {-x, 0.03, 1.0}};
    const std::vector<int> frame_ids = tracker->update(i / kRate, centres);
    ids.emplace_back(frame_ids[0], frame_ids[1]);
  }
  return ids;
}

TEST(HumanTracker, ConstantVelocityKeepsIdsWherePeopleCross) {
  HumanTracker tracker(withAssociation(HumanTracker::Association::kPredicted));
  const auto ids = trackCrossing(&tracker);
  for (const auto& [a, b] : ids) {
    EXPECT_EQ(a, 1);
    EXPECT_EQ(b, 2);
  }
  ASSERT_EQ(tracker.tracks().size(), 2u);
  EXPECT_EQ(tracker.tracks()[0].points.size(), 50u);
  EXPECT_DOUBLE_EQ(tracker.tracks()[0].points.back().p_w.x(), 0.98);
}

TEST(HumanTracker, PaperHeuristicSwapsIdsWherePeopleCross) {
  HumanTracker tracker(withAssociation(HumanTracker::Association::kPaper));
  const auto ids = trackCrossing(&tracker);
  // Before passing, each is closest to where they were; at the pass (x = -0.02 -> +0.02) each
  // new centre is 3 cm from where the other was and 4 cm from where it was itself: the ids swap.
  for (int i = 0; i <= 24; ++i) EXPECT_EQ(ids[i], std::make_pair(1, 2)) << i;
  for (int i = 25; i < 50; ++i) EXPECT_EQ(ids[i], std::make_pair(2, 1)) << i;
  EXPECT_EQ(tracker.tracks().size(), 2u);
}

// One person walking along x, not detected in frames 10..14.
std::vector<int> trackWithGap(HumanTracker* tracker) {
  std::vector<int> ids;
  for (int i = 0; i < 30; ++i) {
    std::vector<Eigen::Vector3d> centres;
    if (i < 10 || i >= 15) centres.push_back({0.04 * i, 0.0, 0.9});
    const std::vector<int> frame_ids = tracker->update(i / kRate, centres);
    if (!frame_ids.empty()) ids.push_back(frame_ids[0]);
  }
  return ids;
}

TEST(HumanTracker, MissedFramesKeepTheIdWithinMaxMissed) {
  HumanTracker tracker(withAssociation(HumanTracker::Association::kPredicted));
  const std::vector<int> ids = trackWithGap(&tracker);
  ASSERT_EQ(ids.size(), 25u);
  for (int id : ids) EXPECT_EQ(id, 1);
  // The paper's heuristic remembers one frame only: a new id after the gap.
  HumanTracker paper(withAssociation(HumanTracker::Association::kPaper));
  const std::vector<int> paper_ids = trackWithGap(&paper);
  EXPECT_EQ(paper_ids.front(), 1);
  EXPECT_EQ(paper_ids.back(), 2);
  EXPECT_EQ(paper.tracks().size(), 2u);
  // A track unseen for longer than max_missed ends; its id is not reused.
  HumanTracker::Options short_memory;
  short_memory.max_missed = 3;
  HumanTracker forgetful(short_memory);
  const std::vector<int> forgetful_ids = trackWithGap(&forgetful);
  EXPECT_EQ(forgetful_ids.back(), 2);
  EXPECT_EQ(forgetful.liveTracks(), 1);
}

TEST(HumanTracker, GateStartsNewTracksForFarCentres) {
  HumanTracker tracker;
  const int n = tracker.options().reid_after;  // centres that make a track a person
  for (int f = 0; f < n; ++f) EXPECT_EQ(tracker.update(f / kRate, {{0, 0, 1}}), std::vector<int>{1});
  // 2 m away one frame later: beyond the 0.5 m (+ 1 m/s x 1/30 s) gate, so a new person.
  EXPECT_EQ(tracker.update(n / kRate, {{2, 0, 1}}), std::vector<int>{2});
  // The first is still alive and takes a centre near it again; the second too.
  EXPECT_EQ(tracker.update((n + 1) / kRate, {{2.05, 0, 1}, {0.1, 0, 1}}), (std::vector<int>{2, 1}));
  // Nobody for a frame: the person stays live, the new track (two centres, not yet a person) ends.
  EXPECT_EQ(tracker.update((n + 2) / kRate, {}), std::vector<int>{});
  EXPECT_EQ(tracker.liveTracks(), 1);
  tracker.reset();
  EXPECT_EQ(tracker.update((n + 3) / kRate, {{0, 0, 1}}), std::vector<int>{1});
}

// A person stands still; someone walks in 0.7 m in front of them and hides them for half a
// second. Within the 0.5 m gate the walker is someone new and the standing person keeps their id
// when seen again; with a 1 m gate the standing person's track moves onto the walker.
TEST(HumanTracker, AHiddenPersonsTrackDoesNotMoveOntoWhoeverHidesThem) {
  for (const double gate : {0.5, 1.0}) {
    HumanTracker::Options options;
    options.gate = gate;
    HumanTracker tracker(options);
    for (int f = 0; f < 30; ++f) tracker.update(f / kRate, {{0, 0, 3}});
    const Eigen::Vector3d walker_start(-0.3, 0, 2.35);  // 0.72 m from the standing person
    std::vector<int> walker_ids;
    for (int f = 30; f < 45; ++f) {
      walker_ids = tracker.update(f / kRate, {walker_start + Eigen::Vector3d(0.04 * (f - 30), 0, 0)});
    }
    const std::vector<int> ids =
        tracker.update(45 / kRate, {walker_start + Eigen::Vector3d(0.6, 0, 0), Eigen::Vector3d(0, 0, 3)});
    if (gate < 1.0) {
      EXPECT_EQ(walker_ids, std::vector<int>{2});
      EXPECT_EQ(ids, (std::vector<int>{2, 1}));
    } else {
      EXPECT_EQ(walker_ids, std::vector<int>{1});
      EXPECT_EQ(ids, (std::vector<int>{1, 2}));
    }
  }
}

// A person seen again after two thirds of a second unseen: the track's first centre is 0.3 m off
// (their box merged with something beside them), the next one back where they are, 0.6 m from
// it. A prediction made of that one centre is as uncertain as the centre, and the gate widens
// by sqrt(1 + 1/1): the track takes the second centre. At the gate of a track seen all along it
// would be someone new.
TEST(HumanTracker, ATrackSeenAgainOnOneCentreHasAWiderGate) {
  HumanTracker tracker;
  for (int f = 0; f < 30; ++f) tracker.update(f / kRate, {{0, 0, 3}});
  for (int f = 30; f < 50; ++f) tracker.update(f / kRate, {});
  EXPECT_EQ(tracker.update(50 / kRate, {{-0.3, 0, 3}}), std::vector<int>{1});
  const double gap = 0.6;
  ASSERT_GT(gap, tracker.options().gate + tracker.options().gate_growth / kRate);
  EXPECT_EQ(tracker.update(51 / kRate, {{-0.3 + gap, 0, 3}}), std::vector<int>{1});
}

// Two people, both unseen for a moment: one standing still a fifth of a second ago, one out of
// sight for most of a second (a wide gate). A centre nearer to the first one's prediction is
// theirs: the cost measures distance by the same base gate for both, so the longer-lost track
// (whose own, wider gate would make the same distance look smaller) does not win the close call.
TEST(HumanTracker, ALongerLostTrackDoesNotWinACentreNearerToAnother) {
  HumanTracker tracker;
  for (int f = 0; f < 10; ++f) tracker.update(f / kRate, {{0, 0, 3}, {1.2, 0, 3}});
  for (int f = 10; f < 30; ++f) EXPECT_EQ(tracker.update(f / kRate, {{0, 0, 3}}), std::vector<int>{1});
  for (int f = 30; f < 36; ++f) tracker.update(f / kRate, {});
  ASSERT_EQ(tracker.liveTracks(), 2);
  EXPECT_EQ(tracker.update(36 / kRate, {{0.5, 0, 3}}), std::vector<int>{1});
}

// An image of two people, one in red, one in blue, for their appearances.
PersonAppearance colouredPerson(const cv::Scalar& bgr) {
  cv::Mat image(120, 80, CV_8UC3, bgr);
  cv::randn(image, bgr, cv::Scalar(12, 12, 12));  // some texture, as clothes have
  return personAppearance(image, cv::Rect(0, 0, 80, 120), cv::Mat(120, 80, CV_8U, cv::Scalar(255)));
}

TEST(PersonAppearance, SameColoursAreSimilarOthersAreNot) {
  const PersonAppearance red = colouredPerson({40, 40, 200}), red_again = colouredPerson({45, 35, 205});
  const PersonAppearance blue = colouredPerson({200, 60, 40});
  ASSERT_EQ(red.size(), 72u);
  EXPECT_GT(appearanceSimilarity(red, red_again), 0.9);
  EXPECT_LT(appearanceSimilarity(red, blue), 0.3);
  EXPECT_EQ(appearanceSimilarity(red, PersonAppearance()), 0.0);
  // Too few pixels under the mask: unknown.
  cv::Mat mask(120, 80, CV_8U, cv::Scalar(0));
  mask(cv::Rect(0, 0, 5, 5)).setTo(255);
  EXPECT_TRUE(personAppearance(cv::Mat(120, 80, CV_8UC3, cv::Scalar(0, 0, 255)), cv::Rect(0, 0, 80, 120), mask).empty());
}

// A person hidden for 3 s (longer than max_missed) comes back 1.5 m away: under a new id for the
// first reid_after - 1 frames, then under their old one (the new id an alias of it) when they
// look the same; a new person when someone else in other colours appears there.
TEST(HumanTracker, ReidentifiesAPersonByAppearanceAfterALongGap) {
  const PersonAppearance red = colouredPerson({40, 40, 200}), blue = colouredPerson({200, 60, 40});
  for (const bool same_person : {true, false}) {
    HumanTracker tracker;
    for (int f = 0; f < 30; ++f) EXPECT_EQ(tracker.update(f / kRate, {{0.01 * f, 0, 2}}, {red}), std::vector<int>{1});
    for (int f = 30; f < 120; ++f) tracker.update(f / kRate, {});
    EXPECT_EQ(tracker.liveTracks(), 0);
    const int after = tracker.options().reid_after;
    ASSERT_GE(after, 2);
    for (int f = 120; f < 120 + after - 1; ++f) {
      EXPECT_EQ(tracker.update(f / kRate, {{1.8, 0, 2}}, {same_person ? red : blue}), std::vector<int>{2});
    }
    const std::vector<int> ids = tracker.update((120 + after - 1) / kRate, {{1.8, 0, 2}}, {same_person ? red : blue});
    EXPECT_EQ(ids, std::vector<int>{same_person ? 1 : 2});
    EXPECT_EQ(tracker.resolvedId(2), same_person ? 1 : 2);
    EXPECT_EQ(tracker.liveTracks(), 1);
    EXPECT_EQ(tracker.tracks().size(), same_person ? 1u : 2u);
    EXPECT_EQ(tracker.tracks()[0].points.size(), same_person ? 30u + after : 30u);
  }
  // Beyond reach (farther than gate + max_speed x 3 s) or after reid_window: a new person.
  HumanTracker::Options options;
  options.reid_window = 2.0;
  HumanTracker forgetful(options);
  forgetful.update(0.0, {{0, 0, 2}}, {red});
  for (int f = 1; f < 90; ++f) forgetful.update(f / kRate, {});
  EXPECT_EQ(forgetful.update(90 / kRate, {{0.5, 0, 2}}, {red}), std::vector<int>{2});
  // The paper's association never re-identifies.
  options = HumanTracker::Options();
  options.association = HumanTracker::Association::kPaper;
  HumanTracker paper(options);
  paper.update(0.0, {{0, 0, 2}}, {red});
  paper.update(1 / kRate, {});
  EXPECT_EQ(paper.update(2 / kRate, {{0, 0, 2}}, {red}), std::vector<int>{2});
  EXPECT_THROW(paper.update(3 / kRate, {{0, 0, 2}}, {red, blue}), Error);
}

// A person in red comes back after 3 s at the image border: their first reid_after views show
// them in part, 40 % of the pixels theirs and the rest the grey wall (similarity 0.63 to their
// lost track). Compared again at 2 x reid_after centres, by when they are in full view, they are
// re-identified; compared once only, they stay someone new.
TEST(HumanTracker, APersonFirstSeenInPartIsReidentifiedOnceMoreOfThemIsSeen) {
  const PersonAppearance red = colouredPerson({40, 40, 200}), grey = colouredPerson({128, 128, 128});
  PersonAppearance in_part(red.size());
  for (size_t i = 0; i < red.size(); ++i) in_part[i] = 0.4f * red[i] + 0.6f * grey[i];
  HumanTracker::Options options;
  ASSERT_LT(appearanceSimilarity(in_part, red), options.reid_similarity);
  for (const int checks : {3, 1}) {
    options.reid_checks = checks;
    HumanTracker tracker(options);
    for (int f = 0; f < 30; ++f) tracker.update(f / kRate, {{0.01 * f, 0, 2}}, {red});
    for (int f = 30; f < 120; ++f) tracker.update(f / kRate, {});
    const int after = options.reid_after;
    std::vector<int> ids;
    for (int f = 120; f < 120 + after; ++f) ids = tracker.update(f / kRate, {{1.5, 0, 2}}, {in_part});
    EXPECT_EQ(ids, std::vector<int>{2});
    for (int f = 120 + after; f < 120 + 2 * after; ++f) ids = tracker.update(f / kRate, {{1.5, 0, 2}}, {red});
    EXPECT_EQ(ids, std::vector<int>{checks > 1 ? 1 : 2});
    EXPECT_EQ(tracker.resolvedId(2), checks > 1 ? 1 : 2);
    EXPECT_EQ(tracker.tracks().size(), checks > 1 ? 1u : 2u);
  }
}

// A seated person in red is hidden for 1.2 s (longer than max_missed) and comes back where they
// sat, half hidden still: 40 % of their pixels theirs, the rest a grey wall (similarity 0.63 to
// their track, below reid_similarity). Where they were and soon enough, that is them; the same
// view 1.5 m away, after 3 s, or with reid_near_time 0 is someone new.
TEST(HumanTracker, APersonBackSoonWhereTheyWereIsReidentifiedAtALowerSimilarity) {
  const PersonAppearance red = colouredPerson({40, 40, 200}), grey = colouredPerson({128, 128, 128});
  PersonAppearance in_part(red.size());
  for (size_t i = 0; i < red.size(); ++i) in_part[i] = 0.4f * red[i] + 0.6f * grey[i];
  const HumanTracker::Options defaults;
  ASSERT_LT(appearanceSimilarity(in_part, red), defaults.reid_similarity);
  ASSERT_GE(appearanceSimilarity(in_part, red), defaults.reid_near_similarity);
  const Eigen::Vector3d seat(-1.5, 0.3, 3.1);
  const auto idOnReturn = [&](const HumanTracker::Options& options, int hidden_frames, const Eigen::Vector3d& back) {
    HumanTracker tracker(options);
    int f = 0;
    for (; f < 60; ++f) tracker.update(f / kRate, {seat}, {red});
    for (const int end = f + hidden_frames; f < end; ++f) tracker.update(f / kRate, {});
    std::vector<int> ids;
    for (const int end = f + 4 * options.reid_after; f < end; ++f) ids = tracker.update(f / kRate, {back}, {in_part});
    return ids.at(0);
  };
  EXPECT_EQ(idOnReturn(defaults, 36, seat), 1);
  EXPECT_EQ(idOnReturn(defaults, 36, seat + Eigen::Vector3d(0.2, 0, 0.2)), 1);
  EXPECT_EQ(idOnReturn(defaults, 36, seat + Eigen::Vector3d(1.5, 0, 0)), 2);
  EXPECT_EQ(idOnReturn(defaults, 90, seat), 2);
  HumanTracker::Options off = defaults;
  off.reid_near_time = 0.0;
  EXPECT_EQ(idOnReturn(off, 36, seat), 2);
}

// A stray centre that lasts two frames (a person's part split off, a false detection) in the
// colours of a lost person does not take their id; the person coming back later does, once their
// new track has reid_after centres. The stray track is no person to come back either.
TEST(HumanTracker, AStrayCentreDoesNotTakeALostPersonsId) {
  const PersonAppearance red = colouredPerson({40, 40, 200});
  HumanTracker tracker;
  for (int f = 0; f < 30; ++f) tracker.update(f / kRate, {{0.0, 0, 2}}, {red});
  for (int f = 30; f < 60; ++f) tracker.update(f / kRate, {});
  for (int f = 60; f < 62; ++f) EXPECT_EQ(tracker.update(f / kRate, {{2.0, 0, 3}}, {red}), std::vector<int>{2});
  for (int f = 62; f < 100; ++f) tracker.update(f / kRate, {});
  std::vector<int> ids;
  for (int f = 100; f < 100 + tracker.options().reid_after; ++f) ids = tracker.update(f / kRate, {{0.1, 0, 2}}, {red});
  EXPECT_EQ(ids, std::vector<int>{1});
  EXPECT_EQ(tracker.resolvedId(3), 1);
  EXPECT_EQ(tracker.resolvedId(2), 2);
}

// A lost person's last centre came from a box that merged them with someone 1.7 m away (the gate
// had grown while they were hidden). When they come back where they were walking, their new track
// is beyond reach of that centre but within reach of the ones before it: re-identified.
TEST(HumanTracker, ReidentifiesAPersonWhoseLastCentreWasAStrayOne) {
  const PersonAppearance red = colouredPerson({40, 40, 200});
  HumanTracker tracker;
  for (int f = 0; f < 30; ++f) tracker.update(f / kRate, {{0.01 * f, 0, 2}}, {red});
  for (int f = 30; f < 59; ++f) tracker.update(f / kRate, {});
  EXPECT_EQ(tracker.update(59 / kRate, {{2.0, 0, 2}}, {red}), std::vector<int>{1});  // the merged box
  for (int f = 60; f < 92; ++f) tracker.update(f / kRate, {});
  ASSERT_EQ(tracker.liveTracks(), 0);
  // 4 m from the stray centre in 1.1 s is beyond gate + max_speed x 1.1 s = 3.75 m.
  const Eigen::Vector3d back(-2.0, 0, 2);
  ASSERT_GT((back - Eigen::Vector3d(2.0, 0, 2)).norm(),
            tracker.options().gate + tracker.options().max_speed * (92 - 59) / kRate);
  std::vector<int> ids;
  for (int f = 92; f < 92 + tracker.options().reid_after; ++f) ids = tracker.update(f / kRate, {back}, {red});
  EXPECT_EQ(ids, std::vector<int>{1});
  EXPECT_EQ(tracker.resolvedId(2), 1);
}

// A person in red stands 3 m in front of the camera (at the origin, looking along z) and is hidden
// by someone in the same red who steps in front of them, 0.8 m nearer on the line of sight (beyond
// the lost track's gate, within its reach). The newcomer is the one who hid them: their track
// keeps its own id, and the hidden person, back a second later, is re-identified under theirs.
// Without the camera's position (or with occluder_margin 0) the newcomer took the hidden person's
// id, and the person came back as someone new; a newcomer first seen later than occluder_window
// after the loss may be the person who walked towards the camera.
TEST(HumanTracker, WhoeverHidesALostPersonDoesNotTakeTheirId) {
  const PersonAppearance red = colouredPerson({40, 40, 200});
  const Eigen::Vector3d camera_w = Eigen::Vector3d::Zero();
  const Eigen::Vector3d hidden(0, 0, 3), in_front(0, 0, 2.2);
  struct Ids {
    int newcomer, back;
  };
  const auto run = [&](const HumanTracker::Options& options, bool with_camera, int hidden_frames) {
    HumanTracker tracker(options);
    const auto camera = [&] { return with_camera ? std::optional<Eigen::Vector3d>(camera_w) : std::nullopt; };
    int f = 0;
    for (; f < 30; ++f) tracker.update(f / kRate, {hidden}, {red}, camera());
    for (; f < 30 + hidden_frames; ++f) tracker.update(f / kRate, {}, {}, camera());
    Ids ids{0, 0};
    const int newcomer_end = f + 2 * options.reid_after;
    for (; f < newcomer_end; ++f) ids.newcomer = tracker.update(f / kRate, {in_front}, {red}, camera())[0];
    std::vector<int> both;
    for (const int end = f + 2 * options.reid_after; f < end; ++f) {
      both = tracker.update(f / kRate, {in_front, hidden}, {red, red}, camera());
    }
    EXPECT_EQ(both[0], ids.newcomer);
    ids.back = both[1];
    return ids;
  };
  HumanTracker::Options options;
  // The hidden person stood: from rest they could not have reached the newcomer in 0.2 s either
  // (max_acceleration; ANewTrackIsNotAPersonWhoCouldNotHaveWalkedThereFromRest). Off here, so that
  // this rule is tested alone.
  options.max_acceleration = 0.0;
  ASSERT_GT((in_front - hidden).norm(), options.gate * std::sqrt(1.0 + 1.0 / 15) + 6 / kRate * options.gate_growth);
  Ids ids = run(options, true, 6);
  EXPECT_EQ(ids.newcomer, 2);
  EXPECT_EQ(ids.back, 1);
  ids = run(options, false, 6);
  EXPECT_EQ(ids.newcomer, 1);
  EXPECT_EQ(ids.back, 3);
  ids = run(options, true, 40);  // first seen 1.3 s after the loss
  EXPECT_EQ(ids.newcomer, 1);
  options.occluder_margin = 0.0;
  ids = run(options, true, 6);
  EXPECT_EQ(ids.newcomer, 1);
}

// Two people in much the same red stand at x = 0 and x = 3 m and are both lost. 2 s later one
// comes back at x = 0.2 m: the far track looks more alike (similarity 0.995 against the near one's
// 0.887), but its person would have had to walk 2.3 m beyond the gate in 2 s (1.1 m/s). With
// reid_speed_cost 0.15 the near track takes them back; without it the more similar one does.
TEST(HumanTracker, OfTwoLostTracksThatLookAlikeTheNearOneReidentifies) {
  const PersonAppearance red = colouredPerson({40, 40, 200}), orange_red = colouredPerson({40, 70, 200});
  PersonAppearance mixed(red.size());
  for (size_t i = 0; i < red.size(); ++i) mixed[i] = 0.8f * red[i] + 0.2f * orange_red[i];
  ASSERT_GT(appearanceSimilarity(red, mixed), appearanceSimilarity(orange_red, mixed));
  ASSERT_GT(appearanceSimilarity(orange_red, mixed), HumanTracker::Options().reid_similarity);
  for (const double cost : {0.15, 0.0}) {
    HumanTracker::Options options;
    options.reid_speed_cost = cost;
    HumanTracker tracker(options);
    for (int f = 0; f < 30; ++f) {
      ASSERT_EQ(tracker.update(f / kRate, {{0, 0, 2}, {3, 0, 2}}, {orange_red, red}), (std::vector<int>{1, 2}));
    }
    for (int f = 30; f < 90; ++f) tracker.update(f / kRate, {});
    ASSERT_EQ(tracker.liveTracks(), 0);
    std::vector<int> ids;
    for (int f = 90; f < 90 + options.reid_after; ++f) ids = tracker.update(f / kRate, {{0.2, 0, 2}}, {mixed});
    EXPECT_EQ(ids, std::vector<int>{cost > 0 ? 1 : 2}) << "reid_speed_cost " << cost;
  }
}

// A person in red walks alone, then someone in blue stands 0.3 m beside them for a second, and
// the red person's detection shows the blue one's colours (one detection for the two). With
// appearance_crowd, the red track does not learn them: back after 3 s unseen, the red person is
// re-identified. Without it the red track has turned blue, and the red person is someone new.
TEST(HumanTracker, ACentreBesideAnotherTracksPredictionLeavesItsAppearanceAsItWas) {
  const PersonAppearance red = colouredPerson({40, 40, 200}), blue = colouredPerson({200, 60, 40});
  for (const double crowd : {0.6, 0.0}) {
    HumanTracker::Options options;
    options.appearance_crowd = crowd;
    HumanTracker tracker(options);
    for (int f = 0; f < 30; ++f) tracker.update(f / kRate, {{0, 0, 2}}, {red});
    for (int f = 30; f < 60; ++f) {
      EXPECT_EQ(tracker.update(f / kRate, {{0, 0, 2}, {0.3, 0, 2}}, {blue, blue}), (std::vector<int>{1, 2}));
    }
    for (int f = 60; f < 150; ++f) tracker.update(f / kRate, {});
    ASSERT_EQ(tracker.liveTracks(), 0);
    std::vector<int> ids;
    for (int f = 150; f < 150 + tracker.options().reid_after; ++f) ids = tracker.update(f / kRate, {{1.0, 0, 2}}, {red});
    EXPECT_EQ(ids, std::vector<int>{crowd > 0 ? 1 : 3}) << "appearance_crowd " << crowd;
  }
}

// Two people side by side whose measured centres jitter across each other for a frame: by
// position alone the tracks swap them, with their appearances each keeps their own.
TEST(HumanTracker, AppearanceKeepsTwoPeopleApartWherePositionsCross) {
  const PersonAppearance red = colouredPerson({40, 40, 200}), blue = colouredPerson({200, 60, 40});
  for (const double weight : {0.0, 0.5}) {
    HumanTracker::Options options;
    options.appearance_weight = weight;
    HumanTracker tracker(options);
    for (int f = 0; f < 20; ++f) {
      ASSERT_EQ(tracker.update(f / kRate, {{0.0, 0, 2}, {0.4, 0, 2}}, {red, blue}), (std::vector<int>{1, 2}));
    }
    const std::vector<int> ids = tracker.update(20 / kRate, {{0.25, 0, 2}, {0.15, 0, 2}}, {red, blue});
    EXPECT_EQ(ids, weight > 0 ? (std::vector<int>{1, 2}) : (std::vector<int>{2, 1})) << "weight " << weight;
  }
}

// A person seen for 20 frames, then missed for 13; 0.47 s after they were last seen one centre
// appears 0.8 m to the side of where their track predicts them. Standing, their gate has grown by
// still_gate_growth (0.3 m/s) to 0.52 + 0.14 m: the centre is someone else and starts a new track.
// At gate_growth (1 m/s, still_speed 0) it would lie within 0.52 + 0.47 m and take their id. A
// walker (1.2 m/s) keeps the gate grown at walking pace and their id.
TEST(HumanTracker, APersonLastSeenStandingIsLookedForNearWhereTheyStood) {
  const auto idOfCentreBeside = [](const HumanTracker::Options& options, double speed) {
    HumanTracker tracker(options);
    int f = 0;
    for (; f < 20; ++f) tracker.update(f / kRate, {{speed * f / kRate, 0.0, 2.0}});
    for (; f < 33; ++f) tracker.update(f / kRate, {});
    const Eigen::Vector3d predicted(speed * f / kRate, 0.0, 2.0);
    return tracker.update(f / kRate, {predicted + Eigen::Vector3d(0.0, 0.0, 0.8)})[0];
  };
  HumanTracker::Options options;
  EXPECT_EQ(idOfCentreBeside(options, 0.0), 2);
  EXPECT_EQ(idOfCentreBeside(options, 1.2), 1);
  options.still_speed = 0.0;
  EXPECT_EQ(idOfCentreBeside(options, 0.0), 1);
}

// A person in red stands for a second and is missed for 11 frames (0.37 s); then someone in the
// same colours comes into view 1.2 m behind where they stood. From rest at max_acceleration
// (1 m/s²) the person could have got 0.07 m beyond the gate by then: the newcomer is someone new.
// By max_speed alone (2.5 m/s) they could have, and with max_acceleration 0 the newcomer takes
// their id. The same newcomer 1.5 s later is within reach (1.1 m beyond the gate): re-identified.
TEST(HumanTracker, ANewTrackIsNotAPersonWhoCouldNotHaveWalkedThereFromRest) {
  const PersonAppearance red = colouredPerson({40, 40, 200});
  const auto idOfNewcomer = [&](const HumanTracker::Options& options, int missed) {
    HumanTracker tracker(options);
    int f = 0;
    for (; f < 30; ++f) tracker.update(f / kRate, {{-1.0, 0.2, 2.0}}, {red});
    for (const int end = f + missed; f < end; ++f) tracker.update(f / kRate, {});
    std::vector<int> ids;
    for (const int end = f + options.reid_after; f < end; ++f) ids = tracker.update(f / kRate, {{-1.3, 0.2, 3.16}}, {red});
    return ids.at(0);
  };
  HumanTracker::Options options;
  ASSERT_DOUBLE_EQ(options.max_acceleration, 1.0);
  EXPECT_EQ(idOfNewcomer(options, 11), 2);
  EXPECT_EQ(idOfNewcomer(options, 45), 1);
  options.max_acceleration = 0.0;
  EXPECT_EQ(idOfNewcomer(options, 11), 1);
}

// A walking person's centre jumps 25 cm for two frames (a second person entering the view beside
// them, their boxes merged), then both are seen apart: the prediction, a line fitted to the last
// half second, stays with the walker (from the last centre and the velocity to the oldest one in
// the window it would lie next to the newcomer, who would take the walker's id).
TEST(HumanTracker, AJumpOfTwoFramesDoesNotCarryThePredictionAway) {
  HumanTracker tracker;
  for (int f = 0; f < 17; ++f) {
    const double jump = f >= 15 ? 0.25 : 0.0;
    ASSERT_EQ(tracker.update(f / kRate, {{0.02 * f + jump, 0, 2}}), std::vector<int>{1});
  }
  EXPECT_EQ(tracker.update(17 / kRate, {{0.65, 0, 2}, {0.34, 0, 2}}), (std::vector<int>{2, 1}));
}

TEST(HumanTracker, AssociationNames) {
  EXPECT_EQ(humanAssociationFromName("paper"), HumanTracker::Association::kPaper);
  EXPECT_EQ(humanAssociationFromName("predicted"), HumanTracker::Association::kPredicted);
  EXPECT_STREQ(toString(HumanTracker::Association::kPaper), "paper");
  EXPECT_THROW(humanAssociationFromName("nearest"), Error);
}

}  // namespace
}  // namespace pf2
