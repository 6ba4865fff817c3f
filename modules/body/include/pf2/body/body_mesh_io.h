#pragma once
// Export of a posed body mesh for viewers and renderers: binary little-endian PLY or Wavefront
// OBJ, chosen by the file extension. Written atomically (temporary file + rename).
#include <string>

#include "pf2/body/body_model.h"

namespace pf2 {

// Writes `mesh` to path ending in .ply or .obj. Throws pf2::Error naming the path on an unknown
// extension or a failed write. Thread safe for distinct paths.
void writeBodyMesh(const std::string& path, const BodyMesh& mesh);

}  // namespace pf2

namespace pf2 {

// Reads joint rotations into parameters->pose from a text file: one joint per line,
// "NAME ax ay az" (SMPL joint name from kBodyJointNames, axis-angle in radians, relative to the
// parent); '#' starts a comment; joints not listed keep their value. Throws pf2::Error with the
// file and line on an unknown joint or a bad number. Thread safe.
void readBodyPoseFile(const std::string& path, BodyParameters* parameters);

}  // namespace pf2
