#include "pf2/surface/triangle_mesh.h"

#include <pcl/PolygonMesh.h>
#include <pcl/conversions.h>
#include <pcl/io/ply_io.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>

#include "pf2/core/atomic_file.h"
#include "pf2/core/error.h"

namespace pf2 {

double TriangleMesh::area() const {
  double total = 0.0;
  for (const Eigen::Vector3i& t : triangles) {
    const Eigen::Vector3d a = vertices[t[0]].cast<double>(), b = vertices[t[1]].cast<double>(),
                          c = vertices[t[2]].cast<double>();
    total += 0.5 * (b - a).cross(c - a).norm();
  }
  return total;
}

namespace {

// True when the mesh has one colour per vertex, false when it has none; throws pf2::Error naming
// the path on any other count (and when the edges' colours do not match the edges).
bool hasVertexColours(const TriangleMesh& mesh, const std::string& path) {
  if (mesh.edge_colors.size() != mesh.edges.size()) {
    throw fileError(path, "mesh has " + std::to_string(mesh.edge_colors.size()) + " edge colours for " +
                              std::to_string(mesh.edges.size()) + " edges");
  }
  if (mesh.colors.empty()) return false;
  if (mesh.colors.size() != mesh.vertices.size()) {
    throw fileError(path, "mesh has " + std::to_string(mesh.colors.size()) + " colours for " +
                              std::to_string(mesh.vertices.size()) + " vertices");
  }
  return true;
}

}  // namespace

void saveMeshPly(const TriangleMesh& mesh, const std::string& path) {
  const bool coloured = hasVertexColours(mesh, path);
  writeFileAtomically(path, [&](std::ostream& out) {
    out << "ply\nformat binary_little_endian 1.0\ncomment PoseFusion2 static map, metres, world frame\n"
        << "element vertex " << mesh.vertices.size() << "\nproperty float x\nproperty float y\nproperty float z\n";
    if (coloured) out << "property uchar red\nproperty uchar green\nproperty uchar blue\n";
    out << "element face " << mesh.triangles.size() << "\nproperty list uchar int vertex_indices\n";
    if (!mesh.edges.empty()) {
      out << "element edge " << mesh.edges.size() << "\nproperty int vertex1\nproperty int vertex2\n"
          << "property uchar red\nproperty uchar green\nproperty uchar blue\n";
    }
    out << "end_header\n";
    // Little-endian host (x86-64, arm64): the in-memory bytes are the file's bytes.
    std::vector<char> buffer;
    const std::size_t vertex_bytes = 12 + (coloured ? 3 : 0);
    buffer.resize(mesh.vertices.size() * vertex_bytes);
    for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
      char* p = buffer.data() + i * vertex_bytes;
      std::memcpy(p, mesh.vertices[i].data(), 12);
      if (coloured) std::memcpy(p + 12, mesh.colors[i].data(), 3);
    }
    out.write(buffer.data(), static_cast<std::streamsize>(buffer.size()));
    buffer.resize(mesh.triangles.size() * 13);
    for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
      char* p = buffer.data() + i * 13;
      p[0] = 3;
      std::memcpy(p + 1, mesh.triangles[i].data(), 12);
    }
    out.write(buffer.data(), static_cast<std::streamsize>(buffer.size()));
    buffer.resize(mesh.edges.size() * 11);
    for (std::size_t i = 0; i < mesh.edges.size(); ++i) {
      char* p = buffer.data() + i * 11;
      std::memcpy(p, mesh.edges[i].data(), 8);
      std::memcpy(p + 8, mesh.edge_colors[i].data(), 3);
    }
    out.write(buffer.data(), static_cast<std::streamsize>(buffer.size()));
  });
}

void saveMeshObj(const TriangleMesh& mesh, const std::string& path) {
  const bool coloured = hasVertexColours(mesh, path);
  writeFileAtomically(path, [&](std::ostream& out) {
    out << "# PoseFusion2 static map, metres, world frame\n";
    char line[128];
    for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
      const Eigen::Vector3f& v = mesh.vertices[i];
      int n = std::snprintf(line, sizeof(line), "v %.6g %.6g %.6g", v.x(), v.y(), v.z());
      if (coloured) {
        const auto& c = mesh.colors[i];
        n += std::snprintf(line + n, sizeof(line) - n, " %.4g %.4g %.4g", c[0] / 255.0, c[1] / 255.0, c[2] / 255.0);
      }
      out.write(line, n);
      out.put('\n');
    }
    for (const Eigen::Vector3i& t : mesh.triangles) {
      const int n = std::snprintf(line, sizeof(line), "f %d %d %d\n", t[0] + 1, t[1] + 1, t[2] + 1);
      out.write(line, n);
    }
    for (const Eigen::Vector2i& e : mesh.edges) {
      const int n = std::snprintf(line, sizeof(line), "l %d %d\n", e[0] + 1, e[1] + 1);
      out.write(line, n);
    }
  });
}

namespace {

// Reads the PLY header and refuses counts the file cannot hold (every vertex takes at least 3
// bytes in ASCII and 12 in binary, every face at least 7 and 13) before PCL allocates for them:
// a header claiming 10^9 vertices would otherwise cost gigabytes before failing.
void checkPlyHeader(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw fileError(path, "cannot open for reading");
  std::string line;
  if (!std::getline(in, line) || line.rfind("ply", 0) != 0) throw fileError(path, "not a PLY file (no 'ply' header)");
  bool ascii = false;
  double vertices = 0, faces = 0;
  for (int n = 0; std::getline(in, line) && line.rfind("end_header", 0) != 0; ++n) {
    if (n > 1000) throw fileError(path, "PLY header without end_header in its first 1000 lines");
    std::istringstream fields(line);
    std::string word, element;
    fields >> word;
    if (word == "format") ascii = line.find("ascii") != std::string::npos;
    double count = 0;
    if (word == "element" && (fields >> element >> count)) {
      if (element == "vertex") vertices = count;
      if (element == "face") faces = count;
    }
  }
  const auto header_end = static_cast<double>(in.tellg());
  in.seekg(0, std::ios::end);
  const double body_bytes = static_cast<double>(in.tellg()) - header_end;
  const double needed = ascii ? 3 * vertices + 7 * faces : 12 * vertices + 13 * faces;
  if (vertices < 0 || faces < 0 || needed > body_bytes) {
    char text[160];
    std::snprintf(text, sizeof(text), "PLY header claims %.0f vertices and %.0f faces, more than its %.0f bytes can hold",
                  vertices, faces, body_bytes);
    throw fileError(path, text);
  }
}

}  // namespace

TriangleMesh loadMeshPly(const std::string& path) {
  checkPlyHeader(path);
  pcl::PolygonMesh polygon_mesh;
  if (pcl::io::loadPLYFile(path, polygon_mesh) < 0) throw fileError(path, "not a readable PLY mesh");
  TriangleMesh mesh;
  try {
    mesh = fromPolygonMesh(polygon_mesh);
  } catch (const Error& e) {
    throw fileError(path, e.what());
  }
  return mesh;
}

void toPolygonMesh(const TriangleMesh& mesh, pcl::PolygonMesh* out) {
  if (!mesh.colors.empty()) {
    pcl::PointCloud<pcl::PointXYZRGB> cloud;
    cloud.resize(mesh.vertices.size());
    for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
      pcl::PointXYZRGB& p = cloud[i];
      p.x = mesh.vertices[i].x();
      p.y = mesh.vertices[i].y();
      p.z = mesh.vertices[i].z();
      p.r = mesh.colors[i][0];
      p.g = mesh.colors[i][1];
      p.b = mesh.colors[i][2];
    }
    pcl::toPCLPointCloud2(cloud, out->cloud);
  } else {
    pcl::PointCloud<pcl::PointXYZ> cloud;
    cloud.resize(mesh.vertices.size());
    for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
      cloud[i].getVector3fMap() = mesh.vertices[i];
    }
    pcl::toPCLPointCloud2(cloud, out->cloud);
  }
  out->polygons.resize(mesh.triangles.size());
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    const Eigen::Vector3i& t = mesh.triangles[i];
    out->polygons[i].vertices.assign(t.data(), t.data() + 3);
  }
}

TriangleMesh fromPolygonMesh(const pcl::PolygonMesh& polygon_mesh) {
  TriangleMesh mesh;
  bool has_colour = false;
  for (const auto& field : polygon_mesh.cloud.fields) has_colour = has_colour || field.name == "rgb" || field.name == "rgba";
  if (has_colour) {
    pcl::PointCloud<pcl::PointXYZRGB> cloud;
    pcl::fromPCLPointCloud2(polygon_mesh.cloud, cloud);
    for (const auto& p : cloud) {
      mesh.vertices.emplace_back(p.x, p.y, p.z);
      mesh.colors.push_back({p.r, p.g, p.b});
    }
  } else {
    pcl::PointCloud<pcl::PointXYZ> cloud;
    pcl::fromPCLPointCloud2(polygon_mesh.cloud, cloud);
    for (const auto& p : cloud) mesh.vertices.emplace_back(p.x, p.y, p.z);
  }
  const int n = static_cast<int>(mesh.vertices.size());
  for (const auto& polygon : polygon_mesh.polygons) {
    const auto& v = polygon.vertices;
    for (std::size_t k = 1; k + 1 < v.size(); ++k) {
      const Eigen::Vector3i t(static_cast<int>(v[0]), static_cast<int>(v[k]), static_cast<int>(v[k + 1]));
      if (!((t.array() >= 0).all() && (t.array() < n).all())) {
        throw Error("a face refers to vertex " + std::to_string(t.minCoeff() < 0 ? t.minCoeff() : t.maxCoeff()) +
                    " of " + std::to_string(n));
      }
      mesh.triangles.push_back(t);
    }
  }
  return mesh;
}

}  // namespace pf2
