#include "pf2/synth/rasterizer.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "parallel_for.h"
namespace pf2 {

void RenderMesh::computeVertexNormals() {
  normals.assign(vertices.size(), Eigen::Vector3f::Zero());
  for (const Eigen::Vector3i& t : triangles) {
    // The cross product's length is twice the area: larger faces weigh more.
    const Eigen::Vector3f n =
        (vertices[t[1]] - vertices[t[0]]).cross(vertices[t[2]] - vertices[t[0]]);
    for (int k = 0; k < 3; ++k) normals[t[k]] += n;
  }
  for (Eigen::Vector3f& n : normals) {
    const float length = n.norm();
    n = length > 0.0f ? Eigen::Vector3f(n / length) : Eigen::Vector3f::UnitZ();
  }
}

namespace {

// A triangle after near-plane clipping and projection. Its vertices carry their barycentric
// coordinates in the source triangle, so shading interpolates the source attributes.
struct ScreenTriangle {
  double x[3], y[3];
  double inv_z[3];
  Eigen::Vector3d source_bary[3];
  // Edge functions w_k(x, y) = a[k] x + b[k] y + c[k], normalised so that they sum to 1.
  double a[3], b[3], c[3];
  int mesh = 0;
  int triangle = 0;
  int min_x = 0, max_x = 0, min_y = 0, max_y = 0;  // pixel bounding box, inclusive
};

struct ClipVertex {
  Eigen::Vector3d p_c;
  Eigen::Vector3d bary;
};

// Sutherland–Hodgman against z >= near: a triangle becomes a polygon of up to four vertices.
int clipNear(const ClipVertex in[3], double near_plane, ClipVertex out[4]) {
  int count = 0;
  for (int i = 0; i < 3; ++i) {
    const ClipVertex& a = in[i];
    const ClipVertex& b = in[(i + 1) % 3];
    const bool a_inside = a.p_c.z() >= near_plane;
    const bool b_inside = b.p_c.z() >= near_plane;
    if (a_inside) out[count++] = a;
    if (a_inside != b_inside) {
      const double s = (near_plane - a.p_c.z()) / (b.p_c.z() - a.p_c.z());
      out[count++] = {a.p_c + s * (b.p_c - a.p_c), a.bary + s * (b.bary - a.bary)};
    }
  }
  return count;
}

// Projects the clipped triangle; false if it is degenerate or misses the pixel window.
bool setUp(const ClipVertex& v0, const ClipVertex& v1, const ClipVertex& v2,
           const CameraIntrinsics& K, int x_lo, int y_lo, int x_hi, int y_hi, ScreenTriangle* t) {
  const ClipVertex* v[3] = {&v0, &v1, &v2};
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d& p = v[k]->p_c;
    t->inv_z[k] = 1.0 / p.z();
    t->x[k] = K.fx * p.x() * t->inv_z[k] + K.cx;
    t->y[k] = K.fy * p.y() * t->inv_z[k] + K.cy;
    t->source_bary[k] = v[k]->bary;
  }
  const double area = (t->x[1] - t->x[0]) * (t->y[2] - t->y[0]) -
                      (t->x[2] - t->x[0]) * (t->y[1] - t->y[0]);
  if (!(std::abs(area) > 1e-12)) return false;
  const double min_xf = std::min({t->x[0], t->x[1], t->x[2]});
  const double max_xf = std::max({t->x[0], t->x[1], t->x[2]});
  const double min_yf = std::min({t->y[0], t->y[1], t->y[2]});
  const double max_yf = std::max({t->y[0], t->y[1], t->y[2]});
  t->min_x = static_cast<int>(std::max<double>(x_lo, std::ceil(min_xf)));
  t->max_x = static_cast<int>(std::min<double>(x_hi, std::floor(max_xf)));
  t->min_y = static_cast<int>(std::max<double>(y_lo, std::ceil(min_yf)));
  t->max_y = static_cast<int>(std::min<double>(y_hi, std::floor(max_yf)));
  if (t->min_x > t->max_x || t->min_y > t->max_y) return false;
  for (int k = 0; k < 3; ++k) {
    const int i = (k + 1) % 3, j = (k + 2) % 3;  // edge opposite vertex k
    t->a[k] = (t->y[i] - t->y[j]) / area;
    t->b[k] = (t->x[j] - t->x[i]) / area;
    t->c[k] = (t->x[i] * t->y[j] - t->x[j] * t->y[i]) / area;
  }
  return true;
}

// Clips, culls and projects every triangle of the meshes.
std::vector<ScreenTriangle> project(const std::vector<const RenderMesh*>& meshes,
                                    const CameraIntrinsics& K, const Eigen::Isometry3d& T_w_c,
                                    double near_plane, int x_lo, int y_lo, int x_hi, int y_hi) {
  const Eigen::Isometry3d T_c_w = T_w_c.inverse();
  std::vector<ScreenTriangle> result;
  size_t triangle_count = 0;
  for (const RenderMesh* mesh : meshes) triangle_count += mesh->triangles.size();
  result.reserve(triangle_count);
  std::vector<Eigen::Vector3d> p_c;
  for (size_t m = 0; m < meshes.size(); ++m) {
    const RenderMesh& mesh = *meshes[m];
    p_c.resize(mesh.vertices.size());
    for (size_t i = 0; i < p_c.size(); ++i) p_c[i] = T_c_w * mesh.vertices[i].cast<double>();
    for (size_t f = 0; f < mesh.triangles.size(); ++f) {
      const Eigen::Vector3i& tri = mesh.triangles[f];
      const Eigen::Vector3d& a = p_c[tri[0]];
      const Eigen::Vector3d& b = p_c[tri[1]];
      const Eigen::Vector3d& c = p_c[tri[2]];
      if (a.z() < near_plane && b.z() < near_plane && c.z() < near_plane) continue;
      // Seen from behind: the camera (origin) lies on the back side of the triangle's plane.
      if (mesh.cull_back_faces && (b - a).cross(c - a).dot(a) >= 0.0) continue;
      const ClipVertex in[3] = {{a, Eigen::Vector3d::UnitX()},
                                {b, Eigen::Vector3d::UnitY()},
                                {c, Eigen::Vector3d::UnitZ()}};
      ClipVertex poly[4];
      const int count = clipNear(in, near_plane, poly);
      for (int k = 1; k + 1 < count; ++k) {
        ScreenTriangle t;
        t.mesh = static_cast<int>(m);
        t.triangle = static_cast<int>(f);
        if (setUp(poly[0], poly[k], poly[k + 1], K, x_lo, y_lo, x_hi, y_hi, &t)) {
          result.push_back(t);
        }
      }
    }
  }
  return result;
}

// Pixels x0..x1 of row y inside the triangle (all three edge functions >= 0). The bounds are
// widened by a hair so that a pixel centre exactly on a shared edge is never missed by both sides.
bool rowSpan(const ScreenTriangle& t, int y, int* x0, int* x1) {
  double lo = t.min_x, hi = t.max_x;
  for (int k = 0; k < 3; ++k) {
    const double offset = t.b[k] * y + t.c[k];
    if (t.a[k] > 0.0) {
      lo = std::max(lo, -offset / t.a[k] - 1e-9);
    } else if (t.a[k] < 0.0) {
      hi = std::min(hi, -offset / t.a[k] + 1e-9);
    } else if (offset < -1e-12) {
      return false;
    }
  }
  *x0 = static_cast<int>(std::ceil(lo));
  *x1 = static_cast<int>(std::floor(hi));
  return *x0 <= *x1;
}

Eigen::Vector3f sampleBilinear(const cv::Mat& texture, float u, float v) {
  u = std::min(std::max(u, 0.0f), static_cast<float>(texture.cols - 1));
  v = std::min(std::max(v, 0.0f), static_cast<float>(texture.rows - 1));
  const int u0 = std::min(static_cast<int>(u), texture.cols - 2 < 0 ? 0 : texture.cols - 2);
  const int v0 = std::min(static_cast<int>(v), texture.rows - 2 < 0 ? 0 : texture.rows - 2);
  const int u1 = std::min(u0 + 1, texture.cols - 1);
  const int v1 = std::min(v0 + 1, texture.rows - 1);
  const float fu = u - u0, fv = v - v0;
  const cv::Vec3b* r0 = texture.ptr<cv::Vec3b>(v0);
  const cv::Vec3b* r1 = texture.ptr<cv::Vec3b>(v1);
  Eigen::Vector3f result;
  for (int ch = 0; ch < 3; ++ch) {
    const float top = r0[u0][ch] + fu * (r0[u1][ch] - r0[u0][ch]);
    const float bottom = r1[u0][ch] + fu * (r1[u1][ch] - r1[u0][ch]);
    result[ch] = (top + fv * (bottom - top)) * (1.0f / 255.0f);
  }
  return result;
}

}  // namespace

void Rasterizer::render(const std::vector<const RenderMesh*>& meshes, const TextureList& textures,
                        const CameraIntrinsics& K, const Eigen::Isometry3d& T_w_c,
                        RenderedImages* out) const {
  const int width = K.width, height = K.height;
  const std::vector<ScreenTriangle> screen =
      project(meshes, K, T_w_c, options_.near_plane, 0, 0, width - 1, height - 1);

  const int bands = std::max(1, std::min(options_.bands, height));
  const int band_height = (height + bands - 1) / bands;
  std::vector<std::vector<int>> band_triangles(bands);
  for (size_t i = 0; i < screen.size(); ++i) {
    for (int b = screen[i].min_y / band_height; b <= screen[i].max_y / band_height; ++b) {
      band_triangles[b].push_back(static_cast<int>(i));
    }
  }

  out->bgr.create(height, width, CV_8UC3);
  out->depth.create(height, width, CV_32F);
  out->labels.create(height, width, CV_16U);
  std::vector<float> inv_z(static_cast<size_t>(width) * height, 0.0f);
  std::vector<int> owner(static_cast<size_t>(width) * height, -1);
  const Eigen::Vector3f light_w = options_.light_position_w.cast<float>();
  const Eigen::Vector3f camera_w = T_w_c.translation().cast<float>();
  const float ambient = static_cast<float>(options_.ambient);
  const float diffuse = static_cast<float>(options_.diffuse);

  synth::parallelFor(0, bands, options_.parallel, [&](int band) {
    const int y_begin = band * band_height;
    const int y_end = std::min(height, y_begin + band_height);
    // Visibility: nearest surface (largest 1/z) wins; ties keep the earlier triangle.
    for (const int index : band_triangles[band]) {
      const ScreenTriangle& t = screen[index];
      const int y0 = std::max(t.min_y, y_begin), y1 = std::min(t.max_y, y_end - 1);
      for (int y = y0; y <= y1; ++y) {
        int x0 = 0, x1 = 0;
        if (!rowSpan(t, y, &x0, &x1)) continue;
        float* z_row = inv_z.data() + static_cast<size_t>(y) * width;
        int* owner_row = owner.data() + static_cast<size_t>(y) * width;
        const double w0_row = t.b[0] * y + t.c[0], w1_row = t.b[1] * y + t.c[1];
        for (int x = x0; x <= x1; ++x) {
          const double w0 = t.a[0] * x + w0_row;
          const double w1 = t.a[1] * x + w1_row;
          const double w2 = 1.0 - w0 - w1;
          const float iz = static_cast<float>(w0 * t.inv_z[0] + w1 * t.inv_z[1] + w2 * t.inv_z[2]);
          if (iz > z_row[x]) {
            z_row[x] = iz;
            owner_row[x] = index;
          }
        }
      }
    }
    // Shading of the visible surface.
    for (int y = y_begin; y < y_end; ++y) {
      cv::Vec3b* bgr_row = out->bgr.ptr<cv::Vec3b>(y);
      float* depth_row = out->depth.ptr<float>(y);
      std::uint16_t* label_row = out->labels.ptr<std::uint16_t>(y);
      for (int x = 0; x < width; ++x) {
        const size_t pixel = static_cast<size_t>(y) * width + x;
        if (owner[pixel] < 0) {
          bgr_row[x] = cv::Vec3b(0, 0, 0);
          depth_row[x] = 0.0f;
          label_row[x] = 0;
          continue;
        }
        const ScreenTriangle& t = screen[owner[pixel]];
        const RenderMesh& mesh = *meshes[t.mesh];
        const Eigen::Vector3i& tri = mesh.triangles[t.triangle];
        // Perspective-correct weights of the screen vertices, then of the source vertices.
        const double w0 = t.a[0] * x + t.b[0] * y + t.c[0];
        const double w1 = t.a[1] * x + t.b[1] * y + t.c[1];
        const double w2 = 1.0 - w0 - w1;
        const double iz = w0 * t.inv_z[0] + w1 * t.inv_z[1] + w2 * t.inv_z[2];
        const Eigen::Vector3f bary =
            ((w0 * t.inv_z[0] * t.source_bary[0] + w1 * t.inv_z[1] * t.source_bary[1] +
              w2 * t.inv_z[2] * t.source_bary[2]) / iz).cast<float>();
        const Eigen::Vector3f p_w = bary[0] * mesh.vertices[tri[0]] +
                                    bary[1] * mesh.vertices[tri[1]] +
                                    bary[2] * mesh.vertices[tri[2]];
        Eigen::Vector3f normal;
        if (mesh.normals.empty()) {
          normal = (mesh.vertices[tri[1]] - mesh.vertices[tri[0]])
                       .cross(mesh.vertices[tri[2]] - mesh.vertices[tri[0]]);
        } else {
          normal = bary[0] * mesh.normals[tri[0]] + bary[1] * mesh.normals[tri[1]] +
                   bary[2] * mesh.normals[tri[2]];
        }
        normal.normalize();
        if (normal.dot(camera_w - p_w) < 0.0f) normal = -normal;  // lit from the side we see
        Eigen::Vector3f albedo;
        if (!mesh.triangle_textures.empty()) {
          const Eigen::Vector2f uv = bary[0] * mesh.uvs[tri[0]] + bary[1] * mesh.uvs[tri[1]] +
                                     bary[2] * mesh.uvs[tri[2]];
          albedo = sampleBilinear(textures[mesh.triangle_textures[t.triangle]], uv.x(), uv.y());
        } else {
          albedo = bary[0] * mesh.colors[tri[0]] + bary[1] * mesh.colors[tri[1]] +
                   bary[2] * mesh.colors[tri[2]];
        }
        const Eigen::Vector3f to_light = (light_w - p_w).normalized();
        const float shade = ambient + diffuse * std::max(0.0f, normal.dot(to_light));
        for (int ch = 0; ch < 3; ++ch) {
          bgr_row[x][ch] = static_cast<std::uint8_t>(
              std::min(255.0f, std::max(0.0f, albedo[ch] * shade * 255.0f + 0.5f)));
        }
        depth_row[x] = static_cast<float>(1.0 / iz);
        label_row[x] = mesh.label;
      }
    }
  });
}

double Rasterizer::unboundedCoverage(const RenderMesh& mesh, const CameraIntrinsics& K,
                                     const Eigen::Isometry3d& T_w_c, int stride,
                                     int margin) const {
  stride = std::max(1, stride);
  const int x_lo = -margin * K.width, x_hi = (margin + 1) * K.width - 1;
  const int y_lo = -margin * K.height, y_hi = (margin + 1) * K.height - 1;
  const std::vector<ScreenTriangle> screen =
      project({&mesh}, K, T_w_c, options_.near_plane, x_lo, y_lo, x_hi, y_hi);
  if (screen.empty()) return 0.0;
  // Only the sample grid under the mesh's bounding box is allocated.
  int box_x0 = x_hi, box_x1 = x_lo, box_y0 = y_hi, box_y1 = y_lo;
  for (const ScreenTriangle& t : screen) {
    box_x0 = std::min(box_x0, t.min_x);
    box_x1 = std::max(box_x1, t.max_x);
    box_y0 = std::min(box_y0, t.min_y);
    box_y1 = std::max(box_y1, t.max_y);
  }
  const int cols = (box_x1 - box_x0) / stride + 1, rows = (box_y1 - box_y0) / stride + 1;
  std::vector<std::uint8_t> covered(static_cast<size_t>(cols) * rows, 0);
  for (const ScreenTriangle& t : screen) {
    // Sample positions box_x0 + stride * i inside the triangle's box.
    const int i0 = (t.min_x - box_x0 + stride - 1) / stride, i1 = (t.max_x - box_x0) / stride;
    const int j0 = (t.min_y - box_y0 + stride - 1) / stride, j1 = (t.max_y - box_y0) / stride;
    for (int j = j0; j <= j1; ++j) {
      const double y = box_y0 + stride * j;
      std::uint8_t* row = covered.data() + static_cast<size_t>(j) * cols;
      for (int i = i0; i <= i1; ++i) {
        if (row[i]) continue;
        const double x = box_x0 + stride * i;
        const double w0 = t.a[0] * x + t.b[0] * y + t.c[0];
        const double w1 = t.a[1] * x + t.b[1] * y + t.c[1];
        if (w0 >= 0.0 && w1 >= 0.0 && w0 + w1 <= 1.0) row[i] = 1;
      }
    }
  }
  size_t count = 0;
  for (const std::uint8_t c : covered) count += c;
  return static_cast<double>(count) * stride * stride;
}

}  // namespace pf2
