// Facts fixed when LiSTA was configured.
#pragma once

namespace lista::core {
const char* lista_version();  // project version, e.g. "0.1.0"
const char* git_revision();   // `git describe --always --dirty` at configure time, or "unknown"
}  // namespace lista::core
