// Google Benchmark of BodyFitter::fit for one person (docs/BENCHMARKS.md, "Body fitting (eq. 4)"):
// the default model posed, its joints projected into an fr3 camera at 3 m as COCO keypoints, and
// its camera-facing vertices as the person's depth points (about 6 000).
#include <benchmark/benchmark.h>

#include <Eigen/Geometry>

#include "pf2/body/body_fitter.h"
#include "pf2/body/body_surface_aligner.h"

namespace {

struct Scene {
  pf2::BodyModel model = pf2::BodyModel::loadDefault();
  pf2::CameraIntrinsics K = pf2::CameraIntrinsics::tumFreiburg3();
  pf2::BodyFitInput input;
  pf2::BodyParameters truth;

  Scene() {
    const Eigen::AngleAxisd root(Eigen::AngleAxisd(0.44, Eigen::Vector3d::UnitY()) *
                                 Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()));
    truth.pose[0] = root.angle() * root.axis();
    truth.pose[1] = {-0.35, 0, 0};
    truth.pose[4] = {0.5, 0, 0};
    truth.pose[16] = {0, 0, -1.3};
    truth.pose[17] = {0, 0, 1.25};
    truth.pose[18] = {0, -0.5, 0};
    truth.translation = {0.15, 0.1, 3.0};
    const pf2::BodyMesh mesh = model.evaluate(truth);
    for (int k = 0; k < pf2::kCocoKeypointCount; ++k) {
      if (pf2::kCocoToBodyJoint[k].joint < 0) continue;
      const Eigen::Vector2d px = K.project(mesh.joints[pf2::kCocoToBodyJoint[k].joint]);
      input.keypoints[k] = {px.x(), px.y(), 1.0};
    }
    // Camera-facing vertices: normal (area-weighted over the triangles) towards the camera.
    std::vector<Eigen::Vector3d> normals(mesh.vertices.size(), Eigen::Vector3d::Zero());
    for (const auto& t : mesh.triangles) {
      const Eigen::Vector3d a = mesh.vertices[t[0]].cast<double>();
      const Eigen::Vector3d n = (mesh.vertices[t[1]].cast<double>() - a).cross(mesh.vertices[t[2]].cast<double>() - a);
      for (int k = 0; k < 3; ++k) normals[t[k]] += n;
    }
    for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
      if (normals[i].dot(mesh.vertices[i].cast<double>()) < 0) input.points_c.push_back(mesh.vertices[i].cast<double>());
    }
  }
};

Scene& scene() {
  static Scene s;
  return s;
}

// Arg 2: keypoints + depth with the surface alignment (the default), 1: without it, 0: keypoints only.
void BM_FitPerson(benchmark::State& state) {
  Scene& s = scene();
  pf2::BodyFitInput input = s.input;
  if (state.range(0) == 0) input.points_c.clear();
  pf2::BodyFitter::Options options;
  options.surface_alignment = state.range(0) == 2;
  const pf2::BodyFitter fitter(s.model, options);
  for (auto _ : state) benchmark::DoNotOptimize(fitter.fit(input, s.K));
  state.SetLabel(state.range(0) == 2 ? "keypoints + depth + surface alignment"
                                     : (state.range(0) ? "keypoints + depth" : "keypoints only"));
}
BENCHMARK(BM_FitPerson)->Arg(2)->Arg(1)->Arg(0)->Unit(benchmark::kMillisecond);

// Warm start from the exact previous parameters (a person who did not move): the per-frame cost
// when tracking a person with the temporal start.
void BM_FitPersonWarmStart(benchmark::State& state) {
  Scene& s = scene();
  pf2::BodyFitInput input = s.input;
  input.previous = &s.truth;
  const pf2::BodyFitter fitter(s.model);
  for (auto _ : state) benchmark::DoNotOptimize(fitter.fit(input, s.K));
}
BENCHMARK(BM_FitPersonWarmStart)->Unit(benchmark::kMillisecond);

// The surface alignment alone (part of every fit with depth points): the true body placed 5 cm too
// far along its ray, moved back onto the camera-facing vertices.
void BM_AlignSurface(benchmark::State& state) {
  Scene& s = scene();
  const pf2::BodySurfaceAligner aligner(s.model, pf2::BodySurfaceAligner::Options());
  pf2::BodyParameters far = s.truth;
  far.translation += 0.05 * s.model.posedJoints(s.truth)[0].normalized();
  for (auto _ : state) {
    pf2::BodyParameters body = far;
    benchmark::DoNotOptimize(aligner.align(s.input.points_c, s.K, &body));
  }
}
BENCHMARK(BM_AlignSurface)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
