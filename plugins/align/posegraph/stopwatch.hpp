// Seconds since the alignment started, for its progress lines.
#pragma once

#include <chrono>
#include <string>

namespace lista::align {

struct Stopwatch {
  std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
  // "12.345678 s"
  std::string elapsed() const {
    return std::to_string(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()) + " s";
  }
};

}  // namespace lista::align
