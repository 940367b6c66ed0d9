// The shared volumetric parameters (common/raycast) as both volumetric
// plugins declare them, with the range max_range lacked: without one, NaN and
// inf passed validation, NaN ran as "unlimited" and the report recorded nan.
#pragma once

#include <lista_raycast/volumetric_config.hpp>

#include <vector>

namespace lista::volumetric {

inline std::vector<ParamSpec> declared_volumetric_params() {
  std::vector<ParamSpec> params = raycast::volumetric_params();
  for (ParamSpec& p : params)
    if (p.name == "max_range") {
      // Any bound also refuses NaN and inf (ParamSpec::check); 0 keeps its meaning.
      p.at_least(0.0);
      p.doc =
          "beams are cut at this range: a farther return adds free space up to the range and no hit "
          "(far beams are wider than a voxel); 0 means unlimited";
    }
  return params;
}

}  // namespace lista::volumetric
