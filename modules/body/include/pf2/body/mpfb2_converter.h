#pragma once
// Builds the project's default SMPL-compatible body model from the CC0 MakeHuman/MPFB2 data
// (base mesh, macro shape targets, game-engine rig and skinning weights; see docs/body.md):
//   - body part of the base mesh only (helper geometry dropped), quads split into triangles with
//     outward normals, decimetres -> metres, axes as SMPL's (y up, facing +z, left at +x);
//   - shape: random adult macro slider settings (gender, age, muscle, weight, height, proportions,
//     ethnic mix) combined the MakeHuman way, PCA of the vertex offsets, directions scaled so that
//     each coefficient has unit variance over the samples (like SMPL's betas);
//   - joints: the 24 SMPL joints are the rig's joint cubes (helper geometry) of the matching bones;
//     a non-negative J_regressor over body vertices is fitted to reproduce them over the shape space;
//   - skinning: the rig's 53 bone weights folded onto the 24 SMPL segments, rows renormalised;
//   - no pose blend shapes (posedirs all zero); origin at the pelvis joint of the mean shape.
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "pf2/body/npy.h"

namespace pf2 {

class Mpfb2Converter {
 public:
  struct Options {
    int sample_count = 500;               // random macro settings sampled for the PCA
    int shape_count = 10;                 // shape directions kept (SMPL: 10)
    std::uint64_t seed = 20250101;        // seed of the slider sampling (the result is reproducible)
    double age_min = 0.5;                 // MakeHuman age slider range: 0.5 = 25 years,
    double age_max = 0.75;                //   1.0 = 90 years (linear between), so 0.75 = 57.5 years
    double height_min = 0.3;              // MakeHuman height slider range; the full 0..1 spans
    double height_max = 0.6;              //   about 1.3-2.4 m, this about -15..+15 cm around the mean
    double regressor_radius_factor = 3.0; // candidate vertices of a joint: within this factor of the
    double regressor_radius_margin = 0.04;//   distance to the nearest body vertex plus this margin, m
    int regressor_max_candidates = 600;   // at most this many nearest candidates per joint
    double regressor_shape_scale = 2.0;   // the regressor fit weighs shapes out to this many sigmas
    double regressor_ridge = 1e-6;        // ridge on the regressor weights (spreads them), m^2
  };

  struct Report {
    int vertex_count = 0;
    int triangle_count = 0;
    std::vector<double> explained_variance;  // fraction of the sample variance per kept direction
    double max_joint_error = 0.0;  // worst regressor error over joints, template and +-scale sigma, m
    std::string text;              // human-readable summary of the above
  };

  Mpfb2Converter() : Mpfb2Converter(Options{}) {}
  explicit Mpfb2Converter(const Options& options) : options_(options) {}

  // Reads the MPFB2 folder (3dobjs/, targets/macrodetails/, rigs/standard/, mesh_metadata/) and
  // returns the SMPL-format arrays in writeNpz order. Throws pf2::Error naming the file on bad
  // input. Thread safe (const).
  std::vector<std::pair<std::string, NpyArray>> convert(const std::string& source_dir,
                                                        Report* report = nullptr) const;

 private:
  Options options_;
};

}  // namespace pf2
