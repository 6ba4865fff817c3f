#pragma once
// The static indoor scene of the synthetic sequences: a 6 x 5 x 3 m room (world frame: z up,
// floor at z = 0, the room spans [0, 6] x [0, 5] x [0, 3] m) with a desk and monitor, two chairs,
// two shelves full of books, stacked boxes, a cabinet, a door and posters. Every surface carries its
// own deterministic procedural texture (value noise, checker, stripes, blobs, wood planks at
// several scales) so that feature and photometric trackers find structure everywhere.
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "pf2/synth/render_mesh.h"

namespace pf2 {

class StaticScene {
 public:
  struct Options {
    std::uint64_t seed = 1;         // texture colours and patterns
    double texels_per_metre = 128;  // texture resolution (128 = 7.8 mm texels)
  };

  // A chair people may sit on: seat surface centre and the direction a sitter faces.
  struct Seat {
    Eigen::Vector3d position_w;  // metres
    double yaw = 0.0;            // heading of the sitter, radians about world z (0 = +x)
  };

  // Builds geometry and bakes the textures (about 0.1 s). Thread safe afterwards (const).
  explicit StaticScene(const Options& options);

  const RenderMesh& mesh() const { return mesh_; }
  const TextureList& textures() const { return textures_; }
  const std::vector<Seat>& seats() const { return seats_; }
  // Axis-aligned floor rectangle (x_min, y_min, x_max, y_max) free of furniture, where people walk.
  Eigen::Vector4d walkableArea() const { return {0.9, 1.3, 5.1, 3.05}; }
  static Eigen::Vector3d roomSize() { return {6.0, 5.0, 3.0}; }

  // The mesh as an ASCII PLY (positions, faces, per-vertex colour = mean colour of the texture),
  // written atomically. Throws pf2::Error naming the file on failure.
  void savePly(const std::string& path) const;

 private:
  Options options_;
  RenderMesh mesh_;
  TextureList textures_;
  std::vector<Eigen::Vector3f> vertex_colors_;  // for the PLY only
  std::vector<Seat> seats_;

  friend class SceneBuilder;
};

}  // namespace pf2
