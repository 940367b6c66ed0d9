// Facts about this process.
#pragma once

#include <cstdint>

namespace lista::core {
// Peak resident set size (VmHWM), 0 if unknown.
uint64_t peak_rss_bytes();
// Hands the allocator's free pages back to the system (glibc: every arena,
// not only the top of the heap). Called between stages: each stage's
// threads allocate from arenas of their own, and free pages one stage
// leaves in its arenas would otherwise add to the next stage's peak.
void return_free_memory();
}  // namespace lista::core
