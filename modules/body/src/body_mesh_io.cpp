#include "pf2/body/body_mesh_io.h"

#include <array>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <ostream>

#include "pf2/core/atomic_file.h"
#include "pf2/core/error.h"
#include "pf2/core/text_lines.h"

namespace pf2 {
namespace {

bool endsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

void writePly(std::ostream& out, const BodyMesh& mesh) {
  for (const auto& v : mesh.vertices) {
    if (!v.allFinite()) throw Error("body mesh has a vertex that is not a finite number");
  }
  out << "ply\nformat binary_little_endian 1.0\ncomment PoseFusion2 body mesh, metres\n"
      << "element vertex " << mesh.vertices.size() << "\nproperty float x\nproperty float y\nproperty float z\n"
      << "element face " << mesh.triangles.size() << "\nproperty list uchar int vertex_indices\nend_header\n";
  for (const auto& v : mesh.vertices) out.write(reinterpret_cast<const char*>(v.data()), 3 * sizeof(float));
  for (const auto& t : mesh.triangles) {
    const std::uint8_t n = 3;
    out.write(reinterpret_cast<const char*>(&n), 1);
    const std::int32_t indices[3] = {t[0], t[1], t[2]};
    out.write(reinterpret_cast<const char*>(indices), sizeof(indices));
  }
}

void writeObj(std::ostream& out, const BodyMesh& mesh) {
  out << "# PoseFusion2 body mesh, metres\n";
  // %g keeps every finite float whole (a fixed-point format of a huge value would not fit a line buffer).
  char line[128];
  for (const auto& v : mesh.vertices) {
    if (!v.allFinite()) throw Error("body mesh has a vertex that is not a finite number");
    std::snprintf(line, sizeof(line), "v %.7g %.7g %.7g\n", v.x(), v.y(), v.z());
    out << line;
  }
  for (const auto& t : mesh.triangles) out << "f " << t[0] + 1 << ' ' << t[1] + 1 << ' ' << t[2] + 1 << '\n';
}

}  // namespace

void writeBodyMesh(const std::string& path, const BodyMesh& mesh) {
  if (endsWith(path, ".ply")) {
    writeFileAtomically(path, [&](std::ostream& out) { writePly(out, mesh); });
  } else if (endsWith(path, ".obj")) {
    writeFileAtomically(path, [&](std::ostream& out) { writeObj(out, mesh); });
  } else {
    throw fileError(path, "unknown mesh format (use .ply or .obj)");
  }
}

}  // namespace pf2

namespace pf2 {

void readBodyPoseFile(const std::string& path, BodyParameters* parameters) {
  std::array<int, kBodyJointCount> line_of{};  // 0 = not given yet
  forEachDataLine(path, "pose file", [&](std::string line, int line_number) {
    const auto hash = line.find('#');
    if (hash != std::string::npos) line.resize(hash);
    std::istringstream s(line);
    std::string name;
    if (!(s >> name)) return;
    int joint = -1;
    for (int j = 0; j < kBodyJointCount; ++j) {
      if (name == kBodyJointNames[j]) joint = j;
    }
    if (joint < 0) throw fileError(path, line_number, "unknown joint '" + name + "'");
    Eigen::Vector3d r;
    std::string extra;
    // An axis-angle beyond a few turns is a broken number, not a pose (and would overflow the mesh).
    if (!(s >> r.x() >> r.y() >> r.z()) || (s >> extra) || !r.allFinite() || r.norm() > 100.0) {
      throw fileError(path, line_number, "expected 'NAME ax ay az' (three finite numbers, an angle of at most 100 rad)");
    }
    if (line_of[joint] != 0) {
      throw fileError(path, line_number, "joint '" + name + "' set twice (first on line " +
                                             std::to_string(line_of[joint]) + ")");
    }
    line_of[joint] = line_number;
    parameters->pose[joint] = r;
  });
}

}  // namespace pf2
