#include <lista/toml_prechecks.hpp>

#include <lista/utf8.hpp>

#include <algorithm>

namespace lista {

namespace {

// Line and column (1-based) of byte `offset` of `text`.
SourceLocation location_of(const std::string& text, size_t offset, const std::string& file) {
  const auto begin = text.begin(), at = text.begin() + static_cast<std::ptrdiff_t>(offset);
  const auto line_start = std::find(std::make_reverse_iterator(at), std::make_reverse_iterator(begin), '\n').base();
  return {file, static_cast<int>(std::count(begin, at, '\n')) + 1, static_cast<int>(at - line_start) + 1};
}

}  // namespace

void check_toml_nesting(const std::string& text, const std::string& file) {
  int depth = 0;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '#') {  // a comment runs to the end of the line
      i = std::min(text.find('\n', i), text.size());
    } else if (c == '"' || c == '\'') {  // a string: basic (escapes) or literal, one line or multi-line
      const bool multi = text.compare(i, 3, std::string(3, c)) == 0;
      const std::string close = multi ? std::string(3, c) : std::string(1, c);
      size_t j = i + close.size();
      // An unterminated one-line string ends at its line: the parser says so.
      while (j < text.size() && text.compare(j, close.size(), close) != 0 && (multi || text[j] != '\n'))
        j += c == '"' && text[j] == '\\' ? 2 : 1;
      i = std::min(j + close.size() - 1, text.size());
    } else if (c == '[' || c == '{') {
      if (++depth > kMaxTomlNesting)
        throw Error("arrays and inline tables nested more than " + std::to_string(kMaxTomlNesting) +
                    " deep; a pipeline needs a few levels: flatten the value")
            .at(location_of(text, i, file));
    } else if ((c == ']' || c == '}') && depth > 0) {
      --depth;
    }
  }
}

void check_toml_utf8(const std::string& text, const std::string& file) {
  const size_t bad = utf8_error_at(text);
  if (bad == std::string::npos) return;
  const unsigned char c = static_cast<unsigned char>(text[bad]);
  throw Error("byte 0x" + std::string(1, "0123456789ABCDEF"[c >> 4]) + "0123456789ABCDEF"[c & 15] +
              " is not UTF-8; a pipeline file is UTF-8 text")
      .at(location_of(text, bad, file));
}

}  // namespace lista
