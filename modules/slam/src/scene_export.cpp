#include "pf2/slam/scene_export.h"

#include <cmath>

namespace pf2 {

namespace {

std::array<std::uint8_t, 3> colourBytes(int id) {
  const std::array<double, 3> rgb = personColour(id);
  return {static_cast<std::uint8_t>(std::lround(255 * rgb[0])), static_cast<std::uint8_t>(std::lround(255 * rgb[1])),
          static_cast<std::uint8_t>(std::lround(255 * rgb[2]))};
}

// The scene's vertices get a colour each: a map without colours gets grey ones, so that the
// bodies' colours can be stored.
void appendMap(const TriangleMesh& map, TriangleMesh* scene) {
  scene->vertices = map.vertices;
  scene->triangles = map.triangles;
  scene->colors = map.colors;
  if (scene->colors.empty()) scene->colors.assign(map.vertices.size(), {180, 180, 180});
}

void appendBody(const BodyMesh& body, const std::array<std::uint8_t, 3>& colour, TriangleMesh* scene) {
  const int base = static_cast<int>(scene->vertices.size());
  scene->vertices.insert(scene->vertices.end(), body.vertices.begin(), body.vertices.end());
  scene->colors.insert(scene->colors.end(), body.vertices.size(), colour);
  for (const Eigen::Vector3i& t : body.triangles) scene->triangles.push_back(t + Eigen::Vector3i::Constant(base));
}

void appendTrack(const BodyTrack& track, const std::array<std::uint8_t, 3>& colour, TriangleMesh* scene) {
  const int base = static_cast<int>(scene->vertices.size());
  for (const BodyTrackFrame& frame : track.frames) {
    scene->vertices.push_back(frame.pelvis_w.cast<float>());
    scene->colors.push_back(colour);
  }
  for (int i = 1; i < static_cast<int>(track.frames.size()); ++i) {
    scene->edges.emplace_back(base + i - 1, base + i);
    scene->edge_colors.push_back(colour);
  }
}

// The frames of a track whose bodies go into the scene: the last fitted one (the last one when
// none was fitted) and, with bodies_every, every N-th.
std::vector<size_t> shownFrames(const BodyTrack& track, int bodies_every) {
  std::vector<size_t> shown;
  if (track.frames.empty()) return shown;
  size_t last = track.frames.size() - 1;
  for (size_t i = track.frames.size(); i-- > 0;) {
    if (track.frames[i].fitted) {
      last = i;
      break;
    }
  }
  if (bodies_every > 0) {
    for (size_t i = 0; i < track.frames.size(); i += static_cast<size_t>(bodies_every)) {
      if (i != last) shown.push_back(i);
    }
  }
  shown.push_back(last);
  return shown;
}

}  // namespace

TriangleMesh buildScene(const TriangleMesh& static_map, const std::vector<BodyTrack>& bodies, const BodyModel& model,
                        const SceneOptions& options) {
  TriangleMesh scene;
  appendMap(static_map, &scene);
  for (const BodyTrack& track : bodies) {
    const std::array<std::uint8_t, 3> colour = colourBytes(track.id);
    for (size_t i : shownFrames(track, options.bodies_every)) {
      appendBody(model.evaluate(track.frames[i].body_w), colour, &scene);
    }
    appendTrack(track, colour, &scene);
  }
  return scene;
}

}  // namespace pf2
