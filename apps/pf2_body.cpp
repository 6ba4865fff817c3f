// pf2_body: the SMPL-compatible body model on the command line — build the default model from
// the MPFB2 data, print a model's summary, export a posed mesh as PLY/OBJ.
#include <cmath>
#include <cstdio>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "pf2/body/body_mesh_io.h"
#include "pf2/body/body_model.h"
#include "pf2/body/mpfb2_converter.h"
#include "pf2/body/npy.h"
#include "pf2/core/app_settings.h"
#include "pf2/core/command_line.h"
#include "pf2/core/error.h"
#include "pf2/core/settings.h"

namespace {

const char* kUsage =
    "Usage: pf2_body COMMAND [arguments] [options]\n"
    "\n"
    "Commands:\n"
    "  convert-mpfb2 SRC_DIR OUT.npz   build the SMPL-format default model from the MakeHuman/MPFB2\n"
    "                                  data folder (CC0); prints the PCA and joint regressor summary\n"
    "      --samples N                 random slider settings for the shape PCA (default 500)\n"
    "      --seed S                    seed of the slider sampling (default 20250101)\n"
    "  info                            vertex/triangle/shape counts and rest joints of a model\n"
    "  mesh OUT.ply|OUT.obj            the posed mesh (metres, y up, facing +z), written atomically\n"
    "      --shape b0,b1,...           shape coefficients (default all 0)\n"
    "      --pose-file F               joint rotations, lines 'NAME ax ay az' (axis-angle, radians)\n"
    "      --pose walk                 a built-in walking pose (arms down, left leg forward)\n"
    "      --translation x,y,z         root translation, metres\n"
    "Common options:\n"
    "  --model M.npz                   SMPL-format model (default: $PF2_BODY_MODEL or the shipped one)\n"
    "  -h, --help                      this text\n"
    "--samples, --seed, --shape, --pose and --translation are the settings convert.samples,\n"
    "convert.seed, mesh.shape, mesh.pose and mesh.translation:\n";
const char* kExitStatus = "Exit status: 0 on success, 1 on bad input (the error line names the file).\n";

// pf2_body's settings, declared once: --config, --set and the options below read them.
struct BodySettings {
  pf2::Mpfb2Converter::Options convert;
  std::vector<double> shape;             // empty: all coefficients 0
  std::string pose = "rest";
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
};

// Comma-separated finite numbers, each within [-limit, limit].
std::vector<double> parseList(const std::string& text, double limit) {
  std::vector<double> values;
  std::stringstream s(text);
  std::string item;
  while (std::getline(s, item, ',')) {
    std::size_t used = 0;
    double value = 0.0;
    try {
      value = std::stod(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != item.size() || !std::isfinite(value)) {
      throw pf2::Error("bad number '" + item + "'");
    }
    if (std::abs(value) > limit) throw pf2::Error("number " + item + " outside [-" + std::to_string(limit) + ", " + std::to_string(limit) + "]");
    values.push_back(value);
  }
  return values;
}

std::string listText(const double* values, size_t count) {
  std::string text;
  for (size_t i = 0; i < count; ++i) text += (i ? "," : "") + std::to_string(values[i]);
  return text;
}

pf2::Settings declareBodySettings(BodySettings* b) {
  pf2::Settings s;
  s.integer("convert.samples", &b->convert.sample_count, 10, 100000, "settings",
            "random slider settings sampled for the shape PCA");
  s.seed("convert.seed", &b->convert.seed, "seed of the slider sampling");
  // Shape coefficients are in standard deviations of the PCA: beyond 5 the body is no longer human.
  s.custom(
      "mesh.shape", [b](const std::string& text) { b->shape = parseList(text, 5.0); },
      [b] { return listText(b->shape.data(), b->shape.size()); },
      "up to one number in [-5, 5] per shape coefficient of the model, comma-separated",
      "shape coefficients (standard deviations); empty: all 0");
  s.choice("mesh.pose", &b->pose, {"rest", "walk"}, "built-in pose: rest (T pose) or walk");
  s.custom(
      "mesh.translation",
      [b](const std::string& text) {
        const std::vector<double> t = parseList(text, 1e4);
        if (t.size() != 3) throw pf2::Error("expected x,y,z");
        b->translation = Eigen::Vector3d(t[0], t[1], t[2]);
      },
      [b] { return listText(b->translation.data(), 3); }, "x,y,z in [-10000, 10000]", "root translation, metres");
  return s;
}

// Arms down from the T pose, left leg forward, right leg back, knees a little bent.
void walkingPose(pf2::BodyParameters* p) {
  p->pose[1] = Eigen::Vector3d(-0.45, 0, 0);  // left hip: thigh forward
  p->pose[2] = Eigen::Vector3d(0.30, 0, 0);   // right hip: thigh back
  p->pose[4] = Eigen::Vector3d(0.25, 0, 0);   // left knee
  p->pose[5] = Eigen::Vector3d(0.50, 0, 0);   // right knee
  p->pose[16] = Eigen::Vector3d(0.35, 0, -1.2);  // left shoulder: arm down, swung back
  p->pose[17] = Eigen::Vector3d(-0.35, 0, 1.2);  // right shoulder: arm down, swung forward
  p->pose[18] = Eigen::Vector3d(0, -0.3, 0);     // left elbow
  p->pose[19] = Eigen::Vector3d(0, 0.5, 0);      // right elbow
}

int convertCommand(const std::vector<std::string>& args, const BodySettings& settings) {
  if (args.size() != 3) throw pf2::Error("convert-mpfb2 expects SRC_DIR OUT.npz (see -h)");
  pf2::Mpfb2Converter::Report report;
  const auto arrays = pf2::Mpfb2Converter(settings.convert).convert(args[1], &report);
  pf2::writeNpz(args[2], arrays);
  std::cout << report.text << "wrote " << args[2] << "\n";
  return 0;
}

int infoCommand(const std::vector<std::string>& args, const pf2::BodyModel& model) {
  if (args.size() != 1) throw pf2::Error("info takes no arguments (see -h)");
  std::printf("vertices %d\ntriangles %zu\nshape_coefficients %d\npose_blend_shapes %s\n", model.vertexCount(),
              model.triangles().size(), model.shapeCount(), model.hasPoseBlendShapes() ? "yes" : "no");
  const auto joints = model.restJoints(Eigen::VectorXd::Zero(model.shapeCount()));
  for (int j = 0; j < pf2::kBodyJointCount; ++j) {
    std::printf("joint %2d %-15s %8.4f %8.4f %8.4f\n", j, pf2::kBodyJointNames[j], joints[j].x(), joints[j].y(),
                joints[j].z());
  }
  // What each coefficient does at rest: stature and enclosed volume at -1 and +1.
  const pf2::BodyMeasures rest = model.restMeasures(Eigen::VectorXd::Zero(model.shapeCount()));
  std::printf("rest stature %.4f m, soles at y %.4f m, volume %.4f m^3 (shape 0)\n", rest.stature, rest.min_y,
              rest.volume);
  for (int k = 0; k < model.shapeCount(); ++k) {
    Eigen::VectorXd shape = Eigen::VectorXd::Zero(model.shapeCount());
    shape[k] = -1.0;
    const pf2::BodyMeasures minus = model.restMeasures(shape);
    shape[k] = 1.0;
    const pf2::BodyMeasures plus = model.restMeasures(shape);
    std::printf("shape %d: stature %.4f / %.4f m, volume %.4f / %.4f m^3 (at -1 / +1)\n", k, minus.stature,
                plus.stature, minus.volume, plus.volume);
  }
  return 0;
}

int meshCommand(const std::vector<std::string>& args, const BodySettings& settings,
                const std::optional<std::string>& pose_file, const pf2::BodyModel& model) {
  if (args.size() != 2) throw pf2::Error("mesh expects OUT.ply or OUT.obj (see -h)");
  pf2::BodyParameters parameters;
  // Fewer numbers than coefficients set the leading ones (the rest stay 0); more is an error.
  if (static_cast<int>(settings.shape.size()) > model.shapeCount()) {
    throw pf2::Error("setting mesh.shape: " + std::to_string(settings.shape.size()) + " numbers for a model with " +
                     std::to_string(model.shapeCount()) + " shape coefficients");
  }
  parameters.shape = Eigen::VectorXd::Zero(model.shapeCount());
  for (size_t k = 0; k < settings.shape.size(); ++k) parameters.shape[static_cast<Eigen::Index>(k)] = settings.shape[k];
  if (settings.pose == "walk") walkingPose(&parameters);
  if (pose_file) pf2::readBodyPoseFile(*pose_file, &parameters);
  parameters.translation = settings.translation;
  pf2::writeBodyMesh(args[1], model.evaluate(parameters));
  return 0;
}

int run(int argc, char** argv) {
  pf2::CommandLine cli(argc, argv);
  BodySettings body;
  pf2::Settings settings = declareBodySettings(&body);
  if (pf2::answeredHelpOrSettings(&cli, std::string(kUsage) + pf2::kSettingsUsage + kExitStatus, settings)) return 0;
  pf2::readCommandLineSettings(&cli, &settings,
                               {{"--samples", "convert.samples"},
                                {"--seed", "convert.seed"},
                                {"--shape", "mesh.shape"},
                                {"--pose", "mesh.pose"},
                                {"--translation", "mesh.translation"}});
  const auto pose_file = cli.value("--pose-file");
  const auto model_path = cli.value("--model");
  const std::vector<std::string> args = cli.positionals();
  if (args.empty()) throw pf2::Error("no command given (see -h)");
  const std::string& command = args[0];
  if (command == "convert-mpfb2") return convertCommand(args, body);
  if (command != "info" && command != "mesh") throw pf2::Error("unknown command '" + command + "' (see -h)");
  const pf2::BodyModel model = model_path ? pf2::BodyModel::loadNpz(*model_path) : pf2::BodyModel::loadDefault();
  if (command == "info") return infoCommand(args, model);
  return meshCommand(args, body, pose_file, model);
}

}  // namespace

int main(int argc, char** argv) { return pf2::runApp("pf2_body", run, argc, argv); }
