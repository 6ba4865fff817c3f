#include "pf2/synth/static_scene.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <Eigen/Geometry>

#include "pf2/core/atomic_file.h"
#include "pf2/core/error.h"
#include "hash_random.h"
#include "parallel_for.h"

namespace pf2 {

namespace {

using synth::HashRng;
using synth::hashOf;
using synth::uniform01;

// Smooth value noise on the integer lattice, in [0, 1].
double valueNoise(std::uint64_t seed, double x, double y) {
  const double fx = std::floor(x), fy = std::floor(y);
  const auto ix = static_cast<std::int64_t>(fx), iy = static_cast<std::int64_t>(fy);
  double tx = x - fx, ty = y - fy;
  tx = tx * tx * (3.0 - 2.0 * tx);
  ty = ty * ty * (3.0 - 2.0 * ty);
  const auto at = [seed](std::int64_t i, std::int64_t j) {
    return uniform01(synth::hashLattice(seed, static_cast<std::uint64_t>(i), static_cast<std::uint64_t>(j)));
  };
  const double a = at(ix, iy), b = at(ix + 1, iy), c = at(ix, iy + 1), d = at(ix + 1, iy + 1);
  return (a + tx * (b - a)) + ty * ((c + tx * (d - c)) - (a + tx * (b - a)));
}

// Fractal noise: `octaves` layers from `period` metres down, each half the size, in [0, 1].
double fbm(std::uint64_t seed, double s, double t, double period, int octaves) {
  double sum = 0.0, weight = 0.0, amplitude = 1.0, frequency = 1.0 / period;
  for (int k = 0; k < octaves; ++k) {
    sum += amplitude * valueNoise(seed + k, s * frequency, t * frequency);
    weight += amplitude;
    amplitude *= 0.6;
    frequency *= 2.3;
  }
  return sum / weight;
}

Eigen::Vector3f hsvToBgr(double h, double s, double v) {
  h = std::fmod(std::fmod(h, 1.0) + 1.0, 1.0) * 6.0;
  const int sector = static_cast<int>(h) % 6;
  const double f = h - std::floor(h);
  const double p = v * (1 - s), q = v * (1 - s * f), r = v * (1 - s * (1 - f));
  double red = v, green = r, blue = p;
  switch (sector) {
    case 0: red = v; green = r; blue = p; break;
    case 1: red = q; green = v; blue = p; break;
    case 2: red = p; green = v; blue = r; break;
    case 3: red = p; green = q; blue = v; break;
    case 4: red = r; green = p; blue = v; break;
    default: red = v; green = p; blue = q; break;
  }
  return Eigen::Vector3f(static_cast<float>(blue), static_cast<float>(green), static_cast<float>(red));
}

enum class Style { kNoise, kChecker, kStripes, kBlobs, kWood, kPlain };

// What a surface looks like: a pattern over two colours, with fine noise on top everywhere.
struct Material {
  Style style = Style::kNoise;
  Eigen::Vector3f color_a, color_b;
  double period = 0.2;   // main pattern size, metres
  double angle = 0.0;    // stripe direction, radians
  std::uint64_t seed = 0;
};

Material randomMaterial(HashRng* rng, Style style, double saturation, double value) {
  Material m;
  m.style = style;
  const double hue = rng->uniform(0.0, 1.0);
  m.color_a = hsvToBgr(hue, saturation * rng->uniform(0.6, 1.0), value * rng->uniform(0.8, 1.0));
  m.color_b = hsvToBgr(hue + rng->uniform(-0.35, 0.35), saturation * rng->uniform(0.3, 1.0),
                       value * rng->uniform(0.35, 0.75));
  m.period = style == Style::kChecker ? rng->uniform(0.04, 0.16)
           : style == Style::kStripes ? rng->uniform(0.03, 0.12)
           : style == Style::kBlobs   ? rng->uniform(0.06, 0.2)
           : style == Style::kWood    ? rng->uniform(0.12, 0.2)
                                      : rng->uniform(0.15, 0.5);
  m.angle = rng->uniform(0.0, 3.14159);
  m.seed = rng->next();
  return m;
}

Eigen::Vector3f shadeTexel(const Material& m, double s, double t) {
  const double fine = fbm(m.seed ^ 0x5151, s, t, 0.03, 2);  // 1-3 cm detail everywhere
  double mix = 0.0;
  switch (m.style) {
    case Style::kNoise:
      mix = fbm(m.seed, s, t, m.period, 4);
      mix = std::min(1.0, std::max(0.0, (mix - 0.5) * 2.2 + 0.5));
      break;
    case Style::kChecker: {
      const long cell = static_cast<long>(std::floor(s / m.period)) + static_cast<long>(std::floor(t / m.period));
      mix = (cell & 1) ? 0.9 : 0.1;
      mix += 0.25 * (fbm(m.seed, s, t, 4 * m.period, 2) - 0.5);
      break;
    }
    case Style::kStripes: {
      const double along = s * std::cos(m.angle) + t * std::sin(m.angle);
      const double wobble = 0.3 * m.period * (fbm(m.seed, s, t, 0.5, 2) - 0.5);
      mix = std::fmod(std::fabs(along + wobble) / m.period, 1.0) < 0.45 ? 0.85 : 0.15;
      break;
    }
    case Style::kBlobs: {
      mix = 0.25 * fbm(m.seed, s, t, 0.4, 3);
      const auto cs = static_cast<std::int64_t>(std::floor(s / m.period));
      const auto ct = static_cast<std::int64_t>(std::floor(t / m.period));
      for (std::int64_t i = cs - 1; i <= cs + 1; ++i) {
        for (std::int64_t j = ct - 1; j <= ct + 1; ++j) {
          const std::uint64_t h = hashOf(m.seed, static_cast<std::uint64_t>(i), static_cast<std::uint64_t>(j));
          const double bx = (i + uniform01(h)) * m.period;
          const double by = (j + uniform01(synth::mix64(h))) * m.period;
          const double r = m.period * (0.15 + 0.5 * uniform01(synth::mix64(h + 7)));
          if ((s - bx) * (s - bx) + (t - by) * (t - by) < r * r) {
            mix = 0.45 + 0.55 * uniform01(synth::mix64(h + 3));
          }
        }
      }
      break;
    }
    case Style::kWood: {
      const auto plank = static_cast<std::int64_t>(std::floor(t / m.period));
      const double offset = uniform01(hashOf(m.seed, static_cast<std::uint64_t>(plank))) * 2.0;
      const double grain = fbm(m.seed + static_cast<std::uint64_t>(plank), (s + offset) * 0.15, t * 4.0, 0.05, 4);
      const double joint = std::fmod(t / m.period, 1.0) < 0.04 ? 1.0 : 0.0;
      const double butt = std::fmod((s + offset) / 1.2, 1.0) < 0.006 ? 1.0 : 0.0;
      mix = std::min(1.0, 0.25 + 0.5 * grain + 0.4 * uniform01(hashOf(m.seed, 99, static_cast<std::uint64_t>(plank))) +
                              0.8 * std::max(joint, butt));
      break;
    }
    case Style::kPlain:
      mix = 0.5 * fbm(m.seed, s, t, m.period, 3);
      break;
  }
  const float f = static_cast<float>(0.82 + 0.36 * fine);
  return f * (m.color_a + static_cast<float>(mix) * (m.color_b - m.color_a));
}

cv::Mat bakeTexture(const Material& m, int cols, int rows, double texels_per_metre) {
  cv::Mat texture(rows, cols, CV_8UC3);
  synth::parallelFor(0, rows, rows * cols > 50000, [&](int v) {
    cv::Vec3b* row = texture.ptr<cv::Vec3b>(v);
    for (int u = 0; u < cols; ++u) {
      const Eigen::Vector3f c = shadeTexel(m, u / texels_per_metre, v / texels_per_metre);
      for (int ch = 0; ch < 3; ++ch) {
        row[u][ch] = static_cast<std::uint8_t>(std::min(255.0f, std::max(0.0f, c[ch] * 255.0f + 0.5f)));
      }
    }
  });
  return texture;
}

}  // namespace

// Adds textured quads and boxes to a StaticScene.
class SceneBuilder {
 public:
  SceneBuilder(StaticScene* scene, std::uint64_t seed) : scene_(scene), rng_(seed) {}

  HashRng& rng() { return rng_; }

  // Quad o, o+eu, o+eu+ev, o+ev; its front side is eu x ev.
  void quad(const Eigen::Vector3d& o, const Eigen::Vector3d& eu, const Eigen::Vector3d& ev,
            const Material& material) {
    const double tpm = scene_->options_.texels_per_metre;
    const int cols = std::max(2, static_cast<int>(std::ceil(eu.norm() * tpm)) + 1);
    const int rows = std::max(2, static_cast<int>(std::ceil(ev.norm() * tpm)) + 1);
    const int texture = static_cast<int>(scene_->textures_.size());
    scene_->textures_.push_back(bakeTexture(material, cols, rows, tpm));
    const cv::Scalar mean = cv::mean(scene_->textures_.back());
    const Eigen::Vector3f mean_color(static_cast<float>(mean[0] / 255), static_cast<float>(mean[1] / 255),
                                     static_cast<float>(mean[2] / 255));
    RenderMesh& mesh = scene_->mesh_;
    const int base = static_cast<int>(mesh.vertices.size());
    const Eigen::Vector3f normal = eu.cross(ev).normalized().cast<float>();
    const double su = eu.norm() * tpm, sv = ev.norm() * tpm;
    const Eigen::Vector3d corners[4] = {o, o + eu, o + eu + ev, o + ev};
    const Eigen::Vector2f uvs[4] = {{0.0f, 0.0f}, {static_cast<float>(su), 0.0f},
                                    {static_cast<float>(su), static_cast<float>(sv)},
                                    {0.0f, static_cast<float>(sv)}};
    for (int k = 0; k < 4; ++k) {
      mesh.vertices.push_back(corners[k].cast<float>());
      mesh.normals.push_back(normal);
      mesh.uvs.push_back(uvs[k]);
      scene_->vertex_colors_.push_back(mean_color);
    }
    mesh.triangles.emplace_back(base, base + 1, base + 2);
    mesh.triangles.emplace_back(base, base + 2, base + 3);
    mesh.triangle_textures.push_back(texture);
    mesh.triangle_textures.push_back(texture);
  }

  // Closed box (the bottom face is left out when it stands on the floor). One material per box
  // with a fresh pattern seed per face, so no two faces look alike.
  void box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, Material material) {
    const double dx = hi.x() - lo.x(), dy = hi.y() - lo.y(), dz = hi.z() - lo.z();
    const auto next = [&]() { material.seed = rng_.next(); return material; };
    quad({hi.x(), lo.y(), lo.z()}, {0, dy, 0}, {0, 0, dz}, next());   // +x
    quad({lo.x(), hi.y(), lo.z()}, {0, -dy, 0}, {0, 0, dz}, next());  // -x
    quad({hi.x(), hi.y(), lo.z()}, {-dx, 0, 0}, {0, 0, dz}, next());  // +y
    quad({lo.x(), lo.y(), lo.z()}, {dx, 0, 0}, {0, 0, dz}, next());   // -y
    quad({lo.x(), lo.y(), hi.z()}, {dx, 0, 0}, {0, dy, 0}, next());   // +z
    if (lo.z() > 1e-6) quad({lo.x(), hi.y(), lo.z()}, {dx, 0, 0}, {0, -dy, 0}, next());  // -z
  }

  Material material(Style style, double saturation = 0.5, double value = 0.8) {
    return randomMaterial(&rng_, style, saturation, value);
  }

 private:
  StaticScene* scene_;
  HashRng rng_;
};

StaticScene::StaticScene(const Options& options) : options_(options) {
  if (!(options.texels_per_metre >= 8.0 && options.texels_per_metre <= 1024.0)) {
    throw Error("StaticScene: texels_per_metre must lie in [8, 1024]");
  }
  SceneBuilder b(this, synth::hashOf(options.seed, 0x5ce9e));
  using V = Eigen::Vector3d;
  const V room = roomSize();
  const double X = room.x(), Y = room.y(), Z = room.z();

  // Room, seen from inside.
  b.quad({0, 0, 0}, {X, 0, 0}, {0, Y, 0}, b.material(Style::kWood, 0.45, 0.75));     // floor
  b.quad({0, Y, Z}, {X, 0, 0}, {0, -Y, 0}, b.material(Style::kPlain, 0.08, 0.95));   // ceiling
  b.quad({0, 0, 0}, {0, Y, 0}, {0, 0, Z}, b.material(Style::kNoise, 0.3, 0.85));     // x = 0
  b.quad({X, Y, 0}, {0, -Y, 0}, {0, 0, Z}, b.material(Style::kNoise, 0.3, 0.85));    // x = X
  b.quad({X, 0, 0}, {-X, 0, 0}, {0, 0, Z}, b.material(Style::kStripes, 0.25, 0.9));  // y = 0
  b.quad({0, Y, 0}, {X, 0, 0}, {0, 0, Z}, b.material(Style::kNoise, 0.35, 0.85));    // y = Y (far)

  // Posters and a whiteboard, 4 mm off the walls.
  const Style poster_styles[] = {Style::kBlobs, Style::kChecker, Style::kStripes, Style::kBlobs};
  const double far_x[] = {0.5, 1.6, 4.3};
  for (int i = 0; i < 3; ++i) {
    const double w = b.rng().uniform(0.6, 1.0), h = b.rng().uniform(0.5, 0.9);
    b.quad({far_x[i], Y - 0.004, b.rng().uniform(1.2, 1.6)}, {w, 0, 0}, {0, 0, h},
           b.material(poster_styles[i], 0.8, 0.9));
  }
  b.quad({2.3, Y - 0.004, 1.25}, {1.4, 0, 0}, {0, 0, 0.8}, b.material(Style::kBlobs, 0.6, 0.95));
  b.quad({0.004, 3.9, 1.1}, {0, 0.8, 0}, {0, 0, 0.7}, b.material(poster_styles[3], 0.8, 0.9));
  b.quad({X - 0.004, 1.2, 1.2}, {0, -0.9, 0}, {0, 0, 0.7}, b.material(Style::kChecker, 0.8, 0.9));
  b.quad({X - 0.004, 4.7, 0.0}, {0, -0.9, 0}, {0, 0, 2.05}, b.material(Style::kWood, 0.5, 0.6));  // door

  // Desk with monitor, keyboard, books.
  const Material desk = b.material(Style::kWood, 0.5, 0.7);
  b.box({2.0, 3.4, 0.72}, {4.0, 4.2, 0.76}, desk);
  for (const double x : {2.03, 3.92}) {
    for (const double y : {3.43, 4.12}) b.box({x, y, 0.0}, {x + 0.05, y + 0.05, 0.72}, desk);
  }
  b.box({2.1, 4.15, 0.0}, {3.9, 4.18, 0.65}, b.material(Style::kChecker, 0.3, 0.6));  // modesty panel
  b.box({2.65, 3.98, 0.76}, {3.35, 4.03, 1.2}, b.material(Style::kNoise, 0.1, 0.3));  // monitor
  b.box({2.97, 4.03, 0.76}, {3.03, 4.08, 0.98}, b.material(Style::kPlain, 0.1, 0.3));
  b.box({2.75, 3.55, 0.76}, {3.25, 3.72, 0.79}, b.material(Style::kStripes, 0.1, 0.4));  // keyboard
  b.box({3.5, 3.6, 0.76}, {3.75, 3.95, 0.84}, b.material(Style::kBlobs, 0.8, 0.8));     // books
  b.box({2.2, 3.55, 0.76}, {2.45, 3.75, 0.9}, b.material(Style::kChecker, 0.8, 0.8));

  // Two chairs beside the desk ends, facing the camera side (-y); people sit on them.
  for (const double cx : {1.62, 4.38}) {
    const Material chair = b.material(Style::kStripes, 0.7, 0.6);
    const double cy = 3.65;
    b.box({cx - 0.22, cy - 0.22, 0.42}, {cx + 0.22, cy + 0.22, 0.47}, chair);  // seat
    b.box({cx - 0.22, cy + 0.20, 0.47}, {cx + 0.22, cy + 0.24, 0.95}, chair);  // back
    for (const double dx : {-0.2, 0.17}) {
      for (const double dy : {-0.2, 0.17}) b.box({cx + dx, cy + dy, 0.0}, {cx + dx + 0.03, cy + dy + 0.03, 0.42}, chair);
    }
    seats_.push_back({Eigen::Vector3d(cx, cy + 0.02, 0.47), -M_PI / 2});
  }

  // Shelves along the side walls, full of books.
  for (const double side : {0.0, 1.0}) {
    const double x0 = side == 0.0 ? 0.02 : X - 0.42, x1 = x0 + 0.4;
    const double y0 = 1.6, y1 = 3.3, height = 2.0;
    const Material wood = b.material(Style::kWood, 0.4, 0.55);
    b.box({x0, y0, 0.0}, {x1, y0 + 0.03, height}, wood);
    b.box({x0, y1 - 0.03, 0.0}, {x1, y1, height}, wood);
    for (int level = 0; level < 5; ++level) {
      const double z = 0.05 + level * 0.48;
      if (z > height) break;
      b.box({x0, y0 + 0.03, z}, {x1, y1 - 0.03, z + 0.03}, wood);
      if (level == 4) break;
      double y = y0 + 0.05;
      while (y < y1 - 0.12) {
        const double w = b.rng().uniform(0.025, 0.07), h = b.rng().uniform(0.2, 0.38);
        const double depth = b.rng().uniform(0.18, 0.3);
        const double bx0 = side == 0.0 ? x0 + 0.01 : x1 - 0.01 - depth;
        const Style style = b.rng().uniform(0, 1) < 0.5 ? Style::kStripes : Style::kPlain;
        if (b.rng().uniform(0, 1) < 0.85) {
          b.box({bx0, y, z + 0.03}, {bx0 + depth, y + w, z + 0.03 + h}, b.material(style, 0.8, 0.8));
        }
        y += w + 0.004;
      }
    }
  }

  // Stacked boxes and a cabinet in the far corners.
  b.box({5.0, 4.2, 0.0}, {5.6, 4.75, 0.45}, b.material(Style::kNoise, 0.5, 0.7));
  b.box({5.1, 4.3, 0.45}, {5.5, 4.7, 0.8}, b.material(Style::kBlobs, 0.6, 0.8));
  b.box({0.3, 4.4, 0.0}, {1.1, 4.9, 1.1}, b.material(Style::kChecker, 0.4, 0.7));
  b.box({0.4, 4.5, 1.1}, {0.75, 4.8, 1.35}, b.material(Style::kStripes, 0.7, 0.8));
  b.box({0.35, 0.4, 0.0}, {0.85, 0.9, 0.5}, b.material(Style::kBlobs, 0.6, 0.7));
  b.box({5.2, 0.3, 0.0}, {5.7, 0.8, 0.7}, b.material(Style::kNoise, 0.6, 0.6));
}

void StaticScene::savePly(const std::string& path) const {
  writeFileAtomically(path, [this](std::ostream& out) {
    out << "ply\nformat ascii 1.0\ncomment PoseFusion2 synthetic static scene, world frame, metres\n"
        << "element vertex " << mesh_.vertices.size() << "\n"
        << "property float x\nproperty float y\nproperty float z\n"
        << "property uchar red\nproperty uchar green\nproperty uchar blue\n"
        << "element face " << mesh_.triangles.size() << "\n"
        << "property list uchar int vertex_indices\nend_header\n";
    char line[128];
    for (size_t i = 0; i < mesh_.vertices.size(); ++i) {
      const Eigen::Vector3f& p = mesh_.vertices[i];
      const Eigen::Vector3f& c = vertex_colors_[i];
      std::snprintf(line, sizeof(line), "%.6f %.6f %.6f %d %d %d\n", p.x(), p.y(), p.z(),
                    static_cast<int>(c[2] * 255 + 0.5f), static_cast<int>(c[1] * 255 + 0.5f),
                    static_cast<int>(c[0] * 255 + 0.5f));
      out << line;
    }
    for (const Eigen::Vector3i& t : mesh_.triangles) {
      out << "3 " << t[0] << " " << t[1] << " " << t[2] << "\n";
    }
  });
}

}  // namespace pf2
