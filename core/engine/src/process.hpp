// Facts about this process.
#pragma once

#include <cstdint>

namespace lista::core {
// Peak resident set size (VmHWM), 0 if unknown.
uint64_t peak_rss_bytes();
}  // namespace lista::core
