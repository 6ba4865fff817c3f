#pragma once
// The settings of reading a recorded TUM-layout folder (keys input.*), declared once for every app
// that reads one.
#include "pf2/io/tum_sequence.h"

namespace pf2 {

class Settings;

// Binds the fields of `options` to `settings`; `options` must outlive `settings`.
void declareTumSequenceSettings(TumSequence::Options* options, Settings* settings);

}  // namespace pf2
