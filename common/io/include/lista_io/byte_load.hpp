// A value read from unaligned bytes of a file or message.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstring>

namespace lista::io {

// The T at `p`, its bytes reversed first when `swap` (the data's byte order
// is not the host's).
template <class T>
T load_bytes(const uint8_t* p, bool swap = false) {
  uint8_t b[sizeof(T)];
  std::memcpy(b, p, sizeof(T));
  if (swap) std::reverse(b, b + sizeof(T));
  T v;
  std::memcpy(&v, b, sizeof(T));
  return v;
}

}  // namespace lista::io
