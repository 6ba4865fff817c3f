// VisibleCentre against the eq. 2 centre of a rendered body (pf2_synth's rasteriser: triangles, a
// z-buffer, the box and mean depth of the person's pixels, as pf2_slam takes them).
#include <array>
#include <cmath>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "pf2/body/body_model.h"
#include "pf2/core/error.h"
#include "pf2/humans/body_tracks.h"
#include "pf2/humans/human_position.h"
#include "pf2/humans/visible_centre.h"
#include "pf2/synth/people.h"
#include "pf2/synth/rasterizer.h"

namespace pf2 {
namespace {

const BodyModel& model() {
  static const BodyModel loaded = BodyModel::loadDefault();
  return loaded;
}

CameraIntrinsics camera() { return CameraIntrinsics::tumFreiburg3().scaled(0.5); }

// Upright in the camera (y down), turned a little, one arm out, the other down; pelvis at pelvis_c.
BodyParameters body(const Eigen::Vector3d& pelvis_c) {
  BodyParameters b;
  b.shape[0] = 0.4;
  b.pose[0] = Eigen::Vector3d(M_PI, 0, 0) + Eigen::Vector3d(0, 0.4, 0);
  b.pose[16] = Eigen::Vector3d(0, 0, -0.3);
  b.pose[17] = Eigen::Vector3d(0, 0, 1.2);
  b.pose[1] = Eigen::Vector3d(-0.3, 0, 0);
  b.translation = pelvis_c - model().posedJoints(b)[0];
  return b;
}

// Eq. 2 as pf2_slam takes it from a depth image: the box of the person's pixels, at their mean depth;
// pixels from row hidden_from down are hidden (by a table in front of the person), -1: none.
bool renderedCentre(const BodyParameters& b, Eigen::Vector3d* centre_c, int hidden_from = -1) {
  const BodyMesh mesh = model().evaluate(b);
  const RenderMesh person =
      bodyRenderMesh(mesh, std::vector<Eigen::Vector3f>(mesh.vertices.size(), Eigen::Vector3f::Constant(0.5f)), 1);
  Rasterizer::Options options;
  options.parallel = false;
  RenderedImages images;
  Rasterizer(options).render({&person}, {}, camera(), Eigen::Isometry3d::Identity(), &images);
  cv::Mat on_person = images.labels == 1;
  if (hidden_from >= 0 && hidden_from < on_person.rows) on_person.rowRange(hidden_from, on_person.rows) = 0;
  if (cv::countNonZero(on_person) == 0) return false;
  const cv::Rect box = cv::boundingRect(on_person);
  *centre_c = humanCentreInCamera(box.x, box.y, box.x + box.width - 1, box.y + box.height - 1,
                                  cv::mean(images.depth, on_person)[0], camera());
  return true;
}

std::vector<Eigen::Vector3d> aboutPelvis(const BodyParameters& b) {
  const BodyMesh mesh = model().evaluate(b);
  std::vector<Eigen::Vector3d> relative;
  for (size_t v = 0; v < mesh.vertices.size(); v += 4) {
    relative.push_back(mesh.vertices[v].cast<double>() - mesh.joints[0]);
  }
  return relative;
}

// A person in full view gives the offset between their pelvis and their eq. 2 centre (and the
// bias of the rendered centre from the modelled one); 1.4 m to the left at 2.5 m, most of them
// is beyond the image's left border. Their centre plus that offset misses the pelvis by
// decimetres; VisibleCentre finds it.
TEST(VisibleCentre, FindsThePelvisOfAPersonCutByTheImageBorder) {
  const VisibleCentre image(camera());
  const Eigen::Vector3d in_view(0.1, 0.1, 2.5), cut(-1.4, 0.1, 2.5);
  const std::vector<Eigen::Vector3d> relative = aboutPelvis(body(in_view));
  Eigen::Vector3d rendered_in_view, modelled_in_view, rendered_cut;
  ASSERT_TRUE(renderedCentre(body(in_view), &rendered_in_view));
  ASSERT_TRUE(image.centre(relative, in_view, &modelled_in_view));
  ASSERT_TRUE(renderedCentre(body(cut), &rendered_cut));
  const Eigen::Vector3d bias = rendered_in_view - modelled_in_view;
  EXPECT_LT(bias.norm(), 0.03) << "vertices and rendered pixels give about the same centre";

  const Eigen::Vector3d by_offset = rendered_cut + (in_view - rendered_in_view);
  Eigen::Vector3d found(9, 9, 9);
  ASSERT_TRUE(image.pelvisFor(relative, rendered_cut - bias, by_offset, &found));
  std::printf("pelvis of the cut person: centre + offset misses by %.3f m, VisibleCentre by %.3f m\n",
              (by_offset - cut).norm(), (found - cut).norm());
  EXPECT_GT((by_offset - cut).norm(), 0.15);
  EXPECT_LT((found - cut).norm(), 0.04);
}

// In full view the centre moves with the body: one step finds the pelvis from anywhere near.
TEST(VisibleCentre, InFullViewTheCentreMovesWithTheBody) {
  const VisibleCentre image(camera());
  const Eigen::Vector3d pelvis(0.2, 0.0, 3.0);
  const std::vector<Eigen::Vector3d> relative = aboutPelvis(body(pelvis));
  Eigen::Vector3d centre, moved_centre, found;
  ASSERT_TRUE(image.centre(relative, pelvis, &centre));
  ASSERT_TRUE(image.centre(relative, pelvis + Eigen::Vector3d(0.1, -0.05, 0.2), &moved_centre));
  EXPECT_LT((moved_centre - centre - Eigen::Vector3d(0.1, -0.05, 0.2)).norm(), 0.02);
  ASSERT_TRUE(image.pelvisFor(relative, centre, pelvis + Eigen::Vector3d(-0.3, 0.1, 0.4), &found));
  EXPECT_LT((found - pelvis).norm(), 0.005);
}

TEST(VisibleCentre, ABodyOutOfViewHasNoCentreAndLeavesThePelvisAlone) {
  const VisibleCentre image(camera());
  const std::vector<Eigen::Vector3d> relative = aboutPelvis(body(Eigen::Vector3d(0, 0, 2.5)));
  Eigen::Vector3d centre(1, 2, 3), pelvis(4, 5, 6);
  EXPECT_FALSE(image.centre(relative, Eigen::Vector3d(6, 0, 2.5), &centre));
  EXPECT_FALSE(image.centre(relative, Eigen::Vector3d(0, 0, -3), &centre));
  EXPECT_EQ(centre, Eigen::Vector3d(1, 2, 3));
  EXPECT_FALSE(image.pelvisFor(relative, Eigen::Vector3d(0, 0, 2.5), Eigen::Vector3d(6, 0, 2.5), &pelvis));
  EXPECT_EQ(pelvis, Eigen::Vector3d(4, 5, 6));
}

// pf2_slam's end of run for a person fitted in full view (pelvis at fitted_c, frame 0) and seen once
// more `seconds` later with the eq. 2 centre later_centre_c, both frames on one keyframe at T_w_k:
// the two frames' pelvises in that keyframe's camera frame (NaN when there are not two frames).
std::array<Eigen::Vector3d, 2> placedPelvises(const BodyTrackAssembler::Options& options,
                                              const Eigen::Isometry3d& T_w_k, const Eigen::Vector3d& up_w,
                                              const Eigen::Vector3d& fitted_c, const Eigen::Vector3d& later_centre_c,
                                              double seconds) {
  std::vector<PersonSighting> seen(2);
  EXPECT_TRUE(renderedCentre(body(fitted_c), &seen[0].p_c));
  seen[1].p_c = later_centre_c;
  seen[1].frame_index = static_cast<int>(std::lround(30 * seconds));
  seen[1].timestamp = seconds;
  for (PersonSighting& s : seen) s.keyframe_id = 0;
  BodyTrackFit fit;
  fit.keyframe_id = 0;
  fit.body_c = body(fitted_c);
  const std::vector<BodyTrack> tracks =
      BodyTrackAssembler(model(), options).assemble(seen, {fit}, {{0, T_w_k}}, camera(), up_w);
  std::array<Eigen::Vector3d, 2> pelvis_c;
  pelvis_c.fill(Eigen::Vector3d::Constant(NAN));
  if (tracks.size() != 1 || tracks[0].frames.size() != 2) return pelvis_c;
  for (int k = 0; k < 2; ++k) pelvis_c[k] = T_w_k.inverse() * tracks[0].frames[k].pelvis_w;
  return pelvis_c;
}

// A person fitted in full view, seen again 2 s later (beyond max_gap) with most of them beyond the
// image border, same pose. Their body is placed where its visible part gives the centre measured
// then; by the centre plus the fit's offset it would be decimetres off.
TEST(VisibleCentre, PlacesAPersonCutByTheBorderLongAfterTheirFit) {
  const Eigen::Vector3d in_view(0.1, 0.1, 2.5), cut(-1.4, 0.1, 2.5);
  Eigen::Isometry3d T_w_k = Eigen::Isometry3d::Identity();
  T_w_k.linear() = Eigen::AngleAxisd(0.7, Eigen::Vector3d(0.1, 1, 0.2).normalized()).toRotationMatrix();
  T_w_k.translation() = Eigen::Vector3d(1, -0.5, 2);
  Eigen::Vector3d cut_centre;
  ASSERT_TRUE(renderedCentre(body(cut), &cut_centre));
  for (const bool by_visible_centre : {true, false}) {
    BodyTrackAssembler::Options options;
    options.smoothing_sigma = 0;
    options.visible_centre = by_visible_centre;
    const auto pelvis_c = placedPelvises(options, T_w_k, Eigen::Vector3d::Zero(), in_view, cut_centre, 2.0);
    const double miss = (pelvis_c[1] - cut).norm();
    std::printf("cut person placed %s: %.3f m from the pelvis\n",
                by_visible_centre ? "by the visible centre" : "by the offset", miss);
    if (by_visible_centre) EXPECT_LT(miss, 0.04);
    else EXPECT_GT(miss, 0.15);
    EXPECT_LT((pelvis_c[0] - in_view).norm(), 1e-6) << "the fit itself stays";
  }
}

// A person fitted in full view walks 0.4 m on and is seen again 2.5 s later (beyond max_gap) with
// everything below their pelvis hidden by a table. Their eq. 2 centre lies on their upper body, and
// the body placed to give that centre floats decimetres above their pelvis; with hold_height it
// keeps the fit's pelvis height and takes only the horizontal position from the centre.
TEST(VisibleCentre, APersonBehindATableKeepsTheirFitsPelvisHeight) {
  const Eigen::Vector3d fitted(0.1, 0.1, 2.5), later(0.5, 0.1, 2.5);
  Eigen::Isometry3d T_w_k = Eigen::Isometry3d::Identity();
  T_w_k.linear() = Eigen::AngleAxisd(0.5, Eigen::Vector3d(0.3, 1, 0.1).normalized()).toRotationMatrix();
  T_w_k.translation() = Eigen::Vector3d(-1, 0.4, 1.5);
  const Eigen::Vector3d up_w = T_w_k.linear() * Eigen::Vector3d(0, -1, 0);  // the camera's up (y down)
  Eigen::Vector3d later_centre;
  ASSERT_TRUE(renderedCentre(body(later), &later_centre, static_cast<int>(camera().project(later).y())));
  for (const bool hold_height : {true, false}) {
    BodyTrackAssembler::Options options;
    options.smoothing_sigma = 0;
    options.hold_height = hold_height;
    const Eigen::Vector3d miss_c = placedPelvises(options, T_w_k, up_w, fitted, later_centre, 2.5)[1] - later;
    std::printf("person behind a table, hold_height %d: %.3f m from the pelvis (%.3f m in height)\n", hold_height,
                miss_c.norm(), std::abs(miss_c.y()));
    if (hold_height) EXPECT_LT(miss_c.norm(), 0.06);
    else EXPECT_GT(std::abs(miss_c.y()), 0.15);
  }
}

// A wrong fit is dropped by how far its pelvis lies from the eq. 2 centre compared with the
// track's other fits; for a person cut by the image border that offset is no guide (their centre
// lies on the part in view), so such a fit is judged by how far the measured centre lies from the
// one its body gives. Three fits in full view, a right fit of the person mostly beyond the border
// and a wrong one (half a metre too deep) there: the right one is kept only with visible_centre.
TEST(VisibleCentre, ARightFitOfAPersonCutByTheBorderIsKept) {
  const Eigen::Vector3d cut(-1.55, 0.1, 2.5);
  std::vector<PersonSighting> seen;
  std::vector<BodyTrackFit> fits;
  const auto add = [&](const Eigen::Vector3d& pelvis_seen, const Eigen::Vector3d& pelvis_fitted) {
    PersonSighting s;
    s.frame_index = static_cast<int>(seen.size());
    s.timestamp = 0.1 * s.frame_index;
    s.keyframe_id = 0;
    ASSERT_TRUE(renderedCentre(body(pelvis_seen), &s.p_c));
    BodyTrackFit fit;
    fit.frame_index = s.frame_index;
    fit.timestamp = s.timestamp;
    fit.keyframe_id = 0;
    fit.body_c = body(pelvis_fitted);
    seen.push_back(s);
    fits.push_back(fit);
  };
  for (const double x : {0.0, 0.1, 0.2}) add(Eigen::Vector3d(x, 0.1, 2.5), Eigen::Vector3d(x, 0.1, 2.5));
  add(cut, cut);
  add(cut, cut + Eigen::Vector3d(0, 0, 0.5));
  Eigen::Vector3d rendered_whole, rendered_cut;
  ASSERT_TRUE(renderedCentre(body(Eigen::Vector3d(0, 0.1, 2.5)), &rendered_whole));
  ASSERT_TRUE(renderedCentre(body(cut), &rendered_cut));
  const double offset_change = ((cut - rendered_cut) - (Eigen::Vector3d(0, 0.1, 2.5) - rendered_whole)).norm();
  std::printf("offset of the right fit of the cut person: %.3f m from the others'\n", offset_change);
  ASSERT_GT(offset_change, BodyTrackAssembler::Options().max_offset_deviation) << "the offset rule would drop it";
  for (const bool by_visible_centre : {true, false}) {
    BodyTrackAssembler::Options options;
    options.visible_centre = by_visible_centre;
    const std::vector<BodyTrack> tracks = BodyTrackAssembler(model(), options)
                                              .assemble(seen, fits, {{0, Eigen::Isometry3d::Identity()}}, camera());
    ASSERT_EQ(tracks.size(), 1u);
    EXPECT_EQ(tracks[0].fits, by_visible_centre ? 4 : 3);
    EXPECT_EQ(tracks[0].frames[3].fitted, by_visible_centre);
    EXPECT_FALSE(tracks[0].frames[4].fitted) << "the wrong fit is dropped either way";
  }
}

// Where the measured centre lies against the body changes over a track: a seated person's mask
// and box hold the chair and the wall behind them (their centre lies deeper than their body's),
// and when they walk up to the border the centre and the body agree. Eight fits of the first kind,
// then five right fits of the person cut by the border and a wrong one among them: judged against
// the whole track's median the right ones are dropped with the wrong one; judged against the fits
// around them (bodies.cut_bias_window) only the wrong one is.
TEST(VisibleCentre, AFitIsJudgedByTheFitsAroundIt) {
  std::vector<PersonSighting> seen;
  std::vector<BodyTrackFit> fits;
  const auto add = [&](double t, const Eigen::Vector3d& pelvis, const Eigen::Vector3d& centre_error,
                       const Eigen::Vector3d& fit_error) {
    PersonSighting s;
    s.frame_index = static_cast<int>(seen.size());
    s.timestamp = t;
    s.keyframe_id = 0;
    ASSERT_TRUE(renderedCentre(body(pelvis), &s.p_c));
    s.p_c += centre_error;
    BodyTrackFit fit;
    fit.frame_index = s.frame_index;
    fit.timestamp = t;
    fit.keyframe_id = 0;
    fit.body_c = body(pelvis + fit_error);
    seen.push_back(s);
    fits.push_back(fit);
  };
  const Eigen::Vector3d deeper(0, 0, 0.3), none = Eigen::Vector3d::Zero();
  for (int k = 0; k < 8; ++k) add(0.2 * k, Eigen::Vector3d(0.01 * k, 0.1, 2.5), deeper, none);
  for (int k = 0; k < 6; ++k) {
    add(3.0 + 0.2 * k, Eigen::Vector3d(-1.55 + 0.02 * k, 0.1, 2.5), none, k == 3 ? Eigen::Vector3d(0, 0, 0.5) : none);
  }
  for (const double window : {0.0, 1.0}) {
    BodyTrackAssembler::Options options;
    options.cut_bias_window = window;
    const std::vector<BodyTrack> tracks =
        BodyTrackAssembler(model(), options).assemble(seen, fits, {{0, Eigen::Isometry3d::Identity()}}, camera());
    ASSERT_EQ(tracks.size(), 1u);
    std::printf("cut_bias_window %.1f s: %d of 14 fits kept\n", window, tracks[0].fits);
    for (int k = 8; k < 14; ++k) {
      EXPECT_EQ(tracks[0].frames[k].fitted, window > 0 && k != 11) << "fit " << k << ", cut_bias_window " << window;
    }
    for (int k = 0; k < 8; ++k) EXPECT_TRUE(tracks[0].frames[k].fitted) << "seated fit " << k;
  }
}

TEST(VisibleCentre, RefusesOptionsOutOfRange) {
  VisibleCentre::Options options;
  options.cell_px = 0;
  EXPECT_THROW(VisibleCentre(camera(), options), Error);
  options = VisibleCentre::Options();
  options.max_move = 0;
  EXPECT_THROW(VisibleCentre(camera(), options), Error);
  CameraIntrinsics no_size = camera();
  no_size.width = 0;
  EXPECT_THROW(VisibleCentre{no_size}, Error);
}

}  // namespace
}  // namespace pf2
