// toml11 parses nested arrays and inline tables by recursion: a file of a
// few kilobytes nested thousands deep overflows the stack (SIGSEGV, nothing
// printed). Pipelines nest a few levels; deeper input is refused up front.
#pragma once

#include <lista/error.hpp>

#include <string>

namespace lista::core {

inline constexpr int kMaxTomlNesting = 64;

// Throws lista::Error at the first bracket or brace that opens level
// kMaxTomlNesting + 1 (outside strings and comments) of `text`.
void check_toml_nesting(const std::string& text, const std::string& file);

}  // namespace lista::core
