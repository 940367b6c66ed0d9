// How much memory a volumetric map may take, and a counter that stops its
// growth with a clear error before the machine runs out: an allocation
// failing inside OpenVDB or OctoMap ends in std::terminate (their clean-up
// allocates during unwinding), leaving nothing said.
#pragma once

#include <lista/error.hpp>

#include <atomic>
#include <cstdint>
#include <functional>
#include <string>

namespace lista::raycast {

// Bytes this process may still allocate: the least of MemAvailable, the
// address-space and data limits (ulimit -v / -d) less what is mapped, and
// the cgroup's memory.max less its current use.
uint64_t memory_available_bytes();

// A running total of a map's bytes, shared by the threads that build it.
// charge() throws lista::Error (the text from `explain`) once the total
// would pass the limit.
class MemoryBudget {
 public:
  MemoryBudget(uint64_t limit_bytes, std::function<std::string(uint64_t limit)> explain)
      : limit_(limit_bytes), explain_(std::move(explain)) {}
  void charge(uint64_t bytes) {
    if (used_.fetch_add(bytes, std::memory_order_relaxed) + bytes > limit_) throw Error(explain_(limit_));
  }
  void release(uint64_t bytes) { used_.fetch_sub(bytes, std::memory_order_relaxed); }
  uint64_t used() const { return used_.load(std::memory_order_relaxed); }

 private:
  std::atomic<uint64_t> used_{0};
  uint64_t limit_;
  std::function<std::string(uint64_t)> explain_;
};

}  // namespace lista::raycast
