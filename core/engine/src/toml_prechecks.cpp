#include "toml_prechecks.hpp"

namespace lista::core {

void check_toml_nesting(const std::string& text, const std::string& file) {
  int depth = 0, line = 1, column = 0;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    ++column;
    if (c == '\n') {
      ++line;
      column = 0;
      continue;
    }
    if (c == '#') {  // a comment runs to the end of the line
      while (i + 1 < text.size() && text[i + 1] != '\n') ++i;
      continue;
    }
    if (c == '"' || c == '\'') {  // a string: basic (escapes) or literal, one line or multi-line
      const bool multi = text.compare(i, 3, std::string(3, c)) == 0;
      const std::string close = multi ? std::string(3, c) : std::string(1, c);
      size_t j = i + close.size();
      while (j < text.size() && text.compare(j, close.size(), close) != 0) {
        if (c == '"' && text[j] == '\\') ++j;
        if (j < text.size() && text[j] == '\n') {
          if (!multi) break;  // an unterminated one-line string: the parser says so
          ++line;
          column = 0;
        }
        ++j;
      }
      column += int(j - i);
      i = j + (j < text.size() && text[j] != '\n' ? close.size() - 1 : 0);
      if (j < text.size() && text[j] == '\n') --i;
      continue;
    }
    if (c == '[' || c == '{') {
      if (++depth > kMaxTomlNesting)
        throw Error("arrays and inline tables nested more than " + std::to_string(kMaxTomlNesting) +
                    " deep; a pipeline needs a few levels: flatten the value")
            .at({file, line, column});
    } else if ((c == ']' || c == '}') && depth > 0) {
      --depth;
    }
  }
}

void check_toml_utf8(const std::string& text, const std::string& file) {
  int line = 1, column = 1;
  for (size_t i = 0; i < text.size();) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    // Length of the sequence from its lead byte; 0 for a byte that cannot lead one.
    const size_t len = c < 0x80 ? 1 : (c >> 5) == 0x6 && c >= 0xC2 ? 2 : (c >> 4) == 0xE ? 3 : (c >> 3) == 0x1E && c <= 0xF4 ? 4 : 0;
    bool ok = len > 0 && i + len <= text.size();
    for (size_t k = 1; ok && k < len; ++k) ok = (static_cast<unsigned char>(text[i + k]) >> 6) == 0x2;
    if (!ok)
      throw Error("byte 0x" + std::string(1, "0123456789ABCDEF"[c >> 4]) + "0123456789ABCDEF"[c & 15] +
                  " is not UTF-8; a pipeline file is UTF-8 text")
          .at({file, line, column});
    if (c == '\n') {
      ++line;
      column = 1;
    } else {
      ++column;
    }
    i += len;
  }
}

}  // namespace lista::core
