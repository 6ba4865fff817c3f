// pf2_synth: writes a synthetic dynamic RGB-D sequence (TUM layout) with full ground truth.
#include <iostream>
#include <string>

#include "pf2/core/app_settings.h"
#include "pf2/core/command_line.h"
#include "pf2/core/error.h"
#include "pf2/core/settings.h"
#include "pf2/synth/synth_settings.h"
#include "pf2/synth/synthetic_sequence.h"

namespace {

const char* kUsage =
    "Usage: pf2_synth OUT_DIR [options]\n"
    "Renders a synthetic dynamic indoor RGB-D sequence into OUT_DIR in the TUM RGB-D layout (rgb/,\n"
    "depth/, rgb.txt, depth.txt, groundtruth.txt, camera.txt) with ground truth in OUT_DIR/gt/ (person\n"
    "masks, boxes, positions, body parameters, joints, the static scene mesh; see OUT_DIR/gt/README.md).\n"
    "\n"
    "Options (each is a setting: --frames N is --set synth.frames=N):\n"
    "  --frames N        number of frames at 30 Hz (default 300)\n"
    "  --seed S          scene textures, people and noise (default 1); same seed, same bytes\n"
    "  --people K        people in the room, 0..5 (default 3)\n"
    "  --camera M        static | xyz | halfsphere | rpy | loop | above (default xyz; above:\n"
    "                    2.4 m high, looking down at the people)\n"
    "  --noise N         kinect | none (default kinect: z^2 noise, quantisation, holes, 0.4-4.5 m)\n"
    "  --misalign PX     shift depth PX pixels right of colour (default 0; negative = left)\n"
    "  --blur            motion blur: colour blurred along the image motion, depth mixed at edges\n"
    "  --close           people cross the view 0.7-1.6 m in front of the camera, one after the\n"
    "                    other, entering and leaving at the image's left and right borders\n"
    "  --quiet           no progress output\n"
    "  -h, --help        this text\n";
const char* kExitStatus = "Exit status: 0 on success, 1 on bad options or when OUT_DIR cannot be written.\n";

int run(int argc, char** argv) {
  pf2::CommandLine cli(argc, argv);
  pf2::SyntheticSequence::Options options;
  pf2::Settings settings;
  pf2::declareSynthSettings(&options, &settings);
  if (pf2::answeredHelpOrSettings(&cli, std::string(kUsage) + pf2::kSettingsUsage + kExitStatus, settings)) return 0;
  const bool quiet = cli.flag("--quiet");
  pf2::readCommandLineSettings(&cli, &settings,
                               {{"--frames", "synth.frames"},
                                {"--seed", "synth.seed"},
                                {"--people", "synth.people"},
                                {"--camera", "synth.camera"},
                                {"--misalign", "synth.misalign"},
                                {"--blur", "synth.blur", "true"},
                                {"--close", "synth.close", "true"}});
  // --noise names the sensor model rather than a switch.
  const std::string noise = cli.value("--noise", "kinect");
  if (noise != "kinect" && noise != "none") {
    throw pf2::Error("option --noise: expected kinect or none, got '" + noise + "'");
  }
  if (noise == "none") options.sensor.noise = false;
  const auto positionals = cli.positionals();
  if (positionals.size() != 1) {
    throw pf2::Error("expected one OUT_DIR, got " + std::to_string(positionals.size()) + " (see -h)");
  }

  const pf2::SyntheticSequence sequence(options);
  sequence.writeTumFolder(positionals[0], [&](size_t done) {
    if (!quiet && (done % 30 == 0 || done == sequence.size())) {
      std::cerr << "\rpf2_synth: " << done << "/" << sequence.size() << " frames" << std::flush;
    }
  });
  if (!quiet) std::cerr << "\n";
  std::cout << "wrote " << sequence.description() << " to " << positionals[0] << "\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return pf2::runApp("pf2_synth", run, argc, argv); }
