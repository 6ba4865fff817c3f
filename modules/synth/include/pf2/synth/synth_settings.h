#pragma once
// The settings of a synthetic sequence (keys synth.*), declared once for pf2_synth and for
// pf2_slam's built-in sequence: config files, --set and docs read them from here.
#include "pf2/synth/synthetic_sequence.h"

namespace pf2 {

class Settings;

// Binds the user-facing fields of `options` to `settings`; `options` must outlive `settings`.
void declareSynthSettings(SyntheticSequence::Options* options, Settings* settings);

}  // namespace pf2
