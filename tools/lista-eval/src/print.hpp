// A score as a human-readable table or as JSON (undefined values: "n/a" / null).
#pragma once

#include "score.hpp"

#include <string>

namespace lista::eval {

// `objects`: add one line per truly changed object and mission (ObjectVerdict).
std::string format_table(const Score& s, bool objects = false);
std::string format_json(const Score& s);

}  // namespace lista::eval
