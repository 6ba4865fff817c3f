#pragma once
// The run's scene as one mesh (scene.ply, scene.obj): the static map, each person's body at their
// last fitted pose (and, on request, every N-th body along their track), and each person's track
// as a polyline through their pelvis positions; bodies and tracks in the person's colour
// (personColour), the map in its own colours.
#include <vector>

#include "pf2/body/body_model.h"
#include "pf2/humans/body_tracks.h"
#include "pf2/surface/triangle_mesh.h"

namespace pf2 {

struct SceneOptions {
  // 0: each person's last fitted body only (their last body when none was fitted); N > 0: also
  // the body of every N-th frame of their track. [0, 100000]
  int bodies_every = 0;
};

// static_map may be empty (a run without a map). Thread safe.
TriangleMesh buildScene(const TriangleMesh& static_map, const std::vector<BodyTrack>& bodies, const BodyModel& model,
                        const SceneOptions& options);

}  // namespace pf2
