#pragma once
// The Dual-BBox filter's settings (`filter.*` keys), declared once for every app that runs the
// filter: pf2_slam (with its own geometric keys on top) and pf2_detect.
#include "pf2/core/settings.h"
#include "pf2/filters/dual_bbox_filter.h"

namespace pf2 {

// Declares the filter.* keys bound to *options (which must outlive *settings).
void declareFilterSettings(DualBBoxFilter::Options* options, Settings* settings);

}  // namespace pf2
