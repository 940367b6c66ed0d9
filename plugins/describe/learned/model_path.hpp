// Where describe.learned finds its weights when the pipeline names none:
//  1. $LISTA_MODEL_DIR/describe-learned.bin
//  2. <folder of the plugin library>/../../share/lista/models/
//     (<prefix>/share/lista/models in an install tree; the build tree gets
//     the same layout at configure time, see CMakeLists.txt)
//  3. the source tree's models/ recorded at configure time
// The first existing file wins; if none exists the first candidate is
// returned so the error names a path the user can fix.
#pragma once

#include <string>
#include <vector>

namespace lista::describe {

inline constexpr const char* kDefaultWeightsFile = "describe-learned.bin";

std::vector<std::string> weight_candidates();
std::string default_weights_path();

}  // namespace lista::describe
