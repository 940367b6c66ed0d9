// Small text helpers for messages.
#pragma once

#include <string>
#include <vector>

namespace lista::core {

size_t edit_distance(const std::string& a, const std::string& b);
// Candidates within a distance that scales with the length, best first.
std::vector<std::string> similar_names(const std::string& name, const std::vector<std::string>& candidates);
// " (did you mean 'x'?)" or "".
std::string did_you_mean(const std::string& name, const std::vector<std::string>& candidates);

}  // namespace lista::core
