#pragma once
// Marching cubes case table, generated at start-up from the algorithm itself rather than typed in:
// for each of the 256 inside/outside patterns of a cube's corners, the edges the surface crosses
// are joined face by face into closed loops, and each loop is fanned into triangles.
//
// Conventions: corner c sits at offset (c & 1, (c >> 1) & 1, (c >> 2) & 1); bit c of a case index
// is set when corner c is inside (signed distance < 0). Edge e joins kEdgeCorners[e][0] (the lower
// corner) and kEdgeCorners[e][1] along axis kEdgeAxis[e]. On an ambiguous face (two diagonal
// inside corners) the inside corners are cut off separately, a rule that depends only on the face,
// so both cubes sharing it agree and the mesh has no cracks. Triangles are counter-clockwise seen
// from the outside (their normal points to positive distance).
#include <array>
#include <vector>

namespace pf2 {
namespace marching_cubes {

extern const int kEdgeCorners[12][2];
extern const int kEdgeAxis[12];

// Triangles of case `cube_case` (0..255) as triples of edge indices. Thread safe (built once).
const std::vector<std::array<int, 3>>& triangles(int cube_case);

}  // namespace marching_cubes
}  // namespace pf2
