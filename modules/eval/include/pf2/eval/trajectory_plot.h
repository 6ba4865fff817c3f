#pragma once
#include <string>

#include "pf2/eval/trajectory_metrics.h"

namespace pf2 {

// Top view of the ground truth and the aligned estimate with a segment per association showing
// the error. The view plane is the one spanned by the two axes along which the ground truth
// spreads most. Format by extension: .png (raster) or .svg. Written atomically; throws pf2::Error
// naming the path for another extension or a write failure.
void plotTrajectories(const AteResult& ate, const std::string& path);

}  // namespace pf2
