#include "model_path.hpp"

#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>

namespace lista::describe {
namespace fs = std::filesystem;

std::vector<std::string> weight_candidates() {
  std::vector<std::string> out;
  if (const char* env = std::getenv("LISTA_MODEL_DIR"); env && *env)
    out.push_back((fs::path(env) / kDefaultWeightsFile).string());
  Dl_info info{};
  // Any address inside this library tells dladdr which file it came from.
  if (dladdr(reinterpret_cast<void*>(&weight_candidates), &info) && info.dli_fname) {
    fs::path lib_dir = fs::absolute(info.dli_fname).parent_path();
    out.push_back((lib_dir / ".." / ".." / "share" / "lista" / "models" / kDefaultWeightsFile).lexically_normal().string());
  }
#ifdef LISTA_SOURCE_MODEL_DIR
  out.push_back((fs::path(LISTA_SOURCE_MODEL_DIR) / kDefaultWeightsFile).string());
#endif
  return out;
}

std::string default_weights_path() {
  auto c = weight_candidates();
  for (const auto& p : c)
    if (fs::exists(p)) return p;
  return c.empty() ? std::string(kDefaultWeightsFile) : c.front();
}

}  // namespace lista::describe
