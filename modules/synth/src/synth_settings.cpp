#include "pf2/synth/synth_settings.h"

#include <string>

#include "pf2/core/settings.h"

namespace pf2 {

void declareSynthSettings(SyntheticSequence::Options* o, Settings* settings) {
  Settings& s = *settings;
  s.integer("synth.frames", &o->frames, 1, 1000000, "frames", "frames rendered at 30 Hz");
  s.integer("synth.people", &o->people, 0, 5, "people", "people walking in the room");
  s.seed("synth.seed", &o->seed, "scene textures, people and noise; same seed, same bytes");
  s.custom(
      "synth.camera", [o](const std::string& text) { o->camera = cameraMotionFromName(text); },
      [o] { return std::string(cameraMotionName(o->camera)); }, "static, xyz, halfsphere, rpy, loop, above",
      "camera motion");
  s.boolean("synth.noise", &o->sensor.noise,
            "Kinect depth noise, quantisation, holes and range 0.4-4.5 m (false: exact depth)");
  s.integer("synth.misalign", &o->sensor.misalign_px, -100, 100, "pixels",
            "depth shifted right of colour (left if negative); at most a quarter of the image width");
  s.boolean("synth.blur", &o->motion_blur, "motion blur: colour along the image motion, depth mixed at edges");
  s.boolean("synth.close", &o->close_people,
            "people cross 0.7-1.6 m in front of the camera, entering and leaving at the image borders");
}

}  // namespace pf2
