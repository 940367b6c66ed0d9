// What toml11 3.7 cannot be trusted with, refused before it parses:
// - nested arrays and inline tables are parsed by recursion: a file of a few
//   kilobytes nested thousands deep overflows the stack (SIGSEGV, nothing
//   printed). Pipelines nest a few levels; deeper input is refused;
// - a literal string ('...') holding bytes that are not UTF-8 sends its
//   error path reading past its buffer (found by fuzz/fuzz_pipeline). TOML
//   is UTF-8: anything else is refused with the line and column.
#pragma once

#include <lista/error.hpp>

#include <string>

namespace lista {

inline constexpr int kMaxTomlNesting = 64;

// Throws lista::Error at the first bracket or brace that opens level
// kMaxTomlNesting + 1 (outside strings and comments) of `text`.
void check_toml_nesting(const std::string& text, const std::string& file);

// Throws lista::Error at the first byte of `text` that is not UTF-8.
void check_toml_utf8(const std::string& text, const std::string& file);

}  // namespace lista
