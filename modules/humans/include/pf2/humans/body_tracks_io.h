#pragma once
// humans.json: each person's body per frame (README "Outputs"):
//   {"tracks": [{"id": 1, "frames": [{"timestamp": t, "T_w_h": [16 numbers, row-major],
//     "pose": [72 axis-angle numbers], "shape": [10 numbers], "translation": [x, y, z],
//     "joints_w": [[x, y, z] x 24], "pelvis_w": [x, y, z], "fitted": true|false}]}]}
// World frame of trajectory.txt, metres and radians. "pose" holds the 24 joint rotations in SMPL
// order, the root's being its rotation in the world (= the rotation of T_w_h); the body model
// evaluated with pose, shape and translation (SMPL's root translation, added after posing) gives
// joints_w and the person's mesh in the world; its pelvis is pelvis_w.
#include <string>
#include <vector>

#include "pf2/humans/body_tracks.h"

namespace pf2 {

// Writes atomically (temporary file + rename), numbers with 6 decimals. Throws pf2::Error naming
// the path. Thread safe (for different paths).
void writeBodyTracksJson(const std::string& path, const std::vector<BodyTrack>& tracks);

// Reads humans.json back. Throws pf2::Error naming the path and what is wrong (not JSON, a missing field, a list of the wrong length, a non-finite number). Thread safe.
std::vector<BodyTrack> readBodyTracksJson(const std::string& path);

}  // namespace pf2
