// Internal: small text and file helpers shared by the readers.
#pragma once

#include <string>
#include <vector>

namespace lista::io::detail {

// The whole file; throws lista::Error "path: cannot read (...)".
std::string read_whole_file(const std::string& path);
std::vector<std::string> split_ws(const std::string& line);
// Strict: the whole token must be a decimal number (nan/inf accepted for
// doubles; hexadecimal refused).
bool parse_double(const std::string& s, double& out);
bool parse_int(const std::string& s, long long& out);
// Bytes outside printable ASCII as \xHH, so an error message quoting file
// content or a file name stays readable.
std::string escaped(const std::string& s);

}  // namespace lista::io::detail
