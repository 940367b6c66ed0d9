// UTF-8 checks for text from outside (file and folder names, pipeline
// files): report.json is UTF-8, and TOML must be.
#pragma once

#include <cstddef>
#include <string_view>

namespace lista {

// Offset of the first byte of `s` that does not belong to a well-formed
// UTF-8 sequence (a stray continuation byte, a truncated sequence, an
// overlong two-byte lead, a lead past U+10FFFF); npos when `s` is UTF-8.
inline size_t utf8_error_at(std::string_view s) {
  for (size_t i = 0; i < s.size();) {
    const unsigned char c = static_cast<unsigned char>(s[i]);
    const size_t len = c < 0x80                        ? 1
                       : (c >> 5) == 0x6 && c >= 0xC2  ? 2
                       : (c >> 4) == 0xE               ? 3
                       : (c >> 3) == 0x1E && c <= 0xF4 ? 4
                                                       : 0;
    if (len == 0 || i + len > s.size()) return i;
    for (size_t k = 1; k < len; ++k)
      if ((static_cast<unsigned char>(s[i + k]) >> 6) != 0x2) return i;
    i += len;
  }
  return std::string_view::npos;
}

}  // namespace lista
