#include "pf2/io/tum_sequence_settings.h"

#include <string>

#include "pf2/core/settings.h"

namespace pf2 {
namespace {

// A file name setting: any text; empty means "not given".
void declarePath(Settings* s, const std::string& key, std::string* field, const std::string& meaning) {
  s->custom(
      key, [field](const std::string& text) { *field = text; }, [field] { return *field; }, "a file name",
      meaning);
}

}  // namespace

void declareTumSequenceSettings(TumSequence::Options* o, Settings* settings) {
  settings->number("input.depth_scale", &o->depth_scale, 1.0, 1e6, "units per metre",
                   "depth PNG value per metre (TUM and Bonn: 5000)");
  settings->number("input.max_time_difference", &o->max_time_difference, 0.0, 1.0, "s",
                   "largest rgb/depth timestamp difference accepted when associating");
  declarePath(settings, "input.associations", &o->associations_file,
              "rgb/depth associations file ('rgb_stamp rgb_file depth_stamp depth_file'); empty: match "
              "rgb.txt and depth.txt");
  declarePath(settings, "input.calibration", &o->calibration_file,
              "camera calibration file; empty: camera.txt in the folder, else the Bonn or TUM preset");
}

}  // namespace pf2
