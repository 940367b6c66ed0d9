// UTF-8 checks for text from outside (file and folder names, pipeline
// files): report.json is UTF-8, and TOML must be.
#pragma once

#include <cstddef>
#include <string_view>

namespace lista {

// Offset of the first byte of `s` that does not belong to a well-formed
// UTF-8 sequence (RFC 3629: a stray continuation byte, a truncated
// sequence, an overlong form, a surrogate, a code point past U+10FFFF);
// npos when `s` is UTF-8. The same ranges as toml11's lexer, whose own
// error path for a bad sequence inside a multi-line string reads past its
// buffer: a file this passes, toml11 reads as UTF-8 too.
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
    // The second byte's range where the lead alone does not settle it.
    const unsigned char second = len > 1 ? static_cast<unsigned char>(s[i + 1]) : 0x80;
    if ((c == 0xE0 && second < 0xA0) || (c == 0xED && second > 0x9F) || (c == 0xF0 && second < 0x90) ||
        (c == 0xF4 && second > 0x8F))
      return i;
    i += len;
  }
  return std::string_view::npos;
}

}  // namespace lista
