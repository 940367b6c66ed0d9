// A voxel's hit and miss counters packed in one 32-bit grid value (the
// map's only per-voxel storage): hits in the high 16 bits, misses in the
// low 16, each saturating at 65535. A voxel gets at most one update per
// scan, so a count saturates only where more than 65535 scans of one
// mission saw the voxel; only there can its state differ from exact counts.
#pragma once

#include <algorithm>
#include <cstdint>

namespace lista::volumetric::counts {

constexpr int kHitShift = 16;
constexpr uint32_t kMax = 0xFFFF;

inline uint32_t hits(int32_t v) { return static_cast<uint32_t>(v) >> kHitShift; }
inline uint32_t misses(int32_t v) { return static_cast<uint32_t>(v) & kMax; }
inline int32_t pack(uint32_t hits, uint32_t misses) {
  return static_cast<int32_t>(std::min(hits, kMax) << kHitShift | std::min(misses, kMax));
}
// `v` with `h` hits and `m` misses more, each field saturating.
inline int32_t add(int32_t v, uint32_t h, uint32_t m) { return pack(hits(v) + h, misses(v) + m); }

}  // namespace lista::volumetric::counts
