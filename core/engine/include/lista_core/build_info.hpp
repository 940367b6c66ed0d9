// Facts fixed when LiSTA was built.
#pragma once

namespace lista::core {
const char* lista_version();  // project version, e.g. "0.1.0"
const char* git_revision();   // `git describe --always --dirty` at build time, or "unknown"
}  // namespace lista::core
