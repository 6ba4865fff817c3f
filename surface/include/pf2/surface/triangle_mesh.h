#pragma once
// The static map's surface as a plain triangle mesh, and its files: PLY (binary, vertex colours)
// and OBJ written atomically, PLY read back through PCL; conversion to pcl::PolygonMesh for PCL users.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace pcl {
struct PolygonMesh;
}

namespace pf2 {

struct TriangleMesh {
  std::vector<Eigen::Vector3f> vertices;             // world frame, metres
  std::vector<std::array<std::uint8_t, 3>> colors;   // per vertex RGB, empty or one per vertex
  std::vector<Eigen::Vector3i> triangles;            // counter-clockwise seen from free space
  // Line segments between vertices (polylines drawn into a scene), each with an RGB colour; the
  // static map has none.
  std::vector<Eigen::Vector2i> edges;
  std::vector<std::array<std::uint8_t, 3>> edge_colors;  // one per edge

  bool empty() const { return triangles.empty(); }
  // Total triangle area, square metres.
  double area() const;
};

// Binary little-endian PLY with float x y z, uchar red green blue (when colours exist), triangle
// faces and, when there are edges, an `edge` element (int vertex1 vertex2, uchar red green blue: the
// element MeshLab draws; PCL's reader skips it). Written to a temporary name and renamed. Throws
// pf2::Error naming the path.
void saveMeshPly(const TriangleMesh& mesh, const std::string& path);
// Wavefront OBJ (ASCII): `v x y z` lines, with colour as `v x y z r g b` (0..1, the extension
// MeshLab and Blender read) when colours exist, then 1-based `f a b c` faces and `l a b` lines for
// the edges (OBJ lines carry no colour: their vertices have it). For tools that take OBJ but not
// PLY. Written to a temporary name and renamed. Throws pf2::Error naming the path.
void saveMeshObj(const TriangleMesh& mesh, const std::string& path);
// Reads any PLY triangle mesh PCL reads (ASCII or binary; polygons are fanned into triangles); an
// empty mesh (0 vertices, e.g. a map of nothing) reads as an empty TriangleMesh. Throws pf2::Error
// naming the path when it cannot be read.
TriangleMesh loadMeshPly(const std::string& path);

// Conversion to and from PCL (point type pcl::PointXYZRGB when coloured, else pcl::PointXYZ).
// fromPolygonMesh throws pf2::Error on a face that refers to a vertex the mesh does not have.
void toPolygonMesh(const TriangleMesh& mesh, pcl::PolygonMesh* out);
TriangleMesh fromPolygonMesh(const pcl::PolygonMesh& mesh);

}  // namespace pf2
